#include "engine/render/view_rays.h"

#include <cmath>
#include <stdexcept>

namespace engine {

ViewRays viewRaysFrom(const PinholeCamera& camera) {
    const CameraBasis basis = cameraBasis(camera);
    ViewRays rays;
    rays.eyeMm = camera.positionMm;
    rays.wallOriginMm = camera.positionMm + basis.forward - basis.rightScaled + basis.upScaled;
    rays.wallUMm = 2.0 * basis.rightScaled;
    rays.wallVMm = -2.0 * basis.upScaled;
    rays.width = camera.width;
    rays.height = camera.height;
    return rays;
}

glm::dvec3 wallNormalOf(const ViewRays& rays) {
    const glm::dvec3 n = glm::cross(rays.wallUMm, rays.wallVMm);
    const double length = glm::length(n);
    if (!(length > 0.0) || !std::isfinite(length)) throw std::invalid_argument("view rays: degenerate wall rectangle");
    const glm::dvec3 centre = rays.wallOriginMm + 0.5 * (rays.wallUMm + rays.wallVMm);
    const double side = glm::dot(n, centre - rays.eyeMm);
    if (std::abs(side) < 1e-12 * length) throw std::invalid_argument("view rays: the eye lies in the wall's plane");
    return side > 0.0 ? n / length : -n / length;
}

glm::dvec3 rayDirectionOf(const ViewRays& rays, double column, double row) {
    const glm::dvec3 point = rays.wallOriginMm + (column + 0.5) / rays.width * rays.wallUMm +
                             (row + 0.5) / rays.height * rays.wallVMm;
    return glm::normalize(point - rays.eyeMm);
}

double pixelAngleOf(const ViewRays& rays) {
    const glm::dvec3 centre = rays.wallOriginMm + 0.5 * (rays.wallUMm + rays.wallVMm);
    const double pixelMm = glm::length(rays.wallUMm) / rays.width;
    return pixelMm / glm::length(centre - rays.eyeMm);
}

}  // namespace engine
