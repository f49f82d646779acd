/// @brief The static review page of an output folder: index.html with its script and style,
/// the data it shows as review_data.js and the CT for its slices as review_volume.js. The data
/// ships as scripts (window.REVIEW = {...}) because browsers refuse to fetch files from a page
/// opened from the file system; the page needs no server and no network.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/camera_pose.h"
#include "volumes/volume.h"

namespace engine {

/// An image of a frame; `path` is relative to the page's folder, '/' separated. Images of one
/// `group` ("left eye") are shown in one row under its name; the group may be empty.
struct ReviewImage {
    std::string label;
    std::string path;
    std::string group{};
};

struct ReviewFrame {
    int index = 0;                     // the frame's number (frame_NNNN)
    CameraPose pose;                   // volume millimetres
    std::string sheet;                 // the frame's review sheet; may be empty (then the first image is shown large)
    std::vector<ReviewImage> images;   // whatever the frame has: both eyes' walls, a centre eye, before/after
};

/// A wall patch that no frame saw, with a pose from which to look at it.
struct ReviewPatch {
    int rank = 0;
    double areaMm2 = 0.0;
    glm::dvec3 centreMm{0.0};
    CameraPose pose;
    int nearestFrame = -1;   // a ReviewFrame::index, or -1
    std::string picture;     // may be empty
};

struct ReviewCoverage {
    double percent = 0.0;
    double seenMm2 = 0.0;
    double wallMm2 = 0.0;
    std::string overview;                    // a picture of the whole wall, seen and unseen; may be empty
    std::vector<ReviewPatch> patches;        // largest first
    std::vector<double> cumulativePercent;   // one per frame, in the frames' order; may be empty
    std::string description;                 // how coverage was measured, one paragraph
};

/// Where a candidate lies on its frame's review sheet, in one eye: the centre and the radius as
/// fractions of one cross of the sheet (x and the radius of its width, y of its height).
struct SheetRing {
    double x = 0.0, y = 0.0, radius = 0.0;
};

/// A polyp candidate (`cvc candidates`) and the frame that shows it.
struct ReviewCandidate {
    int rank = 0;
    double diameterMm = 0.0;
    double score = 0.0;
    double shapeIndex = 0.0;
    glm::dvec3 centreMm{0.0};
    int frame = -1;          // a ReviewFrame::index, or -1
    std::string picture;     // relative to the page's folder; may be empty
    std::optional<SheetRing> leftRing, rightRing;  // where the frame's walls show it, per eye
};

struct ReviewPage {
    std::string title;
    std::vector<std::pair<std::string, std::string>> facts;  // label, value: display, map, volume, renderer...
    const volumes::Volume* ct = nullptr;  // the slices' CT; null: no slices
    std::vector<ReviewFrame> frames;      // in path order
    /// What the frames' sheets show, under the large one.
    std::string sheetCaption = "review sheet: left eye \u00b7 right eye \u00b7 red\u2013cyan anaglyph (walls unfolded as a "
                               "cross, floor below the front wall)";
    std::optional<ReviewCoverage> coverage;
    std::vector<std::pair<std::string, std::string>> measurements;  // label, value
    std::vector<ReviewCandidate> candidates;  // best first; none: the page has no candidates section
};

/// The files writeReviewPage writes, without the folder.
std::vector<std::string> reviewPageFileNames();

/// Writes folder/index.html, review_page.js, review_page.css, review_data.js (the page's data:
/// each frame's arc length along the frames' positions is computed here) and review_volume.js
/// (the CT reduced for the slices, review_volume.h; window.REVIEW_VOLUME = null without a CT),
/// replacing them; each file is written beside its place and renamed, so an open page never
/// reads half a file. Throws std::runtime_error naming the file that cannot be written.
void writeReviewPage(const std::string& folder, const ReviewPage& page);

}  // namespace engine
