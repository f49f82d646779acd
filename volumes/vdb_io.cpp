#include "volumes/vdb_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>

#include <openvdb/openvdb.h>

namespace volumes {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
static_assert(FloatLeaf::DIM == kBrickSize, "bricks are meant to coincide with OpenVDB leaves");

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw VolumeError(path + ": " + problem);
}

void initializeOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

int16_t huFromFloat(const std::string& path, float value, const openvdb::Coord& where) {
    const double rounded = std::nearbyint(static_cast<double>(value));
    if (!(rounded >= std::numeric_limits<int16_t>::min() && rounded <= std::numeric_limits<int16_t>::max())) {
        fail(path, "voxel (" + std::to_string(where.x()) + ", " + std::to_string(where.y()) + ", " +
                       std::to_string(where.z()) + ") holds " + std::to_string(value) +
                       ", expected a finite HU value within int16");
    }
    return static_cast<int16_t>(rounded);
}

/// Ranges of one brick's voxels that neighbouring bricks' aprons read. Per axis, slot 0 holds
/// only the layer at local coordinate 0, slot 1 all eight layers, slot 2 only layer 7; the
/// brick's own range is slot (1, 1, 1).
struct BrickFaces {
    int16_t lo[27];
    int16_t hi[27];
    void fill(int16_t value) {
        std::fill(std::begin(lo), std::end(lo), value);
        std::fill(std::begin(hi), std::end(hi), value);
    }
};

/// Brick min/max from the tree: a leaf's voxels, a tile's constant, else the background.
BrickMinMax bricksFromTree(const std::string& path, const openvdb::FloatGrid& grid, const openvdb::Coord& indexMin,
                           const std::array<int, 3>& dims) {
    BrickMinMax bricks;
    bricks.brickDims = brickDimsFor(dims);
    const std::size_t count = bricks.brickCount();
    std::vector<BrickFaces> faces(count);
    const int16_t background = huFromFloat(path, grid.background(), indexMin);
    for (BrickFaces& f : faces) f.fill(background);

    auto brickOf = [&](const openvdb::Coord& c) {
        return std::array<int, 3>{(c.x() - indexMin.x()) / kBrickSize, (c.y() - indexMin.y()) / kBrickSize,
                                  (c.z() - indexMin.z()) / kBrickSize};
    };
    // Tiles above the leaf level: constant over whole bricks.
    auto it = grid.tree().cbeginValueAll();
    it.setMaxDepth(grid.tree().treeDepth() - 2);  // tiles only; leaf voxels come below
    for (; it; ++it) {
        openvdb::CoordBBox box = it.getBoundingBox();
        box.intersect(openvdb::CoordBBox(indexMin, indexMin + openvdb::Coord(dims[0] - 1, dims[1] - 1, dims[2] - 1)));
        if (box.empty()) continue;
        const int16_t value = huFromFloat(path, *it, box.min());
        const auto first = brickOf(box.min()), last = brickOf(box.max());
        for (int bz = first[2]; bz <= last[2]; ++bz)
            for (int by = first[1]; by <= last[1]; ++by)
                for (int bx = first[0]; bx <= last[0]; ++bx) faces[bricks.brickIndex(bx, by, bz)].fill(value);
    }
    // Leaves: every voxel inside the volume updates the slots it belongs to.
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        const openvdb::Coord origin = leaf->origin() - indexMin;
        if (origin.x() < 0 || origin.y() < 0 || origin.z() < 0 || origin.x() >= dims[0] || origin.y() >= dims[1] ||
            origin.z() >= dims[2]) {
            continue;  // outside the volume
        }
        BrickFaces& f = faces[bricks.brickIndex(origin.x() / kBrickSize, origin.y() / kBrickSize, origin.z() / kBrickSize)];
        std::fill(std::begin(f.lo), std::end(f.lo), std::numeric_limits<int16_t>::max());
        std::fill(std::begin(f.hi), std::end(f.hi), std::numeric_limits<int16_t>::min());
        for (openvdb::Index n = 0; n < FloatLeaf::SIZE; ++n) {
            const openvdb::Coord local = FloatLeaf::offsetToLocalCoord(n);
            const openvdb::Coord at = origin + local;
            if (at.x() >= dims[0] || at.y() >= dims[1] || at.z() >= dims[2]) continue;
            const int16_t v = huFromFloat(path, leaf->getValue(n), leaf->origin() + local);
            // Slots per axis this voxel belongs to: always 1 ("all"), 0 on layer 0, 2 on layer 7.
            int slots[3][2];
            int slotCount[3];
            for (int axis = 0; axis < 3; ++axis) {
                slotCount[axis] = 0;
                slots[axis][slotCount[axis]++] = 1;
                if (local[axis] == 0) slots[axis][slotCount[axis]++] = 0;
                // A brick cut by the volume's end has its last layer at dims - 1.
                const int lastLayer = std::min(kBrickSize - 1, dims[static_cast<std::size_t>(axis)] - 1 - origin[axis]);
                if (local[axis] == lastLayer) slots[axis][slotCount[axis]++] = 2;
            }
            for (int a = 0; a < slotCount[0]; ++a)
                for (int b = 0; b < slotCount[1]; ++b)
                    for (int c = 0; c < slotCount[2]; ++c) {
                        const int s = slots[0][a] + 3 * (slots[1][b] + 3 * slots[2][c]);
                        f.lo[s] = std::min(f.lo[s], v);
                        f.hi[s] = std::max(f.hi[s], v);
                    }
        }
    }
    // Each brick: its own range and, from each of its 26 neighbours, the layers facing it.
    bricks.minHu.assign(count, 0);
    bricks.maxHu.assign(count, 0);
    const auto& bd = bricks.brickDims;
    for (int bz = 0; bz < bd[2]; ++bz)
        for (int by = 0; by < bd[1]; ++by)
            for (int bx = 0; bx < bd[0]; ++bx) {
                int16_t lo = std::numeric_limits<int16_t>::max(), hi = std::numeric_limits<int16_t>::min();
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const int nx = bx + dx, ny = by + dy, nz = bz + dz;
                            if (nx < 0 || ny < 0 || nz < 0 || nx >= bd[0] || ny >= bd[1] || nz >= bd[2]) continue;
                            // A neighbour below (d = -1) lends its last layer (slot 2), one above its first.
                            const int s = (1 - dx) + 3 * ((1 - dy) + 3 * (1 - dz));
                            const BrickFaces& f = faces[bricks.brickIndex(nx, ny, nz)];
                            lo = std::min(lo, f.lo[s]);
                            hi = std::max(hi, f.hi[s]);
                        }
                bricks.minHu[bricks.brickIndex(bx, by, bz)] = lo;
                bricks.maxHu[bricks.brickIndex(bx, by, bz)] = hi;
            }
    return bricks;
}

}  // namespace

