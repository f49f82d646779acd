/// @brief Point location in a planar triangle mesh covering the unit disk: a uniform bin grid
/// over the disk's bounding square, each bin listing the triangles that overlap it.
#pragma once

#include <array>
#include <complex>
#include <vector>

#include <glm/vec3.hpp>

namespace conformal {

/// Where a point of the plane fell.
struct DiskLocation {
    int triangle = -1;
    glm::dvec3 barycentric{0.0};  ///< may be slightly negative when the point is just outside
    bool isInside = false;        ///< false: the nearest boundary triangle, extrapolated
};

class DiskLocator {
public:
    DiskLocator() = default;
    /// `points` (#V) and `triangles` (#F by 3) of a mesh inside the square [-1.01, 1.01]^2.
    DiskLocator(const std::vector<std::complex<double>>& points,
                const std::vector<std::array<int, 3>>& triangles);

    /// The triangle holding `z`. Points outside the mesh (between its boundary polygon and the
    /// circle) get the triangle whose barycentric coordinates are least negative among those
    /// of the nearby bins, with the coordinates kept for linear extrapolation.
    DiskLocation locate(std::complex<double> z) const;

private:
    int binIndex(double x, double y) const;

    const std::vector<std::complex<double>>* mPoints = nullptr;
    const std::vector<std::array<int, 3>>* mTriangles = nullptr;
    int mBinsPerSide = 0;
    double mLow = -1.01;
    double mBinSize = 0.0;
    std::vector<int> mBinOffsets;    ///< compressed rows: triangles of bin b are
    std::vector<int> mBinTriangles;  ///< mBinTriangles[mBinOffsets[b] .. mBinOffsets[b + 1])
};

}  // namespace conformal
