/// @brief The shape of the iso-surface at a point, from the smoothed volume's derivatives: the
/// principal curvatures of the level set through the point, its shape index and curvedness
/// (Koenderink & van Doorn 1992; as used for polyp detection in CT colonography by Yoshida &
/// Naeppi, IEEE TMI 20(12), 2001).
///
/// The volume is smoothed by a Gaussian of `sigmaMm` (isotropic, in millimetres), its gradient
/// g and Hessian H evaluated exactly at the point by the Gaussian's derivative kernels summed
/// over the voxels within 3 sigma. The surface normal n = -g/|g| points toward lower HU, into
/// the air of the lumen, the side a viewer looks from; the shape operator on the tangent plane
/// is -P H P / |g| (P the projection onto the plane), its eigenvalues k1 >= k2 the principal
/// curvatures, signed so that a bump of tissue into the air (a polyp seen from the lumen) has
/// both positive. Then
///   shape index  SI = 1/2 + atan2(k1 + k2, k1 - k2) / pi   in [0, 1]:
///                0 cup, 0.25 rut (the lumen's tube), 0.5 saddle, 0.75 ridge (a fold), 1 cap;
///   curvedness   CV = sqrt((k1^2 + k2^2) / 2)             (1/mm; 1/r on a sphere of radius r).
/// Yoshida's own formula has the opposite sign of curvature with 1/2 - atan(...): the same
/// values.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "volumes/volume.h"

namespace colon {

struct SurfaceShape {
    glm::dvec3 normal{0.0};  ///< unit, toward lower HU
    double k1 = 0.0;         ///< larger principal curvature (1/mm)
    double k2 = 0.0;         ///< smaller principal curvature (1/mm)
    double shapeIndex = 0.5;
    double curvedness = 0.0;
};

/// Largest kernel half-width, in voxels per axis: a bound on the work per point whatever the
/// spacing and sigma a caller gives.
inline constexpr int kMaxKernelRadiusVoxels = 24;

/// The shape at `pointMm` (volume millimetres) of the iso-surface of `volume` smoothed by
/// `sigmaMm`, measured relative to `isoHu` (which only keeps the sums well conditioned). Nothing
/// where the smoothed gradient vanishes or the point lies outside the volume's box. Throws
/// ColonError for a sigma that is not positive and finite.
std::optional<SurfaceShape> surfaceShapeAt(const volumes::Volume& volume, const glm::dvec3& pointMm, double sigmaMm,
                                           double isoHu);

/// The shape index and curvedness of principal curvatures k1 >= k2 (see above).
double shapeIndexOf(double k1, double k2);
double curvednessOf(double k1, double k2);

}  // namespace colon
