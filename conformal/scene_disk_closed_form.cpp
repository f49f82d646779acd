/// @brief Closed-form phi6 for square ceilings: stereographic projection from the zenith sends
/// Omega6 to the plane minus four rays, which w -> w / sqrt(1 + sqrt(1 + w^4 / a)) opens onto
/// the disk.
#include "conformal/scene_disk_closed_form.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

using Complex = std::complex<double>;

/// a = |w(corner)|^4 with w the stereographic coordinate from the zenith.
double cornerRadiusFourth(const CaveBox& box) {
    const glm::dvec3 corner = ceilingCornerDirections(box)[0];
    const double radius = std::hypot(corner.x, corner.z) / (1.0 - corner.y);
    return std::pow(radius, 4.0);
}

}  // namespace

bool hasSceneDiskClosedForm(const CaveBox& box) {
    return box.size.x == box.size.z && box.mapCentre.x == 0.0 && box.mapCentre.z == 0.0;
}

Complex sceneDiskFromDirectionClosedForm(const CaveBox& box, const glm::dvec3& direction) {
    const double a = cornerRadiusFourth(box);
    const glm::dvec3 d = glm::normalize(direction);
    const Complex w = Complex(d.x, d.z) / (1.0 - d.y);
    const Complex w2 = w * w;
    const Complex inner = std::sqrt(1.0 + w2 * w2 / a);
    const Complex phi = w / (std::pow(a, 0.25) * std::sqrt(1.0 + inner));
    return phi * std::polar(1.0, -0.25 * std::numbers::pi);
}

glm::dvec3 directionFromSceneDiskClosedForm(const CaveBox& box, Complex zeta) {
    const double a = cornerRadiusFourth(box);
    const Complex z = zeta * std::polar(1.0, 0.25 * std::numbers::pi);
    const Complex z2 = z * z;
    const Complex w = std::pow(4.0 * a, 0.25) * z / std::sqrt(1.0 - z2 * z2);
    const double r2 = std::norm(w);
    if (!std::isfinite(r2)) return {0.0, 1.0, 0.0};
    return glm::dvec3(2.0 * w.real(), r2 - 1.0, 2.0 * w.imag()) / (r2 + 1.0);
}

}  // namespace conformal
