/// @brief Rendering every wall for both eyes along a sequence of poses into an output folder,
/// with review sheets, progress, resumption and protection of existing output.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "engine/camera_path.h"
#include "engine/display.h"
#include "engine/raycaster.h"

namespace app {

/// Thrown when the user interrupted (Ctrl-C) between two images; finished frames are kept.
class Interrupted : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SequenceJob {
    engine::Display display;
    std::vector<engine::CameraPose> poses;
    double mmPerMetre = 10.0;
    engine::RenderSettings settings;
    engine::WarpMode warpMode = engine::WarpMode::Chord;
    bool isWritingBeforeAfter = false;  // also the centre eye's walls without and with the map
    int pngCompression = 3;             // zlib level: 1 fast .. 9 small
    std::string manifestJson;           // what was asked for; --resume requires the same
};

struct SequenceOutput {
    std::string folder;
    bool isForced = false;   // replace what an earlier render left there
    bool isResumed = false;  // keep finished frames and render the rest
};

/// What one run did, for the summary line.
struct SequenceSummary {
    int framesRendered = 0;
    int framesKept = 0;
    double seconds = 0.0;
    double rayCastingMs = 0.0;  // device time of the stereo wall images' dispatches (before/after excluded)
};

/// Writes folder/render.json (the manifest), then for each pose
/// folder/frame_NNNN/{left,right}/<wall>.png and folder/frame_NNNN/sheet.png (the walls as a
/// cross for the left eye, the right eye and a red-cyan anaglyph), plus before_after.png on
/// request. A frame is rendered into a hidden folder and renamed when complete, so an
/// interrupted run leaves only whole frames. Throws std::runtime_error when the folder holds
/// output already and neither isForced nor isResumed is set, or when a resumed folder was
/// made with another manifest; Interrupted after Ctrl-C.
SequenceSummary renderSequence(engine::Raycaster& raycaster, const SequenceJob& job, const SequenceOutput& output);

/// The folder name of frame `index`: frame_0000, frame_0001, ...
std::string frameFolderName(int index);

}  // namespace app
