/// @brief A polyp's shape as the viewer sees it, never in raw wall pixels: a wall image is a
/// planar projection that by itself stretches a shape by up to ~25 % near the wall's edge.
///
/// Each pixel of a view (a wall of an immersive display, or a pinhole image) is a direction
/// from the eye with the solid angle it covers. The polyp's pixels (those whose first hit lies
/// on the polyp by the ground truth, polyp_truth.h) are projected onto the tangent plane at the
/// polyp's mean direction (gnomonic projection, each pixel weighted by the area it covers there),
/// and measured there:
///  - the second-moment ellipse: aspect ratio sqrt(l1 / l2) of the covariance's eigenvalues and
///    the orientation of its major axis;
///  - the moment-based circularity A^2 / (2 pi (mu20 + mu02)): 1 for a disc, 2ab / (a^2 + b^2)
///    for an ellipse of semi-axes a, b, less for ragged or cut-off shapes;
///  - the angle of a grid painted on the polyp's cap: two coordinates on the polyp (the hit's
///    offset from the polyp's centre along two axes perpendicular to `gridNormal`, the line of
///    sight from the reference's eye to the polyp, so the grid faces that eye and looks square
///    from it; every view of one eye measures the same painted grid), each fitted
///    as a linear function of the tangent-plane position over the cap's middle (within half the
///    polyp's radius of its centroid); the angle between their gradients is the angle at which
///    the grid's lines cross as seen. A conformal view keeps it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "colon/polyp_truth.h"
#include "colon/rgba_image.h"

namespace colon {

/// One pixel of a view.
struct ViewSample {
    glm::dvec3 direction{0.0};  ///< unit direction from the eye, volume axes (the display direction)
    double solidAngleSr = 0.0;  ///< the solid angle the pixel covers
    bool isHit = false;
    glm::dvec3 hitMm{0.0};      ///< first hit, volume millimetres
    std::array<uint8_t, 4> rgba{0, 0, 0, 255};
};

struct ShapeMeasures {
    int pixels = 0;                  ///< the polyp's pixels in the view
    double pixelsAcross = 0.0;       ///< the polyp's width in pixels (2 sqrt(pixels / pi))
    glm::dvec3 centreDirection{0.0}; ///< the mean direction of its pixels
    double areaSr = 0.0;             ///< its area in the tangent plane (steradians, to first order)
    double aspect = 0.0;             ///< >= 1
    double orientationDeg = 0.0;     ///< the major axis against the tangent plane's first axis, 0..180
    double circularity = 0.0;        ///< 1 for a disc
    double gridAngleDeg = 0.0;       ///< 90 where the grid is seen square-on
};

/// Fewest polyp pixels for the measures to mean something: about 11 pixels across, so that a
/// one-pixel ragged edge moves the aspect and circularity by under ~3 %.
inline constexpr int kMinPolypPixels = 100;


/// Hit tolerance for the polyp's surface: a quarter of the largest voxel spacing plus 0.1 mm
/// (the refined hit lies within a fraction of a voxel of the iso surface).
double polypToleranceMm(const glm::dvec3& spacingMm);

/// The measures of `polyp` in `samples` (every pixel of the view, or any subset holding the
/// polyp's), the grid painted facing `gridNormal`. Fewer than three polyp pixels give
/// pixels < 3 and zero measures.
ShapeMeasures measurePolypShape(const std::vector<ViewSample>& samples, const PolypSurface& polyp, double toleranceMm,
                                const glm::dvec3& gridNormal);

/// The view around the polyp resampled in its tangent plane (centred on its mean direction,
/// `halfWidth` tangent-plane units to each side, the first axis along the view's `right`), so
/// views of one polyp can be set side by side at one scale: what the viewer sees, not the wall.
RgbaImage tangentPlaneCrop(const std::vector<ViewSample>& samples, const glm::dvec3& centreDirection,
                           const glm::dvec3& right, double halfWidth, int size);

}  // namespace colon