Volume readVdb(const std::string& path, BrickMinMax* bricks, const std::string& gridName) {
    initializeOpenVdb();
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) fail(path, "no such file");
    openvdb::GridBase::Ptr base;
    try {
        openvdb::io::File file(path);
        file.open(false);  // no delayed loading: the file is read once, here
        const std::string wanted = gridName.empty() ? kVdbGridName : gridName;
        if (file.hasGrid(wanted)) {
            base = file.readGrid(wanted);
        } else if (!gridName.empty()) {
            fail(path, "holds no grid named '" + gridName + "'");
        } else {
            for (auto name = file.beginName(); name != file.endName(); ++name) {
                openvdb::GridBase::Ptr candidate = file.readGrid(name.gridName());
                if (candidate->isType<openvdb::FloatGrid>()) {
                    base = candidate;
                    break;
                }
            }
        }
        file.close();
    } catch (const openvdb::Exception& e) {
        fail(path, std::string("OpenVDB cannot read it: ") + e.what());
    }
    if (!base) fail(path, "holds no float grid (expected a float grid of HU values)");
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) fail(path, "grid '" + base->getName() + "' is of type " + base->type() + ", expected a float grid of HU values");

    // Index box: the writer's record, else what is active.
    openvdb::CoordBBox box;
    const auto dimsMeta = grid->getMetadata<openvdb::Vec3IMetadata>("cvc_dims");
    if (dimsMeta) {
        const openvdb::Vec3i d = dimsMeta->value();
        box = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(d.x() - 1, d.y() - 1, d.z() - 1));
    } else {
        box = grid->evalActiveVoxelBoundingBox();
        if (box.empty()) fail(path, "grid '" + grid->getName() + "' has no active voxels (an empty volume)");
    }
    Volume volume;
    volume.dims = {box.dim().x(), box.dim().y(), box.dim().z()};

    // Geometry: the rows of OpenVDB's (row-vector) affine matrix are the index axes in world space.
    const openvdb::math::MapBase::ConstPtr map = grid->transform().baseMap();
    if (!map->isLinear()) fail(path, "grid transform is " + map->type() + ", expected a linear (affine) map");
    const openvdb::Mat4d m = map->getAffineMap()->getMat4();
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 row(m(axis, 0), m(axis, 1), m(axis, 2));
        const double length = glm::length(row);
        volume.spacingMm[axis] = length;
        volume.directionLps[axis] = length > 0.0 ? row / length : row;
    }
    const openvdb::Vec3d originWorld = grid->indexToWorld(box.min());
    volume.originLps = {originWorld.x(), originWorld.y(), originWorld.z()};
    validateGeometry(volume, path);

    // Voxels: background everywhere, then tiles, then leaves.
    volume.hu.assign(volume.voxelCount(), huFromFloat(path, grid->background(), box.min()));
    auto it = grid->tree().cbeginValueAll();
    it.setMaxDepth(grid->tree().treeDepth() - 2);  // tiles only
    for (; it; ++it) {
        openvdb::CoordBBox tile = it.getBoundingBox();
        tile.intersect(box);
        if (tile.empty()) continue;
        const int16_t value = huFromFloat(path, *it, tile.min());
        for (int z = tile.min().z(); z <= tile.max().z(); ++z)
            for (int y = tile.min().y(); y <= tile.max().y(); ++y)
                for (int x = tile.min().x(); x <= tile.max().x(); ++x)
                    volume.hu[volume.linearIndex(x - box.min().x(), y - box.min().y(), z - box.min().z())] = value;
    }
    for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
        for (openvdb::Index n = 0; n < FloatLeaf::SIZE; ++n) {
            const openvdb::Coord at = leaf->origin() + FloatLeaf::offsetToLocalCoord(n);
            if (!box.isInside(at)) continue;
            volume.hu[volume.linearIndex(at.x() - box.min().x(), at.y() - box.min().y(), at.z() - box.min().z())] =
                huFromFloat(path, leaf->getValue(n), at);
        }
    }
    validateVolume(volume, path);

    if (bricks != nullptr) {
        const openvdb::Coord& lo = box.min();
        const bool isLeafAligned = lo.x() % kBrickSize == 0 && lo.y() % kBrickSize == 0 && lo.z() % kBrickSize == 0;
        // Leaves coincide with bricks only when the volume starts on a leaf boundary.
        *bricks = isLeafAligned ? bricksFromTree(path, *grid, lo, volume.dims) : buildBrickMinMax(volume);
    }
    return volume;
}

