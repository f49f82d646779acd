/// @brief Uniform-grid point location in the disk meshes, with extrapolation just outside.
#include "conformal/disk_locator.h"

#include <algorithm>
#include <cmath>

namespace conformal {

namespace {

glm::dvec3 planarBarycentric(std::complex<double> z, std::complex<double> a, std::complex<double> b,
                             std::complex<double> c) {
    const double area = (b - a).real() * (c - a).imag() - (b - a).imag() * (c - a).real();
    const auto cross = [](std::complex<double> u, std::complex<double> v) {
        return u.real() * v.imag() - u.imag() * v.real();
    };
    const double la = cross(b - z, c - z) / area;
    const double lb = cross(c - z, a - z) / area;
    return {la, lb, 1.0 - la - lb};
}

}  // namespace

DiskLocator::DiskLocator(const std::vector<std::complex<double>>& points,
                         const std::vector<std::array<int, 3>>& triangles)
    : mPoints(&points), mTriangles(&triangles) {
    mBinsPerSide = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(triangles.size()) / 2.0)),
                              1, 4096);
    mBinSize = -2.0 * mLow / mBinsPerSide;
    const std::size_t binCount = static_cast<std::size_t>(mBinsPerSide) * mBinsPerSide;
    std::vector<int> counts(binCount + 1, 0);
    auto forEachBin = [&](const std::array<int, 3>& tri, auto&& visit) {
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
        for (int v : tri) {
            x0 = std::min(x0, points[v].real());
            x1 = std::max(x1, points[v].real());
            y0 = std::min(y0, points[v].imag());
            y1 = std::max(y1, points[v].imag());
        }
        const int i0 = std::clamp(static_cast<int>((x0 - mLow) / mBinSize), 0, mBinsPerSide - 1);
        const int i1 = std::clamp(static_cast<int>((x1 - mLow) / mBinSize), 0, mBinsPerSide - 1);
        const int j0 = std::clamp(static_cast<int>((y0 - mLow) / mBinSize), 0, mBinsPerSide - 1);
        const int j1 = std::clamp(static_cast<int>((y1 - mLow) / mBinSize), 0, mBinsPerSide - 1);
        for (int j = j0; j <= j1; ++j) {
            for (int i = i0; i <= i1; ++i) visit(j * mBinsPerSide + i);
        }
    };
    for (const auto& tri : triangles) forEachBin(tri, [&](int bin) { ++counts[bin + 1]; });
    for (std::size_t b = 0; b < binCount; ++b) counts[b + 1] += counts[b];
    mBinOffsets = counts;
    mBinTriangles.assign(counts[binCount], -1);
    std::vector<int> fill(counts.begin(), counts.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        forEachBin(triangles[t], [&](int bin) { mBinTriangles[fill[bin]++] = static_cast<int>(t); });
    }
}

int DiskLocator::binIndex(double x, double y) const {
    // Clamped before the conversion: a point far outside the disk would overflow int (UB).
    const double last = mBinsPerSide - 1;
    const int i = static_cast<int>(std::clamp((x - mLow) / mBinSize, 0.0, last));
    const int j = static_cast<int>(std::clamp((y - mLow) / mBinSize, 0.0, last));
    return j * mBinsPerSide + i;
}

DiskLocation DiskLocator::locate(std::complex<double> z) const {
    const auto& points = *mPoints;
    const auto& triangles = *mTriangles;
    DiskLocation best;
    // Not a point: no triangle holds it (and NaN must not reach the bin index's conversion).
    if (!std::isfinite(z.real()) || !std::isfinite(z.imag())) return best;
    double bestMin = -1e300;
    auto test = [&](int bin) {
        for (int k = mBinOffsets[bin]; k < mBinOffsets[bin + 1]; ++k) {
            const int t = mBinTriangles[k];
            const auto& tri = triangles[t];
            const glm::dvec3 bary = planarBarycentric(z, points[tri[0]], points[tri[1]], points[tri[2]]);
            const double least = std::min({bary.x, bary.y, bary.z});
            if (least > bestMin) {
                bestMin = least;
                best.triangle = t;
                best.barycentric = bary;
                if (least >= 0.0) return true;
            }
        }
        return false;
    };
    const int bin = binIndex(z.real(), z.imag());
    if (test(bin)) {
        best.isInside = true;
        return best;
    }
    // Outside the mesh or on a bin's edge: look at the neighbouring bins too.
    const int bi = bin % mBinsPerSide;
    const int bj = bin / mBinsPerSide;
    for (int radius = 1; radius <= 2 && (best.triangle < 0 || radius == 1); ++radius) {
        for (int j = std::max(bj - radius, 0); j <= std::min(bj + radius, mBinsPerSide - 1); ++j) {
            for (int i = std::max(bi - radius, 0); i <= std::min(bi + radius, mBinsPerSide - 1); ++i) {
                if (std::max(std::abs(i - bi), std::abs(j - bj)) != radius) continue;
                if (test(j * mBinsPerSide + i)) {
                    best.isInside = true;
                    return best;
                }
            }
        }
    }
    best.isInside = bestMin >= -1e-12;
    return best;
}

}  // namespace conformal
