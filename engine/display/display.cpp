#include "engine/display/display.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace engine {

glm::dmat3 caveToVolumeRotation(const ScenePose& pose) {
    const double fLength = glm::length(pose.forward);
    if (!(fLength > 0.0) || !std::isfinite(fLength)) throw std::invalid_argument("scene pose: forward is zero");
    const glm::dvec3 forward = pose.forward / fLength;
    const glm::dvec3 right = glm::cross(forward, pose.up);
    const double rLength = glm::length(right);
    if (!(rLength > 1e-9 * std::max(1.0, glm::length(pose.up)))) {
        throw std::invalid_argument("scene pose: up is zero or parallel to forward");
    }
    const glm::dvec3 x = right / rLength;
    const glm::dvec3 y = glm::cross(x, forward);
    return glm::dmat3(x, y, -forward);  // CAVE x = right, y = up, z = back
}

WallView wallView(const Display& display, WallName wall, Eye eye, const ScenePose& pose, WarpMode warpMode) {
    if (!(pose.mmPerMetre > 0.0) || !std::isfinite(pose.mmPerMetre)) {
        throw std::invalid_argument("scene pose: millimetres per metre must be positive");
    }
    const glm::dmat3 rotation = caveToVolumeRotation(pose);
    const double s = pose.mmPerMetre;
    // The pose places the map centre, about which the rays bend; the box (the CAVE origin) sits
    // around it, offset when the map is not centred in the box.
    const auto toVolume = [&](const glm::dvec3& caveM) {
        return pose.positionMm + rotation * (caveM - display.mapCentreM) * s;
    };
    const WallRectangle rect = wallRectangle(display, wall);
    const auto found = std::find_if(display.walls.begin(), display.walls.end(),
                                    [wall](const DisplayWall& w) { return w.name == wall; });
    if (found == display.walls.end()) {
        throw std::invalid_argument("display '" + display.name + "' has no " + wallNameText(wall) + " wall");
    }
    WallView view;
    view.rays.eyeMm = toVolume(eyePositionM(display, eye));
    view.rays.wallOriginMm = toVolume(rect.topLeftM);
    view.rays.wallUMm = rotation * rect.widthM * s;
    view.rays.wallVMm = rotation * rect.heightM * s;
    view.rays.nearMm = display.nearM * s;
    view.rays.width = found->width;
    view.rays.height = found->height;
    view.warp.mode = display.map == conformal::MapKind::None ? WarpMode::None : warpMode;
    view.warp.mapCentreMm = pose.positionMm;
    if (view.warp.mode == WarpMode::EyeCentred) {
        // The map about the eye: W_e(q) = e + |q - e| F(dir(q - e)) sends the eye's ray e + t d
        // to the straight ray e + t F(d), which one chord marches exactly.
        view.warp.mode = WarpMode::Chord;
        view.warp.mapCentreMm = view.rays.eyeMm;
    }
    view.warp.caveToVolume = rotation;
    return view;
}

}  // namespace engine