void writeVdb(const Volume& volume, const std::string& path, bool overwrite) {
    validateVolume(volume, path);
    if (!overwrite && std::filesystem::exists(path)) fail(path, "exists already (pass --force to replace it)");
    initializeOpenVdb();

    auto grid = openvdb::FloatGrid::create(kVdbBackgroundHu);
    grid->setName(kVdbGridName);
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    grid->insertMeta("cvc_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(volume.dims[0], volume.dims[1], volume.dims[2])));
    grid->insertMeta("units", openvdb::StringMetadata("HU"));

    openvdb::Mat4d m = openvdb::Mat4d::identity();
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 row = volume.directionLps[axis] * volume.spacingMm[axis];
        for (int c = 0; c < 3; ++c) m(axis, c) = row[c];
        m(3, axis) = volume.originLps[axis];
    }
    grid->setTransform(openvdb::math::Transform::createLinearTransform(m));

    // One leaf per brick that holds anything but air: built directly, not voxel by voxel.
    const auto background = static_cast<int16_t>(kVdbBackgroundHu);
    const std::array<int, 3> bd = brickDimsFor(volume.dims);
    for (int bz = 0; bz < bd[2]; ++bz)
        for (int by = 0; by < bd[1]; ++by)
            for (int bx = 0; bx < bd[0]; ++bx) {
                const openvdb::Coord origin(bx * kBrickSize, by * kBrickSize, bz * kBrickSize);
                std::unique_ptr<FloatLeaf> leaf;
                for (openvdb::Index n = 0; n < FloatLeaf::SIZE; ++n) {
                    const openvdb::Coord at = origin + FloatLeaf::offsetToLocalCoord(n);
                    if (at.x() >= volume.dims[0] || at.y() >= volume.dims[1] || at.z() >= volume.dims[2]) continue;
                    const int16_t v = volume.at(at.x(), at.y(), at.z());
                    if (v == background) continue;
                    if (!leaf) leaf = std::make_unique<FloatLeaf>(origin, kVdbBackgroundHu, false);
                    leaf->setValueOn(n, static_cast<float>(v));
                }
                if (leaf) grid->tree().addLeaf(leaf.release());
            }

    try {
        openvdb::io::File file(path);
        file.write({grid});
        file.close();
    } catch (const openvdb::Exception& e) {
        fail(path, std::string("OpenVDB cannot write it: ") + e.what());
    }
}

}  // namespace volumes
