/// @brief The whole analysis of a CT colonography scan, from HU to a path to fly along:
/// air segmentation (lumen_segmentation.h), electronic cleansing of tagged fluid
/// (electronic_cleansing.h), the lumen's connected segments, a centreline per segment
/// (centreline.h), and the segments ordered rectum -> caecum with the gaps between them.
///
/// Orientation comes from the scan's orientation matrix, never from the voxel axes: the
/// head-foot axis for the "outside" rule, gravity (supine: toward the patient's back) for the
/// fluid, and the patient's right for the caecum. Order rule: the caecum is the segment end
/// farthest to the patient's right and low, the end that maximises -2 L - S in patient LPS
/// millimetres (the caecum lies low in the right iliac fossa; the hepatic flexure is as far
/// right but high, the rectum as low but on the midline). The chain starts there, each next
/// segment is the one with an end nearest to the chain's last point, and the whole chain is
/// then reversed so that it runs rectum -> caecum (antegrade, the endoscope's direction).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "colon/centreline.h"
#include "colon/electronic_cleansing.h"
#include "colon/lumen_segmentation.h"
#include "volumes/volume.h"

namespace colon {

enum class Cleansing { Auto, Off };

struct ColonSettings {
    SegmentationSettings segmentation;
    CleansingSettings cleansingSettings;
    Cleansing cleansing = Cleansing::Auto;  ///< Auto: cleanse where tagged fluid is found
    CentrelineSettings centreline;
    double minPathLengthMm = 20.0;  ///< shorter lumen segments are reported but not flown through
};

/// Codes of the label volume (lumen.nrrd).
enum LabelCode : int16_t {
    kLabelNone = 0,
    kLabelOutside = 1,
    kLabelSmall = 2,
    kLabelLung = 3,
    kLabelRound = 4,
    kLabelShortColon = 9,  ///< colon lumen too short for a path
    kLabelFirstSegment = 10,  ///< segment k (1-based, antegrade order) is kLabelFirstSegment + k - 1
};

struct ColonSegment {
    double volumeMl = 0.0;
    std::size_t voxels = 0;
    SegmentCentreline centreline;  ///< points run rectum -> caecum
};

struct ColonAnalysis {
    std::vector<AirRegion> airRegions;
    bool isCleansed = false;
    CleansingReport cleansing;
    std::vector<ColonSegment> segments;  ///< antegrade order: rectum -> caecum
    std::vector<double> gapsMm;          ///< gapsMm[i]: from the end of segment i to the start of i + 1
    std::vector<double> shortSegmentsMl;  ///< lumen segments under minPathLengthMm, not flown through
    volumes::Volume labels;               ///< int16 label codes (LabelCode) on the volume's grid
    glm::dvec3 anteriorMm{0.0, -1.0, 0.0};  ///< the patient's anterior, in volume millimetres
    double seconds = 0.0;
};

/// Progress: the step starting now, and how many of the steps are done.
using ColonProgress = std::function<void(const std::string& step, int done, int total)>;

/// Analyses `volume`. With tagged fluid found (and cleansing not Off), `volume`'s HU are
/// cleansed in place. Throws ColonError when no colon is found, naming what was found.
ColonAnalysis analyseColon(volumes::Volume& volume, const ColonSettings& settings, const ColonProgress& progress = {});

}  // namespace colon
