#include "volumes/vdb_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>

#include <openvdb/openvdb.h>

namespace volumes {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
static_assert(FloatLeaf::DIM == kBrickSize, "bricks are meant to coincide with OpenVDB leaves");

/// The grid is read in slabs of this many z layers (a multiple of the leaf size), so a dense
/// CT never sits in memory twice as floats: peak memory is the int16 volume plus one slab.
constexpr int kSlabLayers = 64;

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
/// only the layer at local coordinate 0, slot 1 all eight layers, slot 2 only the last layer;
/// the brick's own range is slot (1, 1, 1).
struct BrickFaces {
    int16_t lo[27];
    int16_t hi[27];
    void fill(int16_t value) {
        std::fill(std::begin(lo), std::end(lo), value);
        std::fill(std::begin(hi), std::end(hi), value);
    }
};

/// Copies a grid into a dense volume, slab by slab, and (when the volume starts on a leaf
/// boundary, so leaves coincide with bricks) collects brick ranges from leaves and tiles.
class VdbVolumeBuilder {
public:
    VdbVolumeBuilder(const std::string& path, Volume& volume, const openvdb::Coord& indexMin, float background,
                     bool wantsBricks)
        : mPath(path), mVolume(volume), mIndexMin(indexMin) {
        const int16_t backgroundHu = huFromFloat(path, background, indexMin);
        mVolume.hu.assign(mVolume.voxelCount(), backgroundHu);
        mIsLeafAligned =
            indexMin.x() % kBrickSize == 0 && indexMin.y() % kBrickSize == 0 && indexMin.z() % kBrickSize == 0;
        mHasLeafBricks = wantsBricks && mIsLeafAligned;
        if (mHasLeafBricks) {
            mBrickDims = brickDimsFor(volume.dims);
            mFaces.resize(static_cast<std::size_t>(mBrickDims[0]) * mBrickDims[1] * mBrickDims[2]);
            for (BrickFaces& f : mFaces) f.fill(backgroundHu);
        }
    }

    /// Takes the voxels of `grid` whose volume z index lies in [kFirst, kEnd).
    void addSlab(const openvdb::FloatGrid& grid, int kFirst, int kEnd) {
        const openvdb::Coord lo = mIndexMin + openvdb::Coord(0, 0, kFirst);
        const openvdb::Coord hi = mIndexMin + openvdb::Coord(mVolume.dims[0] - 1, mVolume.dims[1] - 1, kEnd - 1);
        const openvdb::CoordBBox slab(lo, hi);
        // Tiles above the leaf level: constant over whole 8^3 blocks.
        auto tile = grid.tree().cbeginValueAll();
        tile.setMaxDepth(grid.tree().treeDepth() - 2);
        for (; tile; ++tile) {
            openvdb::CoordBBox box = tile.getBoundingBox();
            box.intersect(slab);
            if (box.empty()) continue;
            const int16_t value = huFromFloat(mPath, *tile, box.min());
            for (int z = box.min().z(); z <= box.max().z(); ++z)
                for (int y = box.min().y(); y <= box.max().y(); ++y)
                    for (int x = box.min().x(); x <= box.max().x(); ++x)
                        mVolume.hu[indexOf(openvdb::Coord(x, y, z))] = value;
            if (mHasLeafBricks) {
                const openvdb::Coord first = brickOf(box.min()), last = brickOf(box.max());
                for (int bz = first.z(); bz <= last.z(); ++bz)
                    for (int by = first.y(); by <= last.y(); ++by)
                        for (int bx = first.x(); bx <= last.x(); ++bx) mFaces[brickIndex(bx, by, bz)].fill(value);
            }
        }
        // Leaves: whole ones when aligned; otherwise voxel by voxel within the slab.
        for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
            if (!leaf->getNodeBoundingBox().hasOverlap(slab)) continue;
            if (mIsLeafAligned) {
                if (slab.isInside(leaf->origin())) addAlignedLeaf(*leaf);
                continue;  // otherwise a clipped copy of a neighbouring slab's leaf
            }
            const float* values = leaf->buffer().data();
            for (openvdb::Index n = 0; n < FloatLeaf::SIZE; ++n) {
                const openvdb::Coord at = leaf->origin() + FloatLeaf::offsetToLocalCoord(n);
                if (!slab.isInside(at)) continue;
                mVolume.hu[indexOf(at)] = huFromFloat(mPath, values[n], at);
            }
        }
    }

