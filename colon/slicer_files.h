/// @brief The colon analysis and the coverage in files 3D Slicer opens as its own objects:
/// Markups JSON (.mrk.json, schema v1.0.3) for the centreline of each segment (a curve) and the
/// unseen patches (a fiducial list), positions in patient LPS millimetres; and the lumen as a
/// segmentation (.seg.nrrd), one segment per colon segment. docs/formats.md shows the files.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "colon/colon_analysis.h"
#include "colon/surface_coverage.h"
#include "volumes/volume.h"

namespace colon {

/// The schema a .mrk.json names in its "@schema" field; Slicer reads files of this version.
inline constexpr const char* kMarkupsSchemaId =
    "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/"
    "markups-schema-v1.0.3.json#";

/// What a markup's list holds: a curve through its points, or separate points.
enum class MarkupsKind { Curve, Fiducial };

struct MarkupsPoint {
    std::string label;
    std::string description;
    glm::dvec3 volumeMm{0.0};  ///< volume millimetres (volumes/volume.h); written in patient LPS
};

/// One markup, as the text of a .mrk.json file: `points` in order, placed in the patient frame
/// of `volume`, locked (they are measurements, not edits), drawn in `colour` (RGB in [0, 1]).
std::string markupsJson(MarkupsKind kind, const std::string& name, const std::vector<MarkupsPoint>& points,
                        const volumes::Volume& volume, const glm::dvec3& colour);

/// The centreline of colon segment `segmentIndex` (0-based, rectum -> caecum) as a curve named
/// "colon segment N". Throws ColonError for an index past the last segment.
std::string centrelineMarkupsJson(const ColonAnalysis& analysis, std::size_t segmentIndex, const volumes::Volume& volume);

/// The unseen patches as a fiducial list "unseen patches": a point at each patch's centre,
/// labelled "patch N" in the order given (largest first), its area in the description.
std::string unseenPatchesMarkupsJson(const std::vector<UnseenPatch>& patches, const volumes::Volume& volume);

/// Writes the colon segments of `analysis.labels` as a Slicer segmentation at `path`: segment N
/// (label value N) is colon segment N, rectum -> caecum, with its name, colour and extent; the
/// rest of the grid is 0. Throws ColonError for more segments than a uint8 label holds and
/// volumes::VolumeError when the file cannot be written (or exists and `overwrite` is false).
void writeLumenSegmentation(const ColonAnalysis& analysis, const std::string& path, bool overwrite);

}  // namespace colon
