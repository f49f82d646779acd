#include "colon/slicer_files.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "colon/colon_error.h"
#include "volumes/nrrd_io.h"

namespace colon {
namespace {

nlohmann::json vec(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

/// Colours of the colon segments in turn: distinct on Slicer's dark 3D background.
glm::dvec3 segmentColour(std::size_t index) {
    static const std::array<glm::dvec3, 6> kColours = {glm::dvec3{0.90, 0.60, 0.20}, glm::dvec3{0.30, 0.75, 0.90},
                                                       glm::dvec3{0.55, 0.85, 0.35}, glm::dvec3{0.85, 0.40, 0.70},
                                                       glm::dvec3{0.95, 0.85, 0.30}, glm::dvec3{0.60, 0.55, 0.95}};
    return kColours[index % kColours.size()];
}

std::string segmentName(std::size_t index) { return "colon segment " + std::to_string(index + 1); }

/// Slicer's point orientation is a 3x3 matrix in the file's coordinate system, row-major: the
/// identity of RAS written in LPS (x and y flipped), as Slicer writes an unrotated point.
const nlohmann::json kUnrotatedInLps = {-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0};

}  // namespace

std::string markupsJson(MarkupsKind kind, const std::string& name, const std::vector<MarkupsPoint>& points,
                        const volumes::Volume& volume, const glm::dvec3& colour) {
    nlohmann::json controlPoints = nlohmann::json::array();
    for (std::size_t i = 0; i < points.size(); ++i) {
        controlPoints.push_back({{"id", std::to_string(i + 1)},
                                 {"label", points[i].label},
                                 {"description", points[i].description},
                                 {"position", vec(volumes::patientFromVolumeMm(volume, points[i].volumeMm))},
                                 {"orientation", kUnrotatedInLps},
                                 {"selected", true},
                                 {"locked", true},
                                 {"visibility", true},
                                 {"positionStatus", "defined"}});
    }
    const bool isCurve = kind == MarkupsKind::Curve;
    const nlohmann::json display = {{"visibility", true},
                                    {"opacity", 1.0},
                                    {"color", vec(colour)},
                                    {"selectedColor", vec(colour)},
                                    // A curve's hundreds of points would bury the view in labels.
                                    {"pointLabelsVisibility", !isCurve},
                                    {"propertiesLabelVisibility", false},
                                    {"glyphType", "Sphere3D"},
                                    {"glyphScale", isCurve ? 0.5 : 2.0},
                                    {"textScale", 3.0},
                                    {"lineThickness", 0.3}};
    const nlohmann::json markup = {{"type", isCurve ? "Curve" : "Fiducial"},
                                   {"name", name},
                                   {"coordinateSystem", "LPS"},
                                   {"coordinateUnits", "mm"},
                                   {"locked", true},
                                   {"labelFormat", "%N-%d"},
                                   {"controlPoints", controlPoints},
                                   {"display", display}};
    const nlohmann::json doc = {{"@schema", kMarkupsSchemaId}, {"markups", nlohmann::json::array({markup})}};
    return doc.dump(1) + "\n";
}

std::string centrelineMarkupsJson(const ColonAnalysis& analysis, std::size_t segmentIndex, const volumes::Volume& volume) {
    if (segmentIndex >= analysis.segments.size()) {
        throw ColonError("colon segment " + std::to_string(segmentIndex + 1) + " asked for, the analysis found " +
                         std::to_string(analysis.segments.size()));
    }
    const auto& pointsMm = analysis.segments[segmentIndex].centreline.pointsMm;
    std::vector<MarkupsPoint> points;
    points.reserve(pointsMm.size());
    for (std::size_t i = 0; i < pointsMm.size(); ++i) points.push_back({std::to_string(i + 1), "", pointsMm[i]});
    return markupsJson(MarkupsKind::Curve, segmentName(segmentIndex), points, volume, segmentColour(segmentIndex));
}

std::string unseenPatchesMarkupsJson(const std::vector<UnseenPatch>& patches, const volumes::Volume& volume) {
    std::vector<MarkupsPoint> points;
    points.reserve(patches.size());
    for (std::size_t p = 0; p < patches.size(); ++p) {
        std::ostringstream area;
        area << std::fixed << std::setprecision(1) << patches[p].areaMm2 << " mm2 of wall not seen";
        points.push_back({"patch " + std::to_string(p + 1), area.str(), patches[p].centreMm});
    }
    return markupsJson(MarkupsKind::Fiducial, "unseen patches", points, volume, {1.0, 0.25, 0.25});
}

void writeLumenSegmentation(const ColonAnalysis& analysis, const std::string& path, bool overwrite) {
    const volumes::Volume& labels = analysis.labels;
    const std::size_t count = analysis.segments.size();
    if (count > std::numeric_limits<std::uint8_t>::max()) {
        throw ColonError(path + ": " + std::to_string(count) + " colon segments, a segmentation file holds at most 255");
    }
    // Segment N's label value is N; each segment's extent is its voxels' bounding box.
    std::vector<std::uint8_t> values(labels.voxelCount(), 0);
    std::vector<std::array<int, 6>> extents(count, {std::numeric_limits<int>::max(), -1, std::numeric_limits<int>::max(),
                                                    -1, std::numeric_limits<int>::max(), -1});
    std::size_t index = 0;
    for (int k = 0; k < labels.dims[2]; ++k) {
        for (int j = 0; j < labels.dims[1]; ++j) {
            for (int i = 0; i < labels.dims[0]; ++i, ++index) {
                const int segment = labels.hu[index] - kLabelFirstSegment;
                if (segment < 0 || static_cast<std::size_t>(segment) >= count) continue;
                values[index] = static_cast<std::uint8_t>(segment + 1);
                auto& e = extents[static_cast<std::size_t>(segment)];
                e = {std::min(e[0], i), std::max(e[1], i), std::min(e[2], j), std::max(e[3], j), std::min(e[4], k),
                     std::max(e[5], k)};
            }
        }
    }
    volumes::NrrdKeyValues fields;
    for (std::size_t s = 0; s < count; ++s) {
        const std::string key = "Segment" + std::to_string(s) + "_";
        const glm::dvec3 colour = segmentColour(s);
        std::ostringstream colourText, extentText;
        colourText << colour.r << ' ' << colour.g << ' ' << colour.b;
        const auto& e = extents[s];
        if (e[1] < 0) {
            extentText << "0 -1 0 -1 0 -1";  // an empty segment: Slicer's empty extent
        } else {
            extentText << e[0] << ' ' << e[1] << ' ' << e[2] << ' ' << e[3] << ' ' << e[4] << ' ' << e[5];
        }
        fields.emplace_back(key + "ID", "colon_segment_" + std::to_string(s + 1));
        fields.emplace_back(key + "Name", segmentName(s));
        fields.emplace_back(key + "NameAutoGenerated", "0");
        fields.emplace_back(key + "Color", colourText.str());
        fields.emplace_back(key + "ColorAutoGenerated", "0");
        fields.emplace_back(key + "LabelValue", std::to_string(s + 1));
        fields.emplace_back(key + "Layer", "0");
        fields.emplace_back(key + "Extent", extentText.str());
        fields.emplace_back(key + "Tags", "|");
    }
    // Slicer 5.4 and later read the first name, earlier versions the second.
    fields.emplace_back("Segmentation_SourceRepresentation", "Binary labelmap");
    fields.emplace_back("Segmentation_MasterRepresentation", "Binary labelmap");
    fields.emplace_back("Segmentation_ContainedRepresentationNames", "Binary labelmap|Closed surface|");
    fields.emplace_back("Segmentation_ReferenceImageExtentOffset", "0 0 0");
    volumes::writeLabelNrrd(labels, values, fields, path, overwrite);
}

}  // namespace colon