    /// The brick ranges from leaves, or nothing when the grid is not leaf-aligned.
    bool takeBricks(BrickMinMax& bricks) const {
        if (!mHasLeafBricks) return false;
        bricks.brickDims = mBrickDims;
        const std::size_t count = mFaces.size();
        bricks.minHu.assign(count, 0);
        bricks.maxHu.assign(count, 0);
        const auto& bd = mBrickDims;
        // Each brick: its own range and, from each of its 26 neighbours, the layers facing it.
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
                                const BrickFaces& f = mFaces[brickIndex(nx, ny, nz)];
                                lo = std::min(lo, f.lo[s]);
                                hi = std::max(hi, f.hi[s]);
                            }
                    bricks.minHu[brickIndex(bx, by, bz)] = lo;
                    bricks.maxHu[brickIndex(bx, by, bz)] = hi;
                }
        return true;
    }

private:
    std::size_t indexOf(const openvdb::Coord& at) const {
        return mVolume.linearIndex(at.x() - mIndexMin.x(), at.y() - mIndexMin.y(), at.z() - mIndexMin.z());
    }
    openvdb::Coord brickOf(const openvdb::Coord& at) const {
        const openvdb::Coord local = at - mIndexMin;
        return {local.x() / kBrickSize, local.y() / kBrickSize, local.z() / kBrickSize};
    }
    std::size_t brickIndex(int bx, int by, int bz) const {
        return static_cast<std::size_t>(bx) +
               static_cast<std::size_t>(mBrickDims[0]) *
                   (static_cast<std::size_t>(by) + static_cast<std::size_t>(mBrickDims[1]) * bz);
    }

    /// Copies a leaf that coincides with a brick into the volume and, when bricks are wanted,
    /// records the ranges of its slots, reducing z, then y, then x (first layer, all layers,
    /// last layer per axis).
    void addAlignedLeaf(const FloatLeaf& leaf) {
        constexpr int kN = kBrickSize;
        const openvdb::Coord origin = leaf.origin() - mIndexMin;
        // Voxels of the leaf inside the volume: a brick cut by the volume's end is shorter.
        int count[3];
        for (int axis = 0; axis < 3; ++axis) {
            count[axis] = std::min(kN, mVolume.dims[static_cast<std::size_t>(axis)] - origin[axis]);
        }
        // Leaf offsets are z fastest: n = (x << 6) | (y << 3) | z.
        const float* values = leaf.buffer().data();
        int16_t hu[kN][kN][kN];
        for (int x = 0; x < count[0]; ++x)
            for (int y = 0; y < count[1]; ++y) {
                for (int z = 0; z < count[2]; ++z) {
                    const openvdb::Coord at = leaf.origin() + openvdb::Coord(x, y, z);
                    hu[x][y][z] = huFromFloat(mPath, values[(x << 6) | (y << 3) | z], at);
                    mVolume.hu[indexOf(at)] = hu[x][y][z];
                }
            }
        if (!mHasLeafBricks) return;
        // Slot s of an axis with `n` layers: 0 the first layer, 1 all of them, 2 the last.
        auto reduce = [](const int16_t* lo, const int16_t* hi, int n, int stride, int s, int16_t& outLo,
                         int16_t& outHi) {
            const int first = s == 2 ? n - 1 : 0, last = s == 0 ? 0 : n - 1;
            outLo = std::numeric_limits<int16_t>::max();
            outHi = std::numeric_limits<int16_t>::min();
            for (int i = first; i <= last; ++i) {
                outLo = std::min(outLo, lo[i * stride]);
                outHi = std::max(outHi, hi[i * stride]);
            }
        };
        int16_t zLo[kN][kN][3], zHi[kN][kN][3];
        for (int x = 0; x < count[0]; ++x)
            for (int y = 0; y < count[1]; ++y)
                for (int s = 0; s < 3; ++s) reduce(hu[x][y], hu[x][y], count[2], 1, s, zLo[x][y][s], zHi[x][y][s]);
        int16_t yLo[kN][3][3], yHi[kN][3][3];
        for (int x = 0; x < count[0]; ++x)
            for (int sz = 0; sz < 3; ++sz)
                for (int sy = 0; sy < 3; ++sy)
                    reduce(&zLo[x][0][sz], &zHi[x][0][sz], count[1], 3, sy, yLo[x][sy][sz], yHi[x][sy][sz]);
        const openvdb::Coord brick = brickOf(leaf.origin());
        BrickFaces& f = mFaces[brickIndex(brick.x(), brick.y(), brick.z())];
        for (int sz = 0; sz < 3; ++sz)
            for (int sy = 0; sy < 3; ++sy)
                for (int sx = 0; sx < 3; ++sx) {
                    const int slot = sx + 3 * (sy + 3 * sz);
                    reduce(&yLo[0][sy][sz], &yHi[0][sy][sz], count[0], 9, sx, f.lo[slot], f.hi[slot]);
                }
    }

    const std::string& mPath;
    Volume& mVolume;
    openvdb::Coord mIndexMin;
    bool mIsLeafAligned = false;  ///< leaves coincide with bricks
    bool mHasLeafBricks = false;  ///< brick ranges are collected from leaves and tiles
    std::array<int, 3> mBrickDims{0, 0, 0};
    std::vector<BrickFaces> mFaces;
};

