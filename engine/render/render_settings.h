/// @brief What one image is rendered with, free of Vulkan: the features (RenderSettings), how
/// the rays are bent (Warp), the request that joins them to the rays, and the rendered image.
/// Option parsing, manifests and the display pipeline build these; only the ray caster
/// (raycaster.h) turns them into dispatches.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/view_rays.h"

namespace engine {

enum class RenderMode { IsoSurface, Composite };
enum class VolumeFilter { Trilinear, Tricubic };
/// How shading normals are computed: central differences of the trilinear interpolant (6 fetches;
/// their kinks at voxel planes band coarse CT), or of the cubic B-spline interpolant (48 fetches,
/// only where a sample is shaded; smooth across voxel planes, as the tricubic filter's), or the
/// B-spline's values at the voxels blended trilinearly (BSplineAtVoxels: one fetch of a gradient
/// volume holding them, engine/render/gradient_volume.h; the B-spline's smoothing at the central
/// differences' cost; without a gradient volume the B-spline's own). The tricubic filter always
/// uses the B-spline's.
enum class GradientFilter { Central, BSpline, BSplineAtVoxels };
/// "central", "bspline", "bspline-voxels"; and back (throws std::invalid_argument listing them).
std::string gradientFilterName(GradientFilter gradient);
GradientFilter gradientFilterFromName(const std::string& name);

/// How rays are bent. The warp of space W about the map centre (DESIGN.md, "Rays"): not at all;
/// by mapping a ray's near and far points and marching the chord between them (paper Eq. 7, exact
/// for an eye at the map centre); by mapping up to five points of the ray and marching the
/// polyline through them (shaders/polyline_warp.glsl: a stereo eye's bent ray within a fraction
/// of a pixel where the chord strays by pixels; for an eye at the map centre the chord itself);
/// or by mapping every sample (the reference both are measured against). Or the map about each
/// eye (EyeCentred, the display default): every eye's ray along F of its own display direction,
/// a straight ray, so each eye sees an exactly conformal image of what it would see unbent, where
/// W's stereo eyes see its space stretched in depth against its squeezed width from a little to
/// the side (docs/polyps.md, "Stereo eyes"). The display code turns it into a chord about the eye
/// (wallView); a Warp handed to the ray caster is never EyeCentred.
enum class WarpMode { None, Chord, Polyline, Exact, EyeCentred };

/// "none", "chord", "polyline", "exact", "eye-centred"; and back (throws std::invalid_argument
/// listing them).
std::string warpModeName(WarpMode mode);
WarpMode warpModeFromName(const std::string& name);
/// The names a display's --warp option takes (every mode but none).
std::vector<std::string> bendingWarpModeNames();

struct RenderSettings {
    RenderMode mode = RenderMode::IsoSurface;
    double isoHu = -500.0;                        // iso-surface mode: the air / soft-tissue boundary
    std::string transferFunction = "colon-wall";  // composite mode: a preset name
    double stepVoxels = 0.5;                      // base step, in units of the smallest voxel side
    /// Iso mode: bisection steps refining a hit, then a linear interpolation in the last bracket;
    /// 0 = the raw sample. Two leave hits within hundredths of a millimetre of 12 on average, far
    /// below the sampling's own error (docs/benchmarks/march.md, "The march loop: two bisection steps").
    int refinementSteps = 2;
    VolumeFilter filter = VolumeFilter::Trilinear;
    GradientFilter gradient = GradientFilter::BSpline;  // docs/benchmarks/normals.md, "Shading normals on coarse CT"
    /// Read shading gradients from the gradient volume (engine/render/gradient_volume.h), computed
    /// once per volume at 8 bytes a voxel: one fetch per shaded sample in place of 6 (8 in place
    /// of 48 for B-spline normals), the same normals but for half-float rounding. Where the device
    /// cannot hold it, the ray caster takes the volume's taps instead.
    bool isUsingGradientVolume = true;
    bool isSkipping = true;                       // empty-space skipping over a distance map
    /// With skipping (not with the exact warp): a pass over the image's 8x8 tiles first finds
    /// where each tile's rays leave the empty space around them, and the march starts there.
    bool isUsingRayStartPass = true;
    /// With the tile pass: false lets it turn off the march's own looks at the distance map in
    /// tiles where they would find nothing to skip (past the tile's start, its centre and corner
    /// rays each meet a cell that can contribute before any empty cell with room to skip); true
    /// keeps them in every tile (benchmarks compare the two). With a fixed step the samples are the same either way,
    /// but for float rounding of where a skip lands.
    bool isLookingInEveryTile = false;
    /// With skipping and the exact warp: skip along the bent rays too, by the map's speed bound
    /// (Raycaster::setSpeedBounds). Off by default: on lavapipe each look costs a map fetch, and
    /// at the demo's pose the frame took 7 % longer with it (docs/benchmarks/march.md).
    bool isSkippingBentRays = false;
    int skipCellVoxels = 2;                       // cell edge of that map, voxels (8: the 8^3 bricks)
    bool isAdaptive = false;                      // lengthen steps where a pixel covers > 1 voxel
    double minStepVoxels = 0.25;                  // adaptive step bounds
    double maxStepVoxels = 4.0;
    double earlyTerminationOpacity = 0.98;        // composite mode
    bool isJittered = false;                      // offset each ray's start by a hashed fraction
    uint32_t jitterSeed = 0;
    double lightHalfDistanceMm = 0.0;             // the headlight is half as bright here; 0: no falloff
    double roughness = 0.45;                      // Cook-Torrance
    double fresnel = 0.04;
    double ambient = 0.10;
    bool isWritingHits = true;                    // fill RenderedImage::hitMm
    bool isCountingFetches = false;               // benchmarks: hitMm's w = volume fetches per ray
    bool isWritingNormals = false;                // tests: hitMm's xyz = the shading normal, not the position
    /// Tests: hitMm holds ray parameters (mm along the marched segment) instead: x the ray's own
    /// start, y its start after the tile pass, z the first sample that contributes (iso mode: the
    /// refined hit), w the flags CVC_RAY_STARTS_* (shaders/host_device.h): 1 where one does, plus
    /// 2 where the march looks at the distance map.
    bool isWritingRayStarts = false;
    /// Chord warp: keep the scene directions of each pixel's chord ends in a table per display
    /// geometry (wall, eye, scale), filled on first use and read on every later frame; false
    /// fetches them from the cube map per ray (the same images but for float rounding; tests
    /// and benchmarks compare the two).
    bool isUsingChordTable = true;
};

/// What images are for, which sets a few defaults: a pinhole still, or display frames (both
/// eyes' walls along a path, by the dozen).
enum class RenderUse { Still, DisplayFrames };

/// RenderSettings with the defaults of `use` (every other field as RenderSettings has it):
/// shading normals, the gradient volume, the step and the headlight's falloff. `cvc render` and
/// the Python module start from these, so the same request gives the same image.
RenderSettings defaultRenderSettings(RenderUse use);

/// The warp of space about the map centre (DESIGN.md "Rays"), in volume millimetres.
struct Warp {
    WarpMode mode = WarpMode::None;
    glm::dvec3 mapCentreMm{0.0};
    glm::dmat3 caveToVolume{1.0};  // columns: the CAVE's x, y, z axes as unit volume vectors
};

/// One rendered image: 8-bit RGBA colour and, per pixel, the first-hit position in volume
/// millimetres (xyz) with w = 1 for a hit, 0 for a miss. Row 0 is the top of the image.
/// Composite mode's hit is where the accumulated opacity first reaches 0.5.
struct RenderedImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
    std::vector<float> hitMm;  // 4 floats per pixel; empty when hits were not asked for
    double deviceMs = -1.0;    // time of the ray-casting dispatch on the device; < 0: unknown
};

/// The volume fetches of a render with RenderSettings::isCountingFetches (each ray's count in
/// hitMm's w): their sum over the rays, the most one ray made, and the rays counted.
struct FetchCounts {
    double total = 0.0;
    double most = 0.0;
    double rays = 0.0;
};

FetchCounts fetchCountsOf(const RenderedImage& counted);

/// One image to render: its rays, the features, and how the rays are bent.
struct RenderRequest {
    ViewRays rays;
    RenderSettings settings;
    Warp warp;
};

/// Throws std::invalid_argument naming the first setting outside its range.
void validateRenderSettings(const RenderSettings& settings);

}  // namespace engine
