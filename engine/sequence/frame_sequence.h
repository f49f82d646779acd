/// @brief Rendering a display along a sequence of poses: every wall for both eyes, in memory or
/// into an output folder with review sheets, hit images, resumption and protection of existing
/// output. The command line adds only parsing, a progress bar and Ctrl-C.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/display/display.h"
#include "engine/output/png_writer.h"
#include "engine/render/raycaster.h"
#include "engine/sequence/camera_path.h"

namespace engine {

/// One rendered wall image of a frame.
struct WallImage {
    Eye eye = Eye::Centre;
    WallName wall = WallName::Front;
    RenderedImage image;  // hitMm filled when the settings ask for hits
};

/// Renders every wall of `display` for each of `eyes` at `pose` in one submission and returns
/// them eye after eye, walls in the display's order. This is the in-memory form of a frame
/// that coverage and measurement use; renderSequence writes the same images to files.
std::vector<WallImage> renderWalls(Raycaster& raycaster, const Display& display, const ScenePose& pose,
                                   std::span<const Eye> eyes, const RenderSettings& settings, WarpMode warpMode);

/// Raised when the caller's cancel hook asked to stop; finished frames are kept.
class SequenceCancelled : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SequenceJob {
    std::string volumePath;  // recorded in the manifest
    Display display;
    std::vector<CameraPose> poses;
    double mmPerMetre = 10.0;
    RenderSettings settings;
    WarpMode warpMode = WarpMode::EyeCentred;
    std::string mapSource;              // how the map was obtained (cache, a file): recorded in the manifest
    bool isWritingBeforeAfter = false;  // also the centre eye's walls without and with the map
    bool isWritingHits = false;         // frame_NNNN/EYE/WALL_hits.nrrd beside each wall's PNG
    bool isComputingHits = false;       // hits in the images hooks.onFrame gets, without writing them
    PngEncoding png = kFastPngEncoding; // see png_writer.h
    std::string rendererDescription;    // device and driver, recorded in the manifest but not compared on resume
};

struct SequenceOutput {
    std::string folder;
    bool isForced = false;   // replace what an earlier render left there
    bool isResumed = false;  // keep finished frames and render the rest
    /// Entries of the folder that the same job wrote beside the sequence before it (the colon
    /// analysis of `cvc render --path auto`): they do not make the folder occupied.
    std::vector<std::string> companions{};
};

/// What the caller learns while the sequence runs. Either may be empty.
struct SequenceHooks {
    /// Polled before each frame is submitted and before each image is written; returning true
    /// stops the run with SequenceCancelled (the frame being written is discarded). The images
    /// are written by worker threads, so it may be called from several threads at once.
    std::function<bool()> isCancelled;
    /// Called once at the start (frames already finished) and after each finished frame.
    std::function<void(int framesDone, int framesTotal)> onProgress;
    /// Called with each frame's stereo wall images (hits included when asked for) before they
    /// are written, so an analysis can use them without reading files back.
    std::function<void(int frameIndex, const std::vector<WallImage>& images)> onFrame;
    /// Called on every rank once the frames still to render are known (ascending), before the
    /// first is rendered: with framesOfRank, what each rank will do.
    std::function<void(const std::vector<int>& pendingFrames)> onPendingFrames;
};

/// How the frames x eyes x walls of a sequence are split between the processes of one run (MPI
/// ranks; the engine knows only their number, its own, how to wait for all of them and how to
/// tell rank 0 that a frame is written).
///  - Frames (the default): rank r renders and writes the pending frames r, r + ranks, ...
///    (both eyes, every wall, the before/after walls) into the frame's hidden folder. Rank 0
///    writes every sheet and moves every frame into place: its own frames' from its images;
///    another rank's once that rank renamed the folder .frame_NNNN.written and sent it the
///    walls reduced for the sheet (a message: reportFrameWritten, takeFrameWritten). Its
///    progress counts the frames of every rank.
///  - Walls (the method's cabin cluster): rank r renders and writes wall w of every frame, both
///    eyes, for every w with w % ranks == r; rank 0 also renders the before/after walls, and
///    once every wall of a frame is written (a barrier) composes its sheet from the files and
///    moves the frame into place.
/// Either way rank 0 alone prepares the folder and writes the manifest, and the folder is byte
/// for byte what one process writes.
enum class Distribution { Frames, Walls };

struct SequenceShare {
    int rank = 0;
    int ranks = 1;
    Distribution distribution = Distribution::Frames;
    /// Returns once every rank has called it; needed when ranks > 1.
    std::function<void()> barrier;
    /// Frames distribution, ranks other than 0: sends `message` to rank 0 (a frame this rank
    /// wrote: its index and its walls reduced for the sheet) without waiting for it.
    std::function<void(std::vector<unsigned char> message)> reportFrameWritten;
    /// Frames distribution, rank 0: a message another rank sent, if one has arrived (never waits).
    std::function<std::optional<std::vector<unsigned char>>()> takeFrameWritten;
};

/// The frames of `pending` (ascending) that `rank` renders under `share`'s distribution: every
/// pending frame under Walls (its walls of each), every ranks-th one from the rank-th under
/// Frames.
std::vector<int> framesOfRank(const std::vector<int>& pending, const SequenceShare& share, int rank);

/// What one run did, for the summary line.
struct SequenceSummary {
    int framesRendered = 0;  // by all ranks together