/// World-space box holding the index box (voxel centres +- 0.4 voxel), for clipped reads.
openvdb::BBoxd worldBoxOf(const openvdb::math::Transform& transform, const openvdb::CoordBBox& box) {
    openvdb::BBoxd world;
    for (int corner = 0; corner < 8; ++corner) {
        const openvdb::Vec3d index((corner & 1) ? box.max().x() + 0.4 : box.min().x() - 0.4,
                                   (corner & 2) ? box.max().y() + 0.4 : box.min().y() - 0.4,
                                   (corner & 4) ? box.max().z() + 0.4 : box.min().z() - 0.4);
        world.expand(transform.indexToWorld(index));
    }
    return world;
}

}  // namespace

Volume readVdb(const std::string& path, BrickMinMax* bricks, const std::string& gridName) {
    initializeOpenVdb();
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) fail(path, "no such file");
    try {
        openvdb::io::File file(path);
        file.open(false);  // no delayed loading: each slab is read once, here

        // Pick the grid from metadata alone: "hu", else the first float grid.
        openvdb::GridBase::Ptr meta;
        const std::string wanted = gridName.empty() ? kVdbGridName : gridName;
        if (file.hasGrid(wanted)) {
            meta = file.readGridMetadata(wanted);
        } else if (!gridName.empty()) {
            fail(path, "holds no grid named '" + gridName + "'");
        } else {
            for (auto name = file.beginName(); name != file.endName(); ++name) {
                openvdb::GridBase::Ptr candidate = file.readGridMetadata(name.gridName());
                if (candidate->isType<openvdb::FloatGrid>()) {
                    meta = candidate;
                    break;
                }
            }
        }
        if (!meta) fail(path, "holds no float grid (expected a float grid of HU values)");
        if (!meta->isType<openvdb::FloatGrid>()) {
            fail(path,
                 "grid '" + meta->getName() + "' is of type " + meta->type() + ", expected a float grid of HU values");
        }
        const std::string name = meta->getName();

        // Index box: the writer's record, else the active-voxel box OpenVDB stores with each grid.
        openvdb::CoordBBox box;
        openvdb::FloatGrid::Ptr whole;
        if (const auto dims = meta->getMetadata<openvdb::Vec3IMetadata>("cvc_dims")) {
            const openvdb::Vec3i d = dims->value();
            box = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(d.x() - 1, d.y() - 1, d.z() - 1));
        } else if (const auto lo = meta->getMetadata<openvdb::Vec3IMetadata>("file_bbox_min"),
                   hi = meta->getMetadata<openvdb::Vec3IMetadata>("file_bbox_max");
                   lo && hi) {
            box = openvdb::CoordBBox(openvdb::Coord(lo->value()), openvdb::Coord(hi->value()));
        } else {
            whole = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(name));
            box = whole->evalActiveVoxelBoundingBox();
        }
        if (box.empty()) fail(path, "grid '" + name + "' has no active voxels (an empty volume)");
        Volume volume;
        volume.dims = {box.dim().x(), box.dim().y(), box.dim().z()};

        // Geometry: the rows of OpenVDB's (row-vector) affine matrix are the index axes in world space.
        const openvdb::math::MapBase::ConstPtr map = meta->transform().baseMap();
        if (!map->isLinear()) fail(path, "grid transform is " + map->type() + ", expected a linear (affine) map");
        const openvdb::Mat4d m = map->getAffineMap()->getMat4();
        for (int axis = 0; axis < 3; ++axis) {
            const glm::dvec3 row(m(axis, 0), m(axis, 1), m(axis, 2));
            const double length = glm::length(row);
            volume.spacingMm[axis] = length;
            volume.directionLps[axis] = length > 0.0 ? row / length : row;
        }
        const openvdb::Vec3d originWorld = meta->transform().indexToWorld(box.min());
        volume.originLps = {originWorld.x(), originWorld.y(), originWorld.z()};
        validateGeometry(volume, path);

        // Voxels, one slab of z layers at a time (or the whole grid if it had to be read already).
        std::unique_ptr<VdbVolumeBuilder> builder;
        for (int kFirst = 0; kFirst < volume.dims[2]; kFirst += kSlabLayers) {
            const int kEnd = whole ? volume.dims[2] : std::min(kFirst + kSlabLayers, volume.dims[2]);
            openvdb::FloatGrid::Ptr grid = whole;
            if (!grid) {
                const openvdb::CoordBBox slab(box.min() + openvdb::Coord(0, 0, kFirst),
                                              openvdb::Coord(box.max().x(), box.max().y(), box.min().z() + kEnd - 1));
                grid =
                    openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(name, worldBoxOf(meta->transform(), slab)));
                if (!grid) fail(path, "grid '" + name + "' could not be read as a float grid");
            }
            if (!builder)
                builder =
                    std::make_unique<VdbVolumeBuilder>(path, volume, box.min(), grid->background(), bricks != nullptr);
            builder->addSlab(*grid, kFirst, kEnd);
            if (whole) break;
        }
        file.close();
        validateVolume(volume, path);
        if (bricks != nullptr && !builder->takeBricks(*bricks)) *bricks = buildBrickMinMax(volume);
        return volume;
    } catch (const openvdb::Exception& e) {
        fail(path, std::string("OpenVDB cannot read it: ") + e.what());
    }
}

void writeVdb(const Volume& volume, const std::string& path, bool overwrite) {
    validateVolume(volume, path);
    if (!overwrite && std::filesystem::exists(path)) fail(path, "exists already (pass --force to replace it)");
    initializeOpenVdb();

    auto grid = openvdb::FloatGrid::create(kVdbBackgroundHu);
    grid->setName(kVdbGridName);
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    grid->insertMeta("cvc_dims",
                     openvdb::Vec3IMetadata(openvdb::Vec3i(volume.dims[0], volume.dims[1], volume.dims[2])));
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
