#include "colon/wall_surface.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include "colon/colon_error.h"
#include "colon/distance_transform.h"
#include "colon/grid.h"
#include "colon/volume_sampling.h"

namespace colon {
namespace {

/// The lumen's voxels grown by `margin` voxels, as a box within the volume.
VoxelBox lumenBox(const volumes::Volume& volume, const std::vector<uint8_t>& isLumen, int margin) {
    const Grid grid{volume.dims, volume.spacingMm};
    VoxelBox box;
    for (std::size_t n = 0; n < isLumen.size(); ++n) {
        if (isLumen[n] == 0) continue;
        const auto v = grid.voxelOf(n);
        box.include(v[0], v[1], v[2]);
    }
    return box.isEmpty() ? box : box.grown(margin, volume.dims);
}

}  // namespace

WallSurface colonWallSurface(const volumes::Volume& volume, const std::vector<uint8_t>& isLumen,
                             const WallSurfaceSettings& settings) {
    if (isLumen.size() != volume.voxelCount()) {
        throw ColonError("wall surface: the lumen mask has " + std::to_string(isLumen.size()) +
                         " voxels, the volume " + std::to_string(volume.voxelCount()));
    }
    if (!std::isfinite(settings.isoHu) || !(settings.maxDistanceFromLumenVoxels > 0.0)) {
        throw ColonError("wall surface: the iso value must be finite and the distance from the lumen positive");
    }
    // The mesher sees the lumen and a band of wall around it (a few voxels, enough for the
    // trilinear iso crossing and its neighbours); everything else is background tissue, so
    // the band's outer rim never crosses the iso value unless other air lies there, and that
    // air's polygons are dropped below by their distance from the lumen.
    constexpr int kBandVoxels = 3;
    const VoxelBox box = lumenBox(volume, isLumen, kBandVoxels + 1);
    if (box.isEmpty()) throw ColonError("wall surface: the lumen mask is empty");

    const Grid crop{{box.hi[0] - box.lo[0] + 1, box.hi[1] - box.lo[1] + 1, box.hi[2] - box.lo[2] + 1},
                    volume.spacingMm};
    // The distance transform counts what lies beyond its grid as the class it measures to (here
    // the lumen): a margin of non-lumen voxels around the crop keeps that phantom lumen farther
    // from every voxel of the crop than the band reaches.
    constexpr int kPad = kBandVoxels + 2;
    const Grid padded{{crop.dims[0] + 2 * kPad, crop.dims[1] + 2 * kPad, crop.dims[2] + 2 * kPad}, volume.spacingMm};
    std::vector<uint8_t> outsideLumen(padded.voxelCount(), 1);
    for (int k = 0; k < crop.dims[2]; ++k) {
        for (int j = 0; j < crop.dims[1]; ++j) {
            for (int i = 0; i < crop.dims[0]; ++i) {
                if (isLumen[volume.linearIndex(i + box.lo[0], j + box.lo[1], k + box.lo[2])] != 0) {
                    outsideLumen[padded.index(i + kPad, j + kPad, k + kPad)] = 0;
                }
            }
        }
    }
    // For voxels outside the lumen: millimetres to the nearest lumen voxel (0 inside it).
    const std::vector<float> paddedToLumenMm = distanceToOutsideMm(padded, outsideLumen);
    const auto toLumenMmAt = [&](int i, int j, int k) { return paddedToLumenMm[padded.index(i + kPad, j + kPad, k + kPad)]; };
    const double largestSpacing = std::max({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});
    const double bandMm = kBandVoxels * largestSpacing;
    const double keepMm = settings.maxDistanceFromLumenVoxels * largestSpacing;

    openvdb::initialize();
    const float tissueHu = static_cast<float>(settings.isoHu + 1000.0);
    openvdb::FloatGrid::Ptr hu = openvdb::FloatGrid::create(tissueHu);
    {
        auto accessor = hu->getAccessor();
        for (int k = 0; k < crop.dims[2]; ++k) {
            for (int j = 0; j < crop.dims[1]; ++j) {
                for (int i = 0; i < crop.dims[0]; ++i) {
                    if (toLumenMmAt(i, j, k) > bandMm) continue;
                    const int vi = i + box.lo[0], vj = j + box.lo[1], vk = k + box.lo[2];
                    accessor.setValue(openvdb::Coord(vi, vj, vk), static_cast<float>(volume.at(vi, vj, vk)));
                }
            }
        }
    }
    // Index (i, j, k) lands on volume millimetres (i, j, k) * spacing, the renderer's frame.
    openvdb::math::Mat4d scale = openvdb::math::Mat4d::identity();
    scale.setToScale(openvdb::Vec3d(volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z));
    hu->setTransform(openvdb::math::Transform::createLinearTransform(scale));

    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*hu, points, quads, settings.isoHu);

    const auto nearLumen = [&](const glm::dvec3& pointMm) {
        // Any voxel of the cell holding the point that is close enough to the lumen.
        std::array<int, 3> base{};
        for (int a = 0; a < 3; ++a) {
            base[static_cast<std::size_t>(a)] =
                static_cast<int>(std::floor(pointMm[a] / volume.spacingMm[a])) - box.lo[static_cast<std::size_t>(a)];
        }
        for (int corner = 0; corner < 8; ++corner) {
            const int i = base[0] + (corner & 1), j = base[1] + ((corner >> 1) & 1), k = base[2] + ((corner >> 2) & 1);
            if (crop.contains(i, j, k) && toLumenMmAt(i, j, k) <= keepMm) return true;
        }
        return false;
    };

    WallSurface surface;
    surface.vertices.reserve(points.size());
    for (const auto& p : points) surface.vertices.emplace_back(p.x(), p.y(), p.z());
    const double probeMm = 0.5 * std::min({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});
    for (const auto& q : quads) {
        std::array<uint32_t, 4> corners{q[0], q[1], q[2], q[3]};
        const glm::dvec3& a = surface.vertices[corners[0]];
        const glm::dvec3& b = surface.vertices[corners[1]];
        const glm::dvec3& c = surface.vertices[corners[2]];
        const glm::dvec3& d = surface.vertices[corners[3]];
        const glm::dvec3 centre = 0.25 * (a + b + c + d);
        if (!nearLumen(centre)) continue;
        // Two triangles' areas: the quads of a dual mesher are not always planar.
        const double area = 0.5 * (glm::length(glm::cross(b - a, c - a)) + glm::length(glm::cross(c - a, d - a)));
        const glm::dvec3 across = glm::cross(c - a, d - b);
        const double acrossLength = glm::length(across);
        if (!(area > 0.0) || !(acrossLength > 0.0)) continue;  // a degenerate quad covers nothing
        glm::dvec3 normal = across / acrossLength;
        // Point it into the lumen: air (lower HU) lies on the side the normal points to.
        if (trilinearHu(volume, centre + probeMm * normal) > trilinearHu(volume, centre - probeMm * normal)) {
            normal = -normal;
            std::swap(corners[1], corners[3]);
        }
        surface.quads.push_back(corners);
        surface.areaMm2.push_back(area);
        surface.centreMm.push_back(centre);
        surface.normal.push_back(normal);
        surface.totalAreaMm2 += area;
    }
    if (surface.quads.empty()) {
        throw ColonError("wall surface: the iso-surface at " + std::to_string(settings.isoHu) +
                         " HU does not bound the lumen anywhere");
    }
    return surface;
}

}  // namespace colon
