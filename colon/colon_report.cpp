#include "colon/colon_report.h"

#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

namespace colon {
namespace {

nlohmann::json vec(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

std::string centrelineText(const ColonAnalysis& analysis) {
    std::ostringstream out;
    out << "# centreline in volume millimetres (voxel (i, j, k) at (i, j, k) * spacing), rectum -> caecum\n";
    out << std::fixed << std::setprecision(3);
    for (std::size_t s = 0; s < analysis.segments.size(); ++s) {
        out << "# segment " << s + 1 << '\n';
        for (const glm::dvec3& p : analysis.segments[s].centreline.pointsMm) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
    return out.str();
}

std::string colonJson(const ColonAnalysis& analysis, const volumes::Volume& volume, const std::string& volumePath) {
    nlohmann::json doc;
    doc["frame"] = "volume millimetres: voxel (i, j, k) has its centre at (i, j, k) * spacing_mm";
    doc["volume"] = volumePath;
    doc["dims"] = volume.dims;
    doc["spacing_mm"] = vec(volume.spacingMm);
    doc["centreline_order"] = "rectum_to_caecum";
    doc["centreline_start"] = "rectum";
    doc["centreline_end"] = "caecum";
    doc["anterior"] = vec(analysis.anteriorMm);
    nlohmann::json centreline = nlohmann::json::array();
    nlohmann::json starts = nlohmann::json::array();
    nlohmann::json segments = nlohmann::json::array();
    double total = 0.0;
    for (std::size_t s = 0; s < analysis.segments.size(); ++s) {
        const ColonSegment& segment = analysis.segments[s];
        starts.push_back(centreline.size());
        for (const glm::dvec3& p : segment.centreline.pointsMm) centreline.push_back(vec(p));
        total += segment.centreline.lengthMm;
        segments.push_back({{"segment", s + 1},
                            {"label", kLabelFirstSegment + static_cast<int>(s)},
                            {"length_mm", segment.centreline.lengthMm},
                            {"volume_ml", segment.volumeMl},
                            {"mean_radius_mm", segment.centreline.meanRadiusMm},
                            {"min_radius_mm", segment.centreline.minRadiusMm},
                            {"start_mm", vec(segment.centreline.pointsMm.front())},
                            {"end_mm", vec(segment.centreline.pointsMm.back())}});
    }
    doc["centreline_mm"] = centreline;
    doc["segment_starts"] = starts;
    doc["segments"] = segments;
    doc["gaps_mm"] = analysis.gapsMm;
    doc["total_length_mm"] = total;
    doc["short_segments_ml"] = analysis.shortSegmentsMl;
    doc["cleansing"] = {{"applied", analysis.isCleansed},
                        {"pools", analysis.cleansing.pools},
                        {"fluid_ml", analysis.cleansing.fluidMl},
                        {"fluid_voxels", analysis.cleansing.fluidVoxels},
                        {"edge_voxels", analysis.cleansing.edgeVoxels},
                        {"rejected_tagged_regions", analysis.cleansing.rejectedRegions}};
    nlohmann::json regions = nlohmann::json::array();
    for (const AirRegion& r : analysis.airRegions) {
        if (r.kind == AirClass::Small) continue;  // hundreds of specks: counted below
        // Each measure is there where a rule needed it (the rules stop at the first that applies).
        nlohmann::json region = {{"class", airClassName(r.kind)}, {"volume_ml", r.volumeMl}};
        if (r.kind != AirClass::Outside) {
            region["median_hu"] = r.medianHu;
            region["centroid_mm"] = vec(r.centroidMm);
        }
        if (r.kind == AirClass::Round || r.kind == AirClass::Colon) {
            region["max_radius_mm"] = r.maxRadiusMm;
            region["tubularity"] = r.tubularity;
        }
        regions.push_back(region);
    }
    doc["air_regions"] = regions;
    doc["small_air_regions"] = std::count_if(analysis.airRegions.begin(), analysis.airRegions.end(),
                                             [](const AirRegion& r) { return r.kind == AirClass::Small; });
    doc["labels"] = {{"0", "no air"},
                     {"1", "air outside the body"},
                     {"2", "small air pocket"},
                     {"3", "lung-like air"},
                     {"4", "round air (not tubular)"},
                     {"9", "colon lumen too short for a path"},
                     {"10+", "colon segment (10 is segment 1, rectum end first)"}};
    doc["seconds"] = analysis.seconds;
    return doc.dump(1) + "\n";
}

}  // namespace colon
