#include "colon/surface_curvature.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "colon/colon_error.h"

namespace colon {
namespace {

/// The 1D Gaussian's weights about a coordinate, and their first and second derivatives with
/// respect to the point, for the voxels of one axis within 3 sigma (clipped to the grid).
struct AxisKernel {
    int first = 0;  ///< index of the first voxel
    std::vector<double> value, slope, curve;
};

AxisKernel axisKernel(double coordinateMm, double spacingMm, int voxels, double sigmaMm) {
    AxisKernel kernel;
    const int radius = std::min(kMaxKernelRadiusVoxels, static_cast<int>(std::ceil(3.0 * sigmaMm / spacingMm)));
    const int centre = static_cast<int>(std::floor(coordinateMm / spacingMm));
    kernel.first = std::max(0, centre - radius);
    const int last = std::min(voxels - 1, centre + radius + 1);
    const double inverseVariance = 1.0 / (sigmaMm * sigmaMm);
    for (int i = kernel.first; i <= last; ++i) {
        const double d = coordinateMm - i * spacingMm;  // the point relative to the voxel
        const double w = std::exp(-0.5 * d * d * inverseVariance);
        kernel.value.push_back(w);
        kernel.slope.push_back(-d * inverseVariance * w);
        kernel.curve.push_back((d * d * inverseVariance - 1.0) * inverseVariance * w);
    }
    return kernel;
}

}  // namespace

double shapeIndexOf(double k1, double k2) { return 0.5 + std::atan2(k1 + k2, k1 - k2) / M_PI; }

double curvednessOf(double k1, double k2) { return std::sqrt(0.5 * (k1 * k1 + k2 * k2)); }

std::optional<SurfaceShape> surfaceShapeAt(const volumes::Volume& volume, const glm::dvec3& pointMm, double sigmaMm,
                                           double isoHu) {
    if (!(sigmaMm > 0.0) || !std::isfinite(sigmaMm)) throw ColonError("surface shape: the smoothing must be positive");
    for (int a = 0; a < 3; ++a) {
        if (!(pointMm[a] >= 0.0 && pointMm[a] <= (volume.dims[static_cast<std::size_t>(a)] - 1) * volume.spacingMm[a])) {
            return std::nullopt;
        }
    }
    const AxisKernel kx = axisKernel(pointMm.x, volume.spacingMm.x, volume.dims[0], sigmaMm);
    const AxisKernel ky = axisKernel(pointMm.y, volume.spacingMm.y, volume.dims[1], sigmaMm);
    const AxisKernel kz = axisKernel(pointMm.z, volume.spacingMm.z, volume.dims[2], sigmaMm);
    // Sums over the voxels: the gradient (x, y, z) and the Hessian (xx, yy, zz, xy, xz, yz).
    std::array<double, 9> sum{};
    for (std::size_t c = 0; c < kz.value.size(); ++c) {
        const int k = kz.first + static_cast<int>(c);
        for (std::size_t b = 0; b < ky.value.size(); ++b) {
            const int j = ky.first + static_cast<int>(b);
            // Along x: the value, slope and curve of the row, then combined with y and z.
            double row = 0.0, rowSlope = 0.0, rowCurve = 0.0;
            for (std::size_t a = 0; a < kx.value.size(); ++a) {
                const double f = volume.at(kx.first + static_cast<int>(a), j, k) - isoHu;
                row += f * kx.value[a];
                rowSlope += f * kx.slope[a];
                rowCurve += f * kx.curve[a];
            }
            const double wy = ky.value[b], sy = ky.slope[b], cy = ky.curve[b];
            const double wz = kz.value[c], sz = kz.slope[c], cz = kz.curve[c];
            sum[0] += rowSlope * wy * wz;
            sum[1] += row * sy * wz;
            sum[2] += row * wy * sz;
            sum[3] += rowCurve * wy * wz;
            sum[4] += row * cy * wz;
            sum[5] += row * wy * cz;
            sum[6] += rowSlope * sy * wz;
            sum[7] += rowSlope * wy * sz;
            sum[8] += row * sy * sz;
        }
    }
    // The same normalisation for every sum (the kernel's discrete mass), so it cancels in the
    // curvatures; it only keeps the numbers in HU per mm.
    double mass = 0.0;
    {
        double mx = 0.0, my = 0.0, mz = 0.0;
        for (double w : kx.value) mx += w;
        for (double w : ky.value) my += w;
        for (double w : kz.value) mz += w;
        mass = mx * my * mz;
    }
    if (!(mass > 0.0)) return std::nullopt;
    for (double& s : sum) s /= mass;
    const glm::dvec3 gradient(sum[0], sum[1], sum[2]);
    const glm::dmat3 hessian(sum[3], sum[6], sum[7],   // column x
                             sum[6], sum[4], sum[8],   // column y
                             sum[7], sum[8], sum[5]);  // column z
    const double slope = glm::length(gradient);
    if (!(slope > 1e-9) || !std::isfinite(slope)) return std::nullopt;

    SurfaceShape shape;
    shape.normal = -gradient / slope;
    // An orthonormal basis of the tangent plane, from the axis least aligned with the normal.
    const glm::dvec3 n = shape.normal;
    const glm::dvec3 axis = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? glm::dvec3(1, 0, 0)
                            : std::abs(n.y) <= std::abs(n.z)                                  ? glm::dvec3(0, 1, 0)
                                                                                               : glm::dvec3(0, 0, 1);
    const glm::dvec3 t1 = glm::normalize(glm::cross(n, axis));
    const glm::dvec3 t2 = glm::cross(n, t1);
    const double a = -glm::dot(t1, hessian * t1) / slope;
    const double b = -glm::dot(t1, hessian * t2) / slope;
    const double c = -glm::dot(t2, hessian * t2) / slope;
    const double mean = 0.5 * (a + c);
    const double spread = std::sqrt(0.25 * (a - c) * (a - c) + b * b);
    shape.k1 = mean + spread;
    shape.k2 = mean - spread;
    shape.shapeIndex = shapeIndexOf(shape.k1, shape.k2);
    shape.curvedness = curvednessOf(shape.k1, shape.k2);
    return shape;
}

}  // namespace colon
