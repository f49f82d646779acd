/// .vdb files not written by us: an index box that does not start at the origin or on a leaf
/// boundary, a different background, and constant tiles above the leaf level.
#include <openvdb/openvdb.h>

#include <gtest/gtest.h>

#include "tests/volumes/test_support.h"
#include "volumes/brick_minmax.h"
#include "volumes/vdb_io.h"

namespace volumes {
namespace {

std::string writeForeignGrid(const std::string& name, const openvdb::Coord& offset, float background) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(background);
    grid->setName("density");
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    // A 16^3 tile-sized block of bone (filled as tiles where it covers whole nodes) and a few
    // scattered voxels, all shifted by `offset`.
    grid->tree().fill(openvdb::CoordBBox(offset, offset + openvdb::Coord(15)), 700.0f, true);
    auto accessor = grid->getAccessor();
    for (int n = 0; n < 40; ++n) {
        accessor.setValue(offset + openvdb::Coord((n * 7) % 29, (n * 5) % 23, (n * 3) % 71),
                          static_cast<float>(n * 10 - 200));
    }
    const std::string path = testing::scratchFolder(name) + "/foreign.vdb";
    openvdb::io::File file(path);
    file.write({grid});
    file.close();
    return path;
}

void expectBricksMatchDense(const std::string& path) {
    BrickMinMax fromFile;
    const Volume volume = readVdb(path, &fromFile);
    const BrickMinMax dense = buildBrickMinMax(volume);
    EXPECT_EQ(fromFile.minHu, dense.minHu);
    EXPECT_EQ(fromFile.maxHu, dense.maxHu);
}

TEST(VdbForeign, UnalignedIndexBoxAndOtherBackground) {
    const openvdb::Coord offset(3, -5, -70);
    const std::string path = writeForeignGrid("vdb_unaligned", offset, -1024.0f);
    const Volume v = readVdb(path);  // no "hu" grid: the first float grid is read
    // The active box spans the block and the scattered voxels: 29 x 23 x 70 from the offset.
    EXPECT_EQ(v.dims, (std::array<int, 3>{29, 23, 70}));
    EXPECT_NEAR(v.spacingMm.x, 0.5, 1e-12);
    EXPECT_NEAR(v.originLps.z, -70 * 0.5, 1e-9);
    EXPECT_EQ(v.at(0, 0, 0), -200);  // scattered voxel n = 0 overwrote the block there
    EXPECT_EQ(v.at(1, 1, 1), 700);   // inside the filled block
    EXPECT_EQ(v.at(15, 15, 15), 700);
    EXPECT_EQ(v.at(20, 20, 60), -1024);  // background elsewhere
    EXPECT_EQ(v.at(7, 5, 3), -190);      // scattered voxel n = 1
    expectBricksMatchDense(path);
}

TEST(VdbForeign, AlignedTilesGiveLeafBricks) {
    // Aligned on leaves and spanning several 64-layer slabs: tiles and leaves feed the bricks.
    const std::string path = writeForeignGrid("vdb_aligned", openvdb::Coord(0, 0, 0), -1000.0f);
    const Volume v = readVdb(path);
    EXPECT_EQ(v.dims[2], 70);
    expectBricksMatchDense(path);
}

}  // namespace
}  // namespace volumes