    int framesKept = 0;
    std::vector<int> framesLeftHalfWritten;  // by a run that stopped (".partial" folders): rendered again
    // Frames whose images a stopped run had all written (another rank's ".written" folder,
    // waiting for rank 0's sheet): this run composed their sheets and moved them into place.
    std::vector<int> framesFinishedFromImages;
    double seconds = 0.0;
    double rayCastingMs = 0.0;  // device time of the stereo wall images' dispatches (before/after excluded)
    // Rank 0 of a shared run: the sheets it wrote of frames whose walls other ranks rendered,
    // and the time that took (the serial part of a shared run: docs/benchmarks/mpi.md).
    int sheetsOfOtherRanks = 0;
    double sheetsOfOtherRanksSeconds = 0.0;
};

/// What one run of `job` into `folder` did, as `cvc render --json` writes it: the display, the
/// renderer, the frames rendered and kept (their indices where a stopped run left them), the wall
/// images, the seconds, the ray casting per stereo frame, the folder and its review page.
nlohmann::json sequenceSummaryJson(const SequenceJob& job, const SequenceSummary& summary, const std::string& folder);

/// The manifest (render.json) of `job`: everything that determines the images, so that
/// --resume can refuse a changed request.
std::string sequenceManifest(const SequenceJob& job);

/// Throws std::runtime_error when `output` cannot take `job`: the folder holds output already and
/// neither isForced nor isResumed is set, a resumed folder was made with another manifest, or
/// the path is not a folder. renderSequence checks this too; a caller may check first, before
/// loading a large volume.
void checkSequenceOutput(const SequenceJob& job, const SequenceOutput& output);

/// Writes folder/render.json (the manifest), then for each pose
/// folder/frame_NNNN/{left,right}/<wall>.png (and <wall>_hits.nrrd on request) and
/// folder/frame_NNNN/sheet.png (the walls as a cross for the left eye, the right eye and a
/// red-cyan anaglyph), plus before_after.png on request. A frame is rendered into a hidden
/// folder and renamed when complete, so a cancelled or failed run leaves only whole frames.
/// Each frame is one submission; the previous frame's images are encoded on worker threads
/// while the device renders the next. Throws std::runtime_error when the folder holds output
/// already and neither isForced nor isResumed is set, or when a resumed folder was made with
/// another manifest; SequenceCancelled when the hook asked to stop.
/// With `share` of several ranks, every rank calls it with the same job and output and each
/// does its part (see SequenceShare); progress is reported by rank 0 for the whole job, counted
/// from the finished frames in the folder.
SequenceSummary renderSequence(Raycaster& raycaster, const SequenceJob& job, const SequenceOutput& output,
                               const SequenceHooks& hooks = {}, const SequenceShare& share = {});

/// The folder name of frame `index`: frame_0000, frame_0001, ...
std::string frameFolderName(int index);
/// The hidden folder of a frame that is being written: .frame_0000.partial, ...
std::string partialFrameFolderName(int index);
/// The hidden folder of a frame another rank wrote, waiting for rank 0's sheet: .frame_0000.written, ...
std::string writtenFrameFolderName(int index);

}  // namespace engine
