/// @brief Linear scaling of polar angles along longitudes.
#include "conformal/linear_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

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

LinearMap::LinearMap(const CaveBox& box) : mBox(box) {
    validateCaveBox(box);
    if (isFaceMissing(box, 3)) {
        throw std::invalid_argument("linear map: it scales angles from the nadir, which needs the floor; this display "
                                    "lacks it");
    }
}

double LinearMap::edgeAngleFromNadir(double azimuth) const {
    const double cx = std::cos(azimuth);
    const double cz = std::sin(azimuth);
    // Horizontal distance from the centre to the wall the azimuth points at, and that wall.
    const double reachX = cx != 0.0 ? ((cx > 0.0 ? 0.5 : -0.5) * mBox.size.x - mBox.mapCentre.x) / cx
                                    : std::numeric_limits<double>::infinity();
    const double reachZ = cz != 0.0 ? ((cz > 0.0 ? 0.5 : -0.5) * mBox.size.z - mBox.mapCentre.z) / cz
                                    : std::numeric_limits<double>::infinity();
    const double reach = std::min(reachX, reachZ);
    const int wall = reachX <= reachZ ? (cx > 0.0 ? 0 : 1) : (cz > 0.0 ? 4 : 5);
    // Up the longitude from the nadir: the floor, that wall, then the ceiling. The first missing
    // one starts the edge.
    if (isFaceMissing(mBox, wall)) return std::atan2(reach, 0.5 * mBox.size.y + mBox.mapCentre.y);
    if (!isFaceMissing(mBox, 2)) return std::numbers::pi;
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
