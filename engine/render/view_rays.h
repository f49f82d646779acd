/// @brief Where the rays of one image come from: an eye and a rectangle (a display wall, or a
/// pinhole camera's image plane) that the rays pass through, in volume millimetres.
#pragma once

#include <glm/glm.hpp>

#include "engine/render/pinhole_camera.h"

namespace engine {

/// Pixel (x, y), row 0 at the top, looks from `eyeMm` through
/// wallOriginMm + (x + 0.5) / width * wallUMm + (y + 0.5) / height * wallVMm.
struct ViewRays {
    glm::dvec3 eyeMm{0.0};
    glm::dvec3 wallOriginMm{0.0};  // the image rectangle's top-left corner
    glm::dvec3 wallUMm{1.0, 0.0, 0.0};   // its full width, left to right
    glm::dvec3 wallVMm{0.0, -1.0, 0.0};  // its full height, top to bottom
    double nearMm = 0.0;  // rays start on the plane parallel to the rectangle this far from the eye
    int width = 1;
    int height = 1;
};

/// The rays of a pinhole camera (the rectangle is its image plane at unit distance).
ViewRays viewRaysFrom(const PinholeCamera& camera);

/// Unit normal of the rectangle, pointing away from the eye. Throws std::invalid_argument for
/// a degenerate rectangle or an eye in its plane.
glm::dvec3 wallNormalOf(const ViewRays& rays);

/// Unit direction of the ray through the centre of pixel (column, row): the C++ twin of
/// wallPointMm() in shaders/ray_generation.glsl.
glm::dvec3 rayDirectionOf(const ViewRays& rays, double column, double row);

/// Angle (radians) one pixel subtends at the rectangle's centre, seen from the eye.
double pixelAngleOf(const ViewRays& rays);

}  // namespace engine
