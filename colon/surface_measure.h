/// @brief Measuring on a rendered wall from its hit image (colon/hit_image.h): the straight 3D
/// distance between two pixels' hits, and the largest diameter of the polyp-like patch of
/// surface around a pixel.
///
/// The patch rule, and why it is built so. A polyp is a protrusion: seen from the lumen its
/// surface is convex, and where it meets the wall the surface turns concave (the crease at a
/// sessile polyp's base, the neck under a pedunculated head), or the view steps behind it onto
/// a far wall (a silhouette). Thresholds on depth or on the image's intensity know nothing of
/// scale and break between a 3 mm and a 15 mm polyp; the sign of curvature does not. So the patch
/// is grown from the seed pixel s over 4-neighbours q and keeps q only when
///  1. q is a hit, continuous with the pixel p it is reached from: |q - p| <= kContinuity * l(p),
///     l(p) the local pixel footprint (per image axis the shorter of the two one-sided steps,
///     the larger of the two axes, so a surface seen at a grazing angle is not cut but a
///     depth jump at a silhouette is);
///  2. q keeps the seed behind its tangent plane: n(q) . (q - s) >= -kTangentSlack * |q - s|,
///     n(q) the surface normal estimated from the hit image (cross product of neighbour
///     differences, facing the viewer; across a depth step, the shorter side's one-sided
///     difference, so a wall pixel beside a silhouette keeps the wall's normal). Every tangent plane of a convex cap has the cap's
///     inside, and so s, behind it; the wall beyond the crease has s in front of it (by about the
///     polyp's height, whether the wall is flat or the lumen's concave tube), so the rule stops
///     at the crease without a length scale. The slack allows for the normal's noise (it is
///     relative to |q - s|, so it does not grow with the polyp);
///  3. q lies within the tolerance of the sphere fitted (least squares) to the grown patch:
///     max(kSphereTolerance * R, 2 l(s)). The patch is grown by 1 and 2, then kSphereRounds
///     times the sphere is fitted and the pixels off it dropped (with what is then no longer
///     connected to the seed): a guard against a leak through a gap in the crease, which adds
///     wall far off the sphere, and it trims the rounded fillet a CT's partial-volume blur
///     leaves at the crease (rule 2 alone lets that in until the normal has turned about 50
///     degrees, some 0.3 mm per side on the phantom). A flat patch (no sphere, or one more than
///     20 times the patch's size) is not guarded.
/// The diameter is the largest 3D distance between two patch hits (a boundary pixel and any
/// other: the farthest pair of a cap lies on its rim). A hemisphere of radius r on a wall gives
/// its base circle, 2r; a polyp head seen from the side, its outline, 2r; from a finite distance
/// D the visible rim is a little smaller than the sphere's, by the factor sqrt(1 - r^2/D^2), so
/// view from 2-3 diameters.
#pragma once

#include <array>
#include <optional>

#include "colon/hit_image.h"

namespace colon {

inline constexpr double kContinuity = 4.0;        ///< rule 1: steps up to this many footprints
inline constexpr double kTangentSlack = 0.1;      ///< rule 2: sin of about 6 degrees
inline constexpr double kSphereTolerance = 0.05;  ///< rule 3: relative to the fitted radius
inline constexpr int kSphereRounds = 4;          ///< rule 3: fits, each dropping what lies off the last

/// The straight 3D distance (mm) between the hits of pixels (x0, y0) and (x1, y1). Throws
/// ColonError naming the pixel if one lies outside the image or its ray missed.
double surfaceDistanceMm(const HitImage& image, int x0, int y0, int x1, int y1);

struct PatchDiameter {
    double diameterMm = 0.0;
    int pixelCount = 0;                    ///< pixels in the patch
    std::array<int, 2> end0{0, 0};         ///< the two pixels (x, y) the diameter runs between
    std::array<int, 2> end1{0, 0};
    glm::dvec3 end0Mm{0.0}, end1Mm{0.0};   ///< their hits
    double footprintMm = 0.0;              ///< the pixel footprint at the seed
    double sphereRadiusMm = 0.0;           ///< radius of the sphere fitted to the patch (0: no fit)
    glm::dvec3 sphereCentreMm{0.0};
};

/// The surface normal at a hit pixel, facing the viewer: the cross product of the row-down and
/// column-right differences of the hits (central where both neighbours are continuous with the
/// pixel, else the continuous side's; an image that is not mirrored, as every cvc render).
/// Nothing where it cannot be estimated (an isolated hit, no continuous neighbour on an axis).
std::optional<glm::dvec3> hitNormalAt(const HitImage& image, int x, int y);

/// The largest diameter of the protruding patch around pixel (x, y) by the rule above. Throws
/// ColonError for a seed outside the image or on a miss, and for a patch of fewer than 3 pixels.
PatchDiameter polypDiameter(const HitImage& image, int x, int y);

}  // namespace colon
