/// @brief Surface coverage along a fly-through: every pose's walls rendered from the centre eye
/// (mono, the view a reader's head is at), each wall's first hits given to a
/// colon::SurfaceCoverage. The device renders frame i + 1 while the host measures frame i.
#pragma once

#include <functional>
#include <vector>

#include "colon/surface_coverage.h"
#include "engine/display/display.h"
#include "engine/render/raycaster.h"
#include "engine/sequence/camera_path.h"
#include "engine/sequence/frame_sequence.h"

namespace engine {

struct CoverageJob {
    Display display;
    std::vector<CameraPose> poses;
    double mmPerMetre = 10.0;
    RenderSettings settings;  // hits are always written: coverage is measured on them
    WarpMode warpMode = WarpMode::EyeCentred;
};

struct CoverageHooks {
    /// Polled before each frame; returning true stops the run with SequenceCancelled.
    std::function<bool()> isCancelled;
    std::function<void(int framesDone, int framesTotal)> onProgress;
    /// Each frame's centre-eye walls once measured (to write a sheet, say).
    std::function<void(int frameIndex, const std::vector<WallImage>& walls)> onFrame;
};

struct CoverageFrame {
    double newlySeenMm2 = 0.0;  ///< wall first shown by this frame
    double percentAfter = 0.0;  ///< coverage once this frame was added
    /// The elements first shown by this frame, ascending: replayed in frame order with
    /// SurfaceCoverage::markSeen they give the run's result, which lets processes that flew
    /// different frames merge what they saw.
    std::vector<uint32_t> newlySeenElements;
};

struct CoverageRunSummary {
    std::vector<CoverageFrame> frames;
    double seconds = 0.0;          ///< the whole run
    double measureSeconds = 0.0;   ///< host time spent in SurfaceCoverage::addView
    double rayCastingMs = 0.0;     ///< device time of the dispatches
};

/// Adds every pose of `job` to `coverage`, in order. Throws std::invalid_argument for a display
/// that cannot be rendered, SequenceCancelled when the hook asked to stop.
CoverageRunSummary runCoverage(Raycaster& raycaster, const CoverageJob& job, colon::SurfaceCoverage& coverage,
                               const CoverageHooks& hooks = {});

}  // namespace engine
