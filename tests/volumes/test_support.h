/// @brief Paths and small file-writing helpers shared by the volumes tests.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "volumes/volume.h"

namespace volumes::testing {

/// A file of the shared real-CT data (../shared/data), or skip-worthy empty path.
inline std::string sharedData(const std::string& relative) {
    return (std::filesystem::path(CVC_SHARED_DATA_DIR) / relative).string();
}

/// A fresh, empty scratch folder for one test, under the build tree.
inline std::string scratchFolder(const std::string& name) {
    const std::filesystem::path folder = std::filesystem::path(CVC_TEST_TMP_DIR) / "volumes" / name;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder.string();
}

inline void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline std::string bytesOf(const std::vector<int16_t>& values) {
    return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(int16_t)};
}

/// `bytes` compressed as a gzip stream (`isGzip`) or a zlib stream.
inline std::string deflateBytes(const std::string& bytes, bool isGzip) {
    z_stream stream{};
    deflateInit2(&stream, Z_BEST_SPEED, Z_DEFLATED, isGzip ? 15 + 16 : 15, 8, Z_DEFAULT_STRATEGY);
    std::string out(deflateBound(&stream, static_cast<uLong>(bytes.size())) + 64, '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = static_cast<uInt>(out.size());
    deflate(&stream, Z_FINISH);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
}

/// A small volume with a known, non-symmetric pattern and a non-trivial geometry.
inline Volume patternVolume(std::array<int, 3> dims = {13, 11, 7}) {
    Volume v;
    v.dims = dims;
    v.spacingMm = {0.7, 0.8, 1.25};
    v.originLps = {-12.5, 30.25, -100.0};
    // A rotation about z by 30 degrees: columns are the grid axes in LPS.
    const double c = std::cos(0.5235987755982988), s = std::sin(0.5235987755982988);
    v.directionLps = glm::dmat3(glm::dvec3(c, s, 0), glm::dvec3(-s, c, 0), glm::dvec3(0, 0, 1));
    v.hu.resize(v.voxelCount());
    for (std::size_t n = 0; n < v.hu.size(); ++n) v.hu[n] = static_cast<int16_t>((n * 37) % 4000) - 1024;
    return v;
}

/// Expects two volumes to have the same grid (to 1e-6 mm) and bit-identical voxels.
inline void expectSameVolume(const Volume& a, const Volume& b, double geometryTolerance = 1e-6) {
    ASSERT_EQ(a.dims, b.dims);
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(a.spacingMm[i], b.spacingMm[i], geometryTolerance) << "spacing axis " << i;
        EXPECT_NEAR(a.originLps[i], b.originLps[i], geometryTolerance) << "origin axis " << i;
        for (int j = 0; j < 3; ++j) {
            EXPECT_NEAR(a.directionLps[i][j], b.directionLps[i][j], geometryTolerance) << "direction " << i << "," << j;
        }
    }
    ASSERT_EQ(a.hu.size(), b.hu.size());
    std::size_t differing = 0, first = 0;
    for (std::size_t n = 0; n < a.hu.size(); ++n) {
        if (a.hu[n] != b.hu[n] && differing++ == 0) first = n;
    }
    EXPECT_EQ(differing, 0u) << "first difference at voxel " << first << ": " << a.hu[first] << " vs " << b.hu[first];
}

}  // namespace volumes::testing
