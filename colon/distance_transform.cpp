#include "colon/distance_transform.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "volumes/parallel_for.h"

namespace colon {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The 1D squared distance transform of f (n samples `spacing` apart) into d: d[p] =
/// min_q (spacing (p - q))^2 + f[q]. v, z are scratch of n + 2 and n + 3 entries (the line's
/// samples and one virtual outside sample beyond each end).
void transformLine(int n, double spacing, const double* f, double* d, int* v, double* z) {
    // Samples beyond the line are outside (f = 0 there), so each end sees at most the distance
    // to the border's first outside sample: seed the envelope with those two virtual samples.
    const double s2 = spacing * spacing;
    int k = 0;
    v[0] = -1;  // a virtual outside sample just before the line
    z[0] = -kInfinity;
    z[1] = kInfinity;
    auto value = [&](int q) { return q < 0 || q >= n ? 0.0 : f[q]; };
    for (int q = 0; q <= n; ++q) {  // q == n: the virtual outside sample just after the line
        const double fq = value(q);
        if (!std::isfinite(fq)) continue;
        double s = 0.0;
        while (true) {
            const int r = v[k];
            s = ((fq + s2 * q * q) - (value(r) + s2 * r * r)) / (2.0 * s2 * (q - r));
            if (s <= z[k] && k > 0) {
                --k;
                continue;
            }
            break;
        }
        if (s <= z[k]) {  // k == 0 and the new parabola hides the first: replace it
            v[0] = q;
            z[0] = -kInfinity;
            z[1] = kInfinity;
            continue;
        }
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = kInfinity;
    }
    k = 0;
    for (int p = 0; p < n; ++p) {
        while (z[k + 1] < p) ++k;
        const double delta = spacing * (p - v[k]);
        d[p] = delta * delta + value(v[k]);
    }
}

}  // namespace

std::vector<float> distanceToOutsideMm(const Grid& grid, const std::vector<uint8_t>& inside) {
    if (inside.size() != grid.voxelCount()) throw std::invalid_argument("distance transform: mask does not fit the grid");
    const std::size_t count = inside.size();
    std::vector<double> squared(count);
    for (std::size_t n = 0; n < count; ++n) squared[n] = inside[n] != 0 ? kInfinity : 0.0;
    const std::array<std::size_t, 3> strides{1, static_cast<std::size_t>(grid.dims[0]),
                                             static_cast<std::size_t>(grid.dims[0]) * static_cast<std::size_t>(grid.dims[1])};
    for (int axis = 0; axis < 3; ++axis) {
        const auto a = static_cast<std::size_t>(axis);
        const int n = grid.dims[a];
        const std::size_t stride = strides[a];
        // The lines along `axis`: one per voxel of the other two axes.
        const int u = grid.dims[(a + 1) % 3], w = grid.dims[(a + 2) % 3];
        const std::size_t strideU = strides[(a + 1) % 3], strideW = strides[(a + 2) % 3];
        volumes::parallelFor(w, [&](int iw) {
            std::vector<double> f(static_cast<std::size_t>(n)), d(static_cast<std::size_t>(n));
            std::vector<double> z(static_cast<std::size_t>(n) + 3);
            std::vector<int> v(static_cast<std::size_t>(n) + 2);
            for (int iu = 0; iu < u; ++iu) {
                const std::size_t start = static_cast<std::size_t>(iu) * strideU + static_cast<std::size_t>(iw) * strideW;
                bool isAllOutside = true;
                for (int p = 0; p < n; ++p) {
                    f[static_cast<std::size_t>(p)] = squared[start + static_cast<std::size_t>(p) * stride];
                    isAllOutside = isAllOutside && f[static_cast<std::size_t>(p)] == 0.0;
                }
                if (isAllOutside) continue;
                transformLine(n, grid.spacingMm[static_cast<glm::length_t>(axis)], f.data(), d.data(), v.data(), z.data());
                for (int p = 0; p < n; ++p) squared[start + static_cast<std::size_t>(p) * stride] = d[static_cast<std::size_t>(p)];
            }
        });
    }
    std::vector<float> distance(count);
    for (std::size_t n = 0; n < count; ++n) distance[n] = static_cast<float>(std::sqrt(squared[n]));
    return distance;
}

}  // namespace colon
