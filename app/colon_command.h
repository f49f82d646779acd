/// @brief The colon analysis as `cvc colon` runs it, also used by `cvc render --path auto`.
#pragma once

#include <string>
#include <vector>

#include "colon/colon_analysis.h"

namespace app {

struct ColonRequest {
    std::string volumePath;
    std::string rawSpec;
    std::string outFolder;
    bool force = false;
    bool resume = false;  ///< reuse a finished analysis in outFolder (its colon.json) instead of redoing it
    std::string jsonPath;  ///< also write the summary here
    colon::ColonSettings settings;
};

/// What a finished analysis left in its folder.
struct ColonOutputs {
    std::string colonJson;
    std::string centrelineText;
    std::string lumenNrrd;
    std::string overviewPng;
    std::string cleansedNrrd;  ///< empty when no fluid was cleansed
    std::string lumenSegmentation;               ///< the lumen for 3D Slicer (.seg.nrrd)
    std::vector<std::string> centrelineMarkups;  ///< per segment, for 3D Slicer (.mrk.json); empty when reused
    bool wasReused = false;
};

/// Runs the analysis and writes DIR/{lumen.nrrd, centreline.txt, colon.json, overview.png}, the
/// same lumen and centreline for 3D Slicer (DIR/lumen.seg.nrrd, DIR/centreline_segment_N.mrk.json)
/// and, where tagged fluid was cleansed, DIR/cleansed.nrrd; progress goes to stderr, the summary to
/// stdout. Refuses to replace existing files without `force`.
ColonOutputs runColonAnalysis(const ColonRequest& request);

}  // namespace app
