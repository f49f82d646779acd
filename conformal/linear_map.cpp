/// @brief Linear scaling of polar angles along longitudes.
#include "conformal/linear_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

struct Polar {
    double fromNadir = 0.0;
    double azimuth = 0.0;
};

Polar polarOf(const glm::dvec3& direction) {
    const glm::dvec3 d = glm::normalize(direction);
    return {std::acos(std::clamp(-d.y, -1.0, 1.0)), std::atan2(d.z, d.x)};
}

glm::dvec3 directionOf(double fromNadir, double azimuth) {
    return {std::sin(fromNadir) * std::cos(azimuth), -std::cos(fromNadir),
            std::sin(fromNadir) * std::sin(azimuth)};
}

}  // namespace

LinearMap::LinearMap(const CaveBox& box) : mBox(box) { validateCaveBox(box); }

double LinearMap::edgeAngleFromNadir(double azimuth) const {
    const double cx = std::cos(azimuth);
    const double cz = std::sin(azimuth);
    double reach = std::numeric_limits<double>::infinity();
    // Horizontal distance from the centre to the ceiling rectangle's edge along the azimuth.
    if (cx != 0.0) reach = std::min(reach, ((cx > 0.0 ? 0.5 : -0.5) * mBox.size.x - mBox.mapCentre.x) / cx);
    if (cz != 0.0) reach = std::min(reach, ((cz > 0.0 ? 0.5 : -0.5) * mBox.size.z - mBox.mapCentre.z) / cz);
    const double height = 0.5 * mBox.size.y - mBox.mapCentre.y;
    return std::numbers::pi - std::atan2(reach, height);
}

glm::dvec3 LinearMap::sceneFromDisplay(const glm::dvec3& display) const {
    const Polar p = polarOf(display);
    return directionOf(p.fromNadir * std::numbers::pi / edgeAngleFromNadir(p.azimuth), p.azimuth);
}

glm::dvec3 LinearMap::displayFromScene(const glm::dvec3& scene) const {
    const Polar p = polarOf(scene);
    return directionOf(p.fromNadir * edgeAngleFromNadir(p.azimuth) / std::numbers::pi, p.azimuth);
}

}  // namespace conformal
