/// @brief The render settings' ranges, and the fetch counts of a counting render.
#include "engine/render/render_settings.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace engine {

void validateRenderSettings(const RenderSettings& s) {
    auto require = [](bool condition, const std::string& what) {
        if (!condition) throw std::invalid_argument("render settings: " + what);
    };
    require(s.stepVoxels >= 0.01 && s.stepVoxels <= 8.0, "step must be 0.01..8 voxels");
    require(s.skipCellVoxels >= 1 && s.skipCellVoxels <= 64, "skipping cells must be 1..64 voxels");
    require(s.refinementSteps >= 0 && s.refinementSteps <= 32, "refinement steps must be 0..32");
    require(std::isfinite(s.isoHu), "iso value must be finite");
    require(s.minStepVoxels > 0.0 && s.minStepVoxels <= s.maxStepVoxels && s.maxStepVoxels <= 64.0,
            "adaptive step bounds must satisfy 0 < min <= max <= 64 voxels");
    require(s.earlyTerminationOpacity > 0.0 && s.earlyTerminationOpacity <= 1.0, "early termination opacity must be in (0, 1]");
    require(s.lightHalfDistanceMm >= 0.0 && std::isfinite(s.lightHalfDistanceMm), "light half distance must be >= 0");
    require(s.roughness > 0.0 && s.roughness <= 1.0 && s.fresnel >= 0.0 && s.fresnel <= 1.0 && s.ambient >= 0.0 &&
                s.ambient <= 1.0,
            "roughness in (0, 1], Fresnel and ambient in [0, 1]");
}

RenderSettings defaultRenderSettings(RenderUse use) {
    const bool isDisplay = use == RenderUse::DisplayFrames;
    RenderSettings settings;
    // Stills get smooth normals: the B-spline's values at the voxels, one fetch of the gradient
    // volume per shaded sample, within 0.005 RMSE of the tricubic image on 3 mm CT at the central
    // differences' cost (docs/benchmarks/normals.md). The volume is built before the first frame
    // (about 4 s for the 512x512x451 yardstick here): it pays from a session's second view on, and
    // a one-off still of a large CT is quicker with it off (the B-spline's own normals, 48 fetches).
    // Display frames, which come by the dozen from inside the colon where the bands hardly show,
    // keep the central differences.
    settings.gradient = isDisplay ? GradientFilter::Central : GradientFilter::BSplineAtVoxels;
    settings.isUsingGradientVolume = true;
    // Display frames light the near wall: a headlight half as bright 25 mm away; a still has none.
    settings.lightHalfDistanceMm = isDisplay ? 25.0 : 0.0;
    // Display frames come by the dozen and their hits are refined by bisection: a voxel-long
    // step halves their time; a still keeps the finer default.
    settings.stepVoxels = isDisplay ? 1.0 : 0.5;
    return settings;
}

std::string gradientFilterName(GradientFilter gradient) {
    switch (gradient) {
        case GradientFilter::Central: return "central";
        case GradientFilter::BSpline: return "bspline";
        case GradientFilter::BSplineAtVoxels: return "bspline-voxels";
    }
    throw std::invalid_argument("unknown gradient filter");
}

GradientFilter gradientFilterFromName(const std::string& name) {
    for (GradientFilter gradient : {GradientFilter::Central, GradientFilter::BSpline, GradientFilter::BSplineAtVoxels}) {
        if (gradientFilterName(gradient) == name) return gradient;
    }
    throw std::invalid_argument("gradient '" + name + "' is not one of central, bspline, bspline-voxels");
}

std::string warpModeName(WarpMode mode) {
    switch (mode) {
        case WarpMode::None: return "none";
        case WarpMode::Chord: return "chord";
        case WarpMode::Polyline: return "polyline";
        case WarpMode::Exact: return "exact";
        case WarpMode::EyeCentred: return "eye-centred";
    }
    throw std::invalid_argument("unknown warp mode");
}

WarpMode warpModeFromName(const std::string& name) {
    for (WarpMode mode : {WarpMode::None, WarpMode::Chord, WarpMode::Polyline, WarpMode::Exact, WarpMode::EyeCentred}) {
        if (warpModeName(mode) == name) return mode;
    }
    throw std::invalid_argument("warp '" + name + "' is not one of none, chord, polyline, exact, eye-centred");
}

std::vector<std::string> bendingWarpModeNames() { return {"eye-centred", "polyline", "chord", "exact"}; }

FetchCounts fetchCountsOf(const RenderedImage& counted) {
    FetchCounts counts;
    for (std::size_t i = 3; i < counted.hitMm.size(); i += 4) {
        counts.total += counted.hitMm[i];
        counts.most = std::max(counts.most, static_cast<double>(counted.hitMm[i]));
    }
    counts.rays = static_cast<double>(counted.hitMm.size() / 4);
    return counts;
}

}  // namespace engine
