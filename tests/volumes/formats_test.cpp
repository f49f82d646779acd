/// Each format's features on small volumes written by hand here (independent of our writers),
/// and bit-exact round trips through our NRRD and VDB writers.
#include <bit>
#include <cmath>
#include <cstring>
#include <sstream>

#include <gtest/gtest.h>

#include "tests/volumes/test_support.h"
#include "volumes/brick_minmax.h"
#include "volumes/load_volume.h"
#include "volumes/metaimage_io.h"
#include "volumes/nifti_reader.h"
#include "volumes/nrrd_io.h"
#include "volumes/raw_reader.h"
#include "volumes/vdb_io.h"

namespace volumes {
namespace {

using testing::bytesOf;
using testing::deflateBytes;
using testing::expectSameVolume;
using testing::patternVolume;
using testing::scratchFolder;
using testing::writeBytes;

std::string vectorText(const glm::dvec3& v) {
    std::ostringstream out;
    out.precision(17);
    out << '(' << v.x << ',' << v.y << ',' << v.z << ')';
    return out.str();
}

/// A NRRD header for `v` with the given type/encoding lines and optional extra lines.
std::string nrrdHeader(const Volume& v, const std::string& type, const std::string& encoding,
                       const std::string& extra = "") {
    std::ostringstream h;
    h.precision(17);
    h << "NRRD0004\ntype: " << type << "\ndimension: 3\nspace: left-posterior-superior\nsizes: " << v.dims[0] << ' '
      << v.dims[1] << ' ' << v.dims[2] << "\nspace directions:";
    for (int a = 0; a < 3; ++a) h << ' ' << vectorText(v.directionLps[a] * v.spacingMm[a]);
    h << "\nendian: little\nencoding: " << encoding << "\nspace origin: " << vectorText(v.originLps) << '\n'
      << extra << '\n';
    return h.str();
}

std::string bigEndianBytes(const std::vector<int16_t>& values) {
    std::string out(values.size() * 2, '\0');
    for (std::size_t n = 0; n < values.size(); ++n) {
        const auto u = static_cast<uint16_t>(values[n]);
        out[2 * n] = static_cast<char>(u >> 8);
        out[2 * n + 1] = static_cast<char>(u & 0xff);
    }
    return out;
}

std::string floatBytes(const std::vector<int16_t>& values, double scale = 1.0, double offset = 0.0) {
    std::string out(values.size() * 4, '\0');
    for (std::size_t n = 0; n < values.size(); ++n) {
        const auto f = static_cast<float>((values[n] - offset) / scale);
        std::memcpy(out.data() + 4 * n, &f, 4);
    }
    return out;
}

TEST(NrrdIo, RoundTripIsBitExact) {
    const Volume v = patternVolume();
    const std::string path = scratchFolder("nrrd_round_trip") + "/v.nrrd";
    writeNrrd(v, path);
    expectSameVolume(readNrrd(path), v, 1e-12);
}

TEST(NrrdIo, ReadsAttachedGzip) {
    const Volume v = patternVolume();
    const std::string path = scratchFolder("nrrd_gzip") + "/v.nrrd";
    writeBytes(path, nrrdHeader(v, "short", "gzip") + deflateBytes(bytesOf(v.hu), true));
    expectSameVolume(readNrrd(path), v);
}

TEST(NrrdIo, ReadsDetachedRawBigEndianWithSkips) {
    const Volume v = patternVolume();
    const std::string folder = scratchFolder("nrrd_detached");
    std::string header = nrrdHeader(v, "int16", "raw", "data file: v.data\nline skip: 2\nbyte skip: 3");
    header.replace(header.find("endian: little"), 14, "endian: big");
    writeBytes(folder + "/v.nhdr", header);
    writeBytes(folder + "/v.data", "first line\nsecond line\nabc" + bigEndianBytes(v.hu));
    expectSameVolume(loadVolume(folder + "/v.nhdr"), v);
}

TEST(NrrdIo, ReadsDetachedGzipFloat) {
    const Volume v = patternVolume();
    const std::string folder = scratchFolder("nrrd_detached_gzip");
    writeBytes(folder + "/v.nhdr", nrrdHeader(v, "float", "gzip", "data file: v.raw.gz"));
    writeBytes(folder + "/v.raw.gz", deflateBytes(floatBytes(v.hu), true));
    expectSameVolume(readNrrd(folder + "/v.nhdr"), v);
}

TEST(NrrdIo, ConvertsRasSpaceToLps) {
    Volume v = patternVolume();
    const std::string path = scratchFolder("nrrd_ras") + "/v.nrrd";
    // The same grid written in RAS: x and y of every vector negated.
    Volume ras = v;
    for (int a = 0; a < 3; ++a)
        ras.directionLps[a] = glm::dvec3(-v.directionLps[a].x, -v.directionLps[a].y, v.directionLps[a].z);
    ras.originLps = {-v.originLps.x, -v.originLps.y, v.originLps.z};
    std::string header = nrrdHeader(ras, "short", "raw");
    header.replace(header.find("left-posterior-superior"), 23, "right-anterior-superior");
    writeBytes(path, header + bytesOf(v.hu));
    expectSameVolume(readNrrd(path), v, 1e-9);
}

/// A MetaImage header for `v`.
std::string metaHeader(const Volume& v, const std::string& type, const std::string& dataFile, bool isCompressed,
                       std::size_t compressedBytes = 0) {
    std::ostringstream h;
    h.precision(17);
    h << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
      << "CompressedData = " << (isCompressed ? "True" : "False") << '\n';
    if (isCompressed) h << "CompressedDataSize = " << compressedBytes << '\n';
    h << "TransformMatrix =";
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) h << ' ' << v.directionLps[a][c];
    h << "\nOffset = " << v.originLps.x << ' ' << v.originLps.y << ' ' << v.originLps.z
      << "\nCenterOfRotation = 0 0 0\nAnatomicalOrientation = RAI\nElementSpacing = " << v.spacingMm.x << ' '
      << v.spacingMm.y << ' ' << v.spacingMm.z << "\nDimSize = " << v.dims[0] << ' ' << v.dims[1] << ' ' << v.dims[2]
      << "\nElementType = " << type << "\nElementDataFile = " << dataFile << '\n';
    return h.str();
}

TEST(MetaImageIo, ReadsAttachedRaw) {
    const Volume v = patternVolume();
    const std::string path = scratchFolder("mha_raw") + "/v.mha";
    writeBytes(path, metaHeader(v, "MET_SHORT", "LOCAL", false) + bytesOf(v.hu));
    expectSameVolume(loadVolume(path), v, 1e-9);
}

TEST(MetaImageIo, ReadsAttachedZlib) {
    const Volume v = patternVolume();
    const std::string path = scratchFolder("mha_zlib") + "/v.mha";
    const std::string packed = deflateBytes(bytesOf(v.hu), false);
    writeBytes(path, metaHeader(v, "MET_SHORT", "LOCAL", true, packed.size()) + packed);
    expectSameVolume(readMetaImage(path), v, 1e-9);
}

TEST(MetaImageIo, ReadsDetachedFloatData) {
    const Volume v = patternVolume();
    const std::string folder = scratchFolder("mhd_float");
    writeBytes(folder + "/v.mhd", metaHeader(v, "MET_FLOAT", "v.raw", false));
    writeBytes(folder + "/v.raw", floatBytes(v.hu));
    expectSameVolume(loadVolume(folder + "/v.mhd"), v, 1e-9);
}

TEST(MetaImageIo, RealChestEqualsItsNrrd) {
    const Volume chest = readNrrd(testing::sharedData("ct/ibsi_ct_phantom_chest.nrrd"));
    const std::string path = scratchFolder("mha_chest") + "/chest.mha";
    const std::string packed = deflateBytes(bytesOf(chest.hu), false);
    writeBytes(path, metaHeader(chest, "MET_SHORT", "LOCAL", true, packed.size()) + packed);
    expectSameVolume(loadVolume(path), chest, 1e-6);
}

TEST(RawReader, ParsesDescriptions) {
    const RawOptions o = parseRawSpec("512x256x451:uint16:0.7x0.8x1.25:big:skip=128:slope=1:intercept=-1024");
    EXPECT_EQ(o.dims, (std::array<int, 3>{512, 256, 451}));
    EXPECT_EQ(o.format.type, ScalarType::UInt16);
    EXPECT_TRUE(o.format.isBigEndian);
    EXPECT_EQ(o.headerBytes, 128u);
    EXPECT_DOUBLE_EQ(o.spacingMm.z, 1.25);
    EXPECT_DOUBLE_EQ(o.format.intercept, -1024.0);
    for (const char* bad : {"", "512x512:int16:1x1x1", "512x512x0:int16:1x1x1", "8x8x8:complex:1x1x1",
                            "8x8x8:int16:1x1", "8x8x8:int16:0x1x1", "8x8x8:int16:nanx1x1", "8x8x8:int16:1x1x1:skip=-1",
                            "8x8x8:int16:1x1x1:what", "99999x8x8:int16:1x1x1"}) {
        EXPECT_THROW(parseRawSpec(bad), VolumeError) << bad;
    }
}

TEST(RawReader, ReadsUnsignedBigEndianWithIntercept) {
    // The chest as a scanner would store it: unsigned, big-endian, HU = stored - 1024.
    const Volume chest = readNrrd(testing::sharedData("ct/ibsi_ct_phantom_chest.nrrd"));
    std::vector<int16_t> stored(chest.hu.size());
    for (std::size_t n = 0; n < stored.size(); ++n) stored[n] = static_cast<int16_t>(chest.hu[n] + 1024);
    const std::string path = scratchFolder("raw_chest") + "/chest.raw";
    writeBytes(path, std::string(64, 'h') + bigEndianBytes(stored));
    LoadOptions options;
    options.raw = parseRawSpec("204x201x60:uint16:0.977x0.977x3:big:skip=64:intercept=-1024");
    const Volume raw = loadVolume(path, options);
    EXPECT_EQ(raw.hu, chest.hu);
    EXPECT_EQ(raw.dims, chest.dims);
}

TEST(VdbIo, RoundTripIsBitExactAndBricksComeFromLeaves) {
    Volume v = patternVolume({37, 21, 18});
    // Air regions, so that the tree has holes and tiles-free background bricks.
    for (int k = 0; k < v.dims[2]; ++k)
        for (int j = 0; j < v.dims[1]; ++j)
            for (int i = 0; i < v.dims[0]; ++i)
                if (i < 16 || k >= 9) v.hu[v.linearIndex(i, j, k)] = -1000;
    const std::string path = scratchFolder("vdb_round_trip") + "/v.vdb";
    writeVdb(v, path);
    BrickMinMax fromLeaves;
    const Volume back = readVdb(path, &fromLeaves);
    expectSameVolume(back, v, 1e-9);
    const BrickMinMax dense = buildBrickMinMax(v);
    EXPECT_EQ(fromLeaves.brickDims, dense.brickDims);
    EXPECT_EQ(fromLeaves.minHu, dense.minHu);
    EXPECT_EQ(fromLeaves.maxHu, dense.maxHu);
}

TEST(VdbIo, RealAbdomenRoundTrip) {
    const Volume abdomen = readNrrd(testing::sharedData("ct/ts_example_abdomen_3mm.nrrd"));
    const std::string path = scratchFolder("vdb_abdomen") + "/abdomen.vdb";
    writeVdb(abdomen, path);
    const LoadedVolume loaded = loadVolumeWithBricks(path);
    EXPECT_EQ(loaded.format, VolumeFormat::Vdb);
    expectSameVolume(loaded.volume, abdomen, 1e-9);
    const BrickMinMax dense = buildBrickMinMax(abdomen);
    EXPECT_EQ(loaded.bricks.minHu, dense.minHu);
    EXPECT_EQ(loaded.bricks.maxHu, dense.maxHu);
}

TEST(VdbIo, RefusesToOverwrite) {
    const std::string path = scratchFolder("vdb_overwrite") + "/v.vdb";
    writeVdb(patternVolume(), path);
    EXPECT_THROW(writeVdb(patternVolume(), path), VolumeError);
    EXPECT_NO_THROW(writeVdb(patternVolume(), path, true));
}

TEST(LoadVolume, DispatchesByExtensionAndFolder) {
    const std::string folder = scratchFolder("dispatch");
    EXPECT_EQ(volumeFormatOf(testing::sharedData("dicom/ibsi_sts008_ct")), VolumeFormat::DicomSeries);
    for (const auto& [name, format] :
         std::vector<std::pair<std::string, VolumeFormat>>{{"a.nrrd", VolumeFormat::Nrrd},
                                                           {"a.NHDR", VolumeFormat::Nrrd},
                                                           {"a.nii", VolumeFormat::Nifti},
                                                           {"a.nii.gz", VolumeFormat::Nifti},
                                                           {"a.mha", VolumeFormat::MetaImage},
                                                           {"a.mhd", VolumeFormat::MetaImage},
                                                           {"a.vdb", VolumeFormat::Vdb}}) {
        writeBytes(folder + "/" + name, "x");
        EXPECT_EQ(volumeFormatOf(folder + "/" + name), format) << name;
    }
    writeBytes(folder + "/a.png", "x");
    EXPECT_THROW(volumeFormatOf(folder + "/a.png"), VolumeError);
    writeBytes(folder + "/a.raw", "x");
    EXPECT_THROW(volumeFormatOf(folder + "/a.raw"), VolumeError);  // raw needs its description
    EXPECT_THROW(volumeFormatOf(folder + "/missing.nrrd"), VolumeError);
}

}  // namespace
}  // namespace volumes
