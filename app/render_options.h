/// @brief Everything `cvc render` takes on the command line.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "engine/render/pinhole_camera.h"
#include "engine/render/render_settings.h"
#include "volumes/volume.h"

namespace CLI {
class App;
}

namespace app {

struct RenderOptions {
    // Input
    std::string volumePath;
    std::string rawSpec;
    // Output: a PNG for a pinhole view, a folder for a display
    std::string outPath;
    std::string hitsPath;               // pinhole view: --hits FILE
    bool isWritingDisplayHits = false;  // display render: --hits (no file name)
    bool isPrintingStats = false;  // pinhole: also count the volume fetches each ray makes
    std::string dicomOut;          // --dicom-out DIR: the pictures also as DICOM Secondary Capture
    std::string jsonPath;          // --json FILE: a machine-readable summary of the render
    bool force = false;
    bool resume = false;
    // Camera (pinhole), or the single pose of a display
    std::vector<double> positionMm;
    std::vector<double> lookAtMm;
    std::vector<double> up;
    double fovDeg = 40.0;
    std::string size = "1024x1024";
    // Display
    std::string display;
    std::string map;  // empty: the display's own
    int mapSize = 1024;
    std::string cubeMapFile;  // empty: the cached bake of the display's map
    std::string warp = "eye-centred";
    double mmPerMetre = 10.0;
    bool isWritingBeforeAfter = false;
    // Path
    std::string pathFile;
    double pathStepMm = 2.0;
    double smoothingMm = 8.0;
    bool isRetrograde = false;
    int maxFrames = 0;  // 0: all
    // Several processes (mpirun): how the frames x eyes x walls are split
    std::string distribution = "frames";
    int polyp = -1;     // >= 0: one pose viewing this polyp of the path's ground truth
    std::string candidatesFile;  // cvc candidates' JSON: listed and ringed on the review page
    bool isAtCandidates = false; // ... and one pose viewing each of them instead of the fly-through
    double polypElevationDeg = 60.0;  // ... seen ahead at this elevation (on the IC's ceiling)
    double polypAzimuthDeg = 0.0;     // ... that many degrees right of straight up
    // Rendering
    std::string mode = "iso";
    std::string filter = "trilinear";
    std::string gradient;  // empty: bspline for a pinhole view, central for display frames
    bool isSkippingOff = false;
    bool isStartPassOff = false;
    std::string gradientVolume;  // empty: on for display frames, off for a pinhole view
    engine::RenderSettings settings;
    std::optional<double> lightHalfDistanceMm;  // not given: none for a pinhole view, 25 mm for a display
    std::optional<double> stepVoxels;           // not given: 0.5 for a pinhole still, 1.0 for display frames
    std::string device;
};

/// Applies the string options (mode, filter, skipping, light) to options.settings; throws
/// std::invalid_argument for an unknown transfer function.
engine::RenderSettings renderSettingsFrom(const RenderOptions& options, bool isDisplay);

/// Refuses, naming why, every option given to `command` that the request makes meaningless (a
/// display's options for a pinhole view, a pose with --path, composite's with iso, ...): throws
/// CLI::ValidationError or std::invalid_argument before any work.
void refuseRenderOptionsNotApplying(const CLI::App& command, const RenderOptions& options);

/// The pinhole camera the options ask for. With no position given, it looks at the volume's
/// centre from the patient's front (anterior, -y in LPS) with the head up (+z), whatever order
/// the file stores the axes in, far enough back for the whole box to fit the field of view.
engine::PinholeCamera cameraFrom(const RenderOptions& options, const volumes::Volume& volume);

/// Throws before any work when `folder` (--dicom-out) is a file, or holds DICOM files and
/// `force` is false.
void checkDicomOutput(const std::string& folder, bool force);

/// Renders a display (walls x eyes x poses) into a folder; see engine/sequence/frame_sequence.h.
void runDisplayRender(const RenderOptions& options);

}  // namespace app
