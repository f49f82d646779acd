/// @brief `cvc candidates`: polyp candidates on the colon wall (colon/polyp_candidates.h) placed
/// along the path a fly-through takes, written for a reader and for programs. No Vulkan: the
/// colon analysis, the wall's mesh, the shape measures and the measuring views all run on the
/// CPU. Outputs in the folder: candidates.json (every candidate with its place on the path and
/// the counts of what the rule dropped), candidates.mrk.json (a 3D Slicer fiducial list) and
/// candidate_NN.png (a view of each of the first candidates, looking down on it from the lumen).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "colon/path_place.h"
#include "colon/polyp_candidates.h"
#include "engine/display/display.h"
#include "engine/review/review_page.h"
#include "engine/sequence/frame_sequence.h"
#include "volumes/volume.h"

namespace engine {

struct CandidateStudySettings {
    std::string volumePath;
    std::string rawSpec;
    std::string pathFile = "auto";  ///< a centreline file, "auto" (the colon analysis's own) or "" (no path)
    double pathStepMm = 2.0;        ///< the fly-through's frame spacing, as `cvc render --path-step`
    std::string outFolder;
    bool force = false;
    int pictures = 12;              ///< candidate_NN.png for the first this many
    colon::CandidateSettings candidates;
};

struct CandidateStudyResult {
    colon::CandidateSearch search;
    std::vector<colon::PathPlace> places;  ///< per candidate
    int frames = 0;                        ///< frames of the fly-through the places refer to
    std::string json;                      ///< candidates.json's text
    std::vector<std::string> pictures;     ///< the paths written
    double seconds = 0.0;
};

/// The output files in `folder` that a run writes: refused (std::runtime_error naming the first)
/// when one exists and `force` is false; with `force`, removed.
void prepareCandidateFolder(const std::string& folder, bool force);

/// Loads the volume, finds the colon, meshes its wall, finds the candidates, places them on the
/// path and writes the outputs. `say` gets each step's line. Throws colon::ColonError when no
/// colon is found, std::runtime_error for unreadable input or unwritable output.
CandidateStudyResult runCandidateStudy(const CandidateStudySettings& settings,
                                       const std::function<void(const std::string&)>& say);

/// The same for a volume already loaded (settings.volumePath and rawSpec only name it), which
/// the colon analysis cleanses in place where it finds tagged fluid.
CandidateStudyResult candidateStudyOf(volumes::Volume& volume, const CandidateStudySettings& settings,
                                      const std::function<void(const std::string&)>& say);

/// The candidates of a candidates.json for the review page of a render of `frames` frames, their
/// pictures' paths made relative to `pageFolder`. With `pathStepMm` 0 the render posed one frame
/// per candidate (`--at-candidates`): candidate N on frame N - 1. Otherwise it flew the path at
/// that step, and each candidate's frame is its "nearest_frame" (-1 past the frames rendered);
/// a list placed at another step is refused (std::invalid_argument naming both steps), as its
/// frames would be others. Throws std::runtime_error naming the file when it is not
/// candidates.json's form.
std::vector<ReviewCandidate> reviewCandidatesOf(const std::string& candidatesFile, const std::string& pageFolder,
                                                int frames, double pathStepMm);

/// Rings the candidates that frame `frameIndex` shows (ReviewCandidate::frame) on its sheet, from
/// the first hits of its stereo walls (`walls`, hits included): per eye, the wall whose pixels hit
/// the candidate's surface (within half its diameter of its centre) most often, and there the
/// centre and the spread of those pixels, placed in the display's cross. An eye where no pixel
/// hits it gets no ring.
void ringCandidatesOnFrame(std::vector<ReviewCandidate>& candidates, int frameIndex, const Display& display,
                           const std::vector<WallImage>& walls);

}  // namespace engine
