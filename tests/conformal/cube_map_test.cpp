#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <sys/resource.h>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "conformal/cube_map_baker.h"
#include "conformal/linear_map.h"

namespace conformal {
namespace {

const std::filesystem::path kTmp = CVC_TEST_TMP_DIR;

// GCC says it builds with a sanitizer by __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__, clang by
// __has_feature.
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define CUBE_MAP_TEST_CLANG_SANITIZED 1
#endif
#endif
#ifndef CUBE_MAP_TEST_CLANG_SANITIZED
#define CUBE_MAP_TEST_CLANG_SANITIZED 0
#endif

TEST(CubeMap, FaceRulesFollowVulkan) {
    // Face centres and the (s, t) = (0, 0) corners from the spec's table.
    EXPECT_EQ(directionFromCubeFace(0, 0.5, 0.5), glm::dvec3(1, 0, 0));
    EXPECT_EQ(directionFromCubeFace(3, 0.5, 0.5), glm::dvec3(0, -1, 0));
    const glm::dvec3 expected[6] = {{1, 1, 1}, {-1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {-1, 1, 1}, {1, 1, -1}};
    for (int face = 0; face < 6; ++face) {
        const glm::dvec3 corner = directionFromCubeFace(face, 0.0, 0.0);
        EXPECT_NEAR(glm::length(corner - glm::normalize(expected[face])), 0.0, 1e-15) << "face " << face;
    }
    for (int face = 0; face < 6; ++face) {
        for (double s = 0.05; s < 1.0; s += 0.1) {
            for (double t = 0.05; t < 1.0; t += 0.1) {
                const CubeFaceCoordinate c = cubeFaceFromDirection(directionFromCubeFace(face, s, t));
                EXPECT_EQ(c.face, face);
                EXPECT_NEAR(c.s, s, 1e-14);
                EXPECT_NEAR(c.t, t, 1e-14);
            }
        }
    }
}

/// A smooth map with a known value everywhere: a rotation of the sphere.
class RotationMap final : public DirectionMap {
public:
    glm::dvec3 sceneFromDisplay(const glm::dvec3& d) const override {
        return {std::cos(kAngle) * d.x - std::sin(kAngle) * d.y, std::sin(kAngle) * d.x + std::cos(kAngle) * d.y, d.z};
    }
    glm::dvec3 displayFromScene(const glm::dvec3& s) const override {
        return {std::cos(kAngle) * s.x + std::sin(kAngle) * s.y, -std::sin(kAngle) * s.x + std::cos(kAngle) * s.y, s.z};
    }

private:
    static constexpr double kAngle = 0.3;
};

TEST(CubeMap, BilinearSamplingMatchesTheMapBetweenTexels) {
    const RotationMap map;
    const CubeMap cube = bakeCubeMap(map, CaveBox{}, MapKind::Conformal, 64);
    double worst = 0.0;
    for (int face = 0; face < 6; ++face) {
        // Includes lookups within half a texel of a face's edge, where taps cross faces.
        for (double s = 0.002; s < 1.0; s += 0.0331) {
            for (double t = 0.004; t < 1.0; t += 0.0497) {
                const glm::dvec3 d = directionFromCubeFace(face, s, t);
                const glm::vec4 sampled = sampleCubeMapBilinear(cube, d);
                worst = std::max(worst, glm::length(glm::dvec3(sampled) - map.sceneFromDisplay(d)));
                EXPECT_NEAR(sampled.w, 1.0, 2e-3);  // a rotation has unit scale
            }
        }
    }
    // Bilinear interpolation of a smooth map: error about (texel size)^2 / 8.
    EXPECT_LT(worst, 3e-3);
}

TEST(CubeMap, FileRoundTripsAndBadFilesAreNamed) {
    const CubeMap cube = bakeCubeMap(LinearMap(immersiveCabinBox()), immersiveCabinBox(), MapKind::Linear, 8);
    const auto path = kTmp / "roundtrip.cvcm";
    saveCubeMap(cube, path);
    const CubeMap loaded = loadCubeMap(path);
    EXPECT_EQ(loaded.size, 8);
    EXPECT_EQ(loaded.kind, MapKind::Linear);
    EXPECT_EQ(loaded.box.size, immersiveCabinBox().size);
    EXPECT_EQ(loaded.rgba, cube.rgba);

    const auto bytes = std::filesystem::file_size(path);
    auto expectError = [](const std::filesystem::path& bad, const std::string& problem) {
        try {
            loadCubeMap(bad);
            ADD_FAILURE() << "no error for " << bad;
        } catch (const CubeMapFileError& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find(bad.string()), std::string::npos) << message;
            EXPECT_NE(message.find(problem), std::string::npos) << message;
        }
    };
    const auto truncated = kTmp / "truncated.cvcm";
    std::filesystem::copy_file(path, truncated, std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(truncated, bytes - 5);
    expectError(truncated, "truncated texel data");
    std::filesystem::resize_file(truncated, 20);
    expectError(truncated, "truncated header");

    const auto wrongMagic = kTmp / "magic.cvcm";
    std::filesystem::copy_file(path, wrongMagic, std::filesystem::copy_options::overwrite_existing);
    {
        std::fstream file(wrongMagic, std::ios::in | std::ios::out | std::ios::binary);
        file.write("NOTACUBE", 8);
    }
    expectError(wrongMagic, "wrong magic");

    const auto wrongSize = kTmp / "size.cvcm";
    std::filesystem::copy_file(path, wrongSize, std::filesystem::copy_options::overwrite_existing);
    {
        std::fstream file(wrongSize, std::ios::in | std::ios::out | std::ios::binary);
        file.seekp(12);
        const std::uint32_t huge = 100000;
        file.write(reinterpret_cast<const char*>(&huge), sizeof(huge));
    }
    expectError(wrongSize, "face size 100000");

    const auto trailing = kTmp / "trailing.cvcm";
    std::filesystem::copy_file(path, trailing, std::filesystem::copy_options::overwrite_existing);
    {
        std::ofstream file(trailing, std::ios::app | std::ios::binary);
        file << "x";
    }
    expectError(trailing, "unexpected bytes");
    expectError(kTmp / "missing.cvcm", "cannot open");
}

/// Patches `bytes` at `offset` of a copy of `source`, returning the copy's path.
std::filesystem::path patchedCopy(const std::filesystem::path& source, const std::string& name, std::streamoff offset,
                                  const void* bytes, std::size_t count) {
    const auto copy = kTmp / name;
    std::filesystem::copy_file(source, copy, std::filesystem::copy_options::overwrite_existing);
    std::fstream file(copy, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(offset);
    file.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(count));
    return copy;
}

TEST(CubeMap, HeaderPromisingMoreTexelsThanTheFileHoldsIsRefusedBeforeAllocating) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || CUBE_MAP_TEST_CLANG_SANITIZED
    GTEST_SKIP() << "an address-space limit cannot be set under a sanitizer's shadow memory";
#else
    // fuzz/corpus/cube_map/header_claims_size_16384_no_texels.cvcm: the header alone, claiming
    // faces of 16384^2 texels (25.8 GB). Under a 4 GiB address-space cap the loader must refuse
    // it as truncated; allocating the texels first would throw std::bad_alloc instead.
    const CubeMap cube = bakeCubeMap(LinearMap(immersiveCabinBox()), immersiveCabinBox(), MapKind::Linear, 2);
    const auto source = kTmp / "header_only_source.cvcm";
    saveCubeMap(cube, source);
    const std::uint32_t size = 16384;
    const std::uint64_t payload = 6ull * size * size * 16;
    const auto headerOnly = patchedCopy(source, "header_only.cvcm", 12, &size, sizeof(size));
    {
        std::fstream file(headerOnly, std::ios::in | std::ios::out | std::ios::binary);
        file.seekp(80);  // the payload byte count, which must match the size
        file.write(reinterpret_cast<const char*>(&payload), sizeof(payload));
    }
    std::filesystem::resize_file(headerOnly, 88);
    const auto loadUnderCap = [&] {
        const rlim_t cap = rlim_t{4} << 30;
        const rlimit limit{cap, cap};
        setrlimit(RLIMIT_AS, &limit);
        try {
            loadCubeMap(headerOnly);
        } catch (const CubeMapFileError& error) {
            const bool named =
                std::string(error.what()).find("truncated texel data (0 of 25769803776 bytes)") != std::string::npos;
            std::_Exit(named ? 0 : 2);
        } catch (...) {
            std::_Exit(3);  // std::bad_alloc: the texels were allocated before the size was checked
        }
        std::_Exit(4);
    };
    EXPECT_EXIT(loadUnderCap(), ::testing::ExitedWithCode(0), "");
#endif
}

TEST(CubeMap, NonFiniteTexelsAreRefused) {
    const CubeMap cube = bakeCubeMap(LinearMap(immersiveCabinBox()), immersiveCabinBox(), MapKind::Linear, 2);
    const auto source = kTmp / "finite.cvcm";
    saveCubeMap(cube, source);
    const float nan = std::nanf("");
    const auto path = patchedCopy(source, "nan_texel.cvcm", 88 + 5 * 4, &nan, sizeof(nan));
    try {
        loadCubeMap(path);
        ADD_FAILURE() << "no error for a NaN texel";
    } catch (const CubeMapFileError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
        EXPECT_NE(message.find("non-finite value (float 5 of 96)"), std::string::npos) << message;
    }
}

TEST(CubeMap, KindNamesRoundTripAndUnknownNamesListTheChoices) {
    for (MapKind kind : {MapKind::Conformal, MapKind::Linear, MapKind::None}) {
        EXPECT_EQ(mapKindFromName(mapKindName(kind)), kind);
    }
    EXPECT_EQ(mapKindName(MapKind::None), "none");
    try {
        mapKindFromName("bent");
        ADD_FAILURE() << "no error for an unknown map";
    } catch (const std::invalid_argument& error) {
        EXPECT_NE(std::string(error.what()).find("'bent' (conformal, linear, none)"), std::string::npos)
            << error.what();
    }
}

TEST(CubeMap, KindNoneIsNeitherBakedNorWrittenNorRead) {
    // "No bending" has no map: a bake of it is a caller's mistake, a file claiming it is malformed.
    BakeSettings settings;
    settings.size = 8;
    settings.kind = MapKind::None;
    const auto expectRefusal = [](const auto& attempt) {
        try {
            attempt();
            ADD_FAILURE() << "no error for map kind none";
        } catch (const std::invalid_argument& error) {
            EXPECT_NE(std::string(error.what()).find("map kind none has nothing to bake"), std::string::npos)
                << error.what();
        }
    };
    expectRefusal([&] { bakeCubeMap(settings); });
    expectRefusal([&] { bakeCubeMap(LinearMap(CaveBox{}), CaveBox{}, MapKind::None, 8); });
    const auto cacheDir = kTmp / "cache_none";
    std::filesystem::remove_all(cacheDir);
    setenv("CVC_CACHE_DIR", cacheDir.c_str(), 1);
    expectRefusal([&] { cachedCubeMap(settings); });
    unsetenv("CVC_CACHE_DIR");
    EXPECT_FALSE(std::filesystem::exists(cacheDir));

    CubeMap cube = bakeCubeMap(LinearMap(CaveBox{}), CaveBox{}, MapKind::Linear, 4);
    cube.kind = MapKind::None;
    EXPECT_THROW(saveCubeMap(cube, kTmp / "none_written.cvcm"), CubeMapFileError);
    EXPECT_FALSE(std::filesystem::exists(kTmp / "none_written.cvcm"));

    // A file whose header says kind 2 (None): the kind field follows magic, version and size.
    cube.kind = MapKind::Linear;
    const auto claimsNone = kTmp / "claims_none.cvcm";
    saveCubeMap(cube, claimsNone);
    {
        std::fstream file(claimsNone, std::ios::in | std::ios::out | std::ios::binary);
        file.seekp(16);
        const std::uint32_t none = static_cast<std::uint32_t>(MapKind::None);
        file.write(reinterpret_cast<const char*>(&none), sizeof(none));
    }
    try {
        loadCubeMap(claimsNone);
        ADD_FAILURE() << "no error for a file of map kind none";
    } catch (const CubeMapFileError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(claimsNone.string()), std::string::npos) << message;
        EXPECT_NE(message.find("map kind 2 is not a baked map"), std::string::npos) << message;
    }
}

TEST(CubeMap, SecondBakeLoadsFromTheCache) {
    const auto cacheDir = kTmp / "cache";
    std::filesystem::remove_all(cacheDir);
    setenv("CVC_CACHE_DIR", cacheDir.c_str(), 1);
    BakeSettings settings;
    settings.size = 16;
    settings.mesh.resolution = 16;
    BakeReport first;
    const CubeMap baked = cachedCubeMap(settings, &first);
    EXPECT_FALSE(first.wasLoadedFromCache);
    EXPECT_TRUE(std::filesystem::exists(first.cachePath));
    BakeReport second;
    const CubeMap loaded = cachedCubeMap(settings, &second);
    EXPECT_TRUE(second.wasLoadedFromCache);
    EXPECT_EQ(loaded.rgba, baked.rgba);
    EXPECT_EQ(loaded.inputHash, bakeInputHash(settings));
    // Other inputs, other hash: a different box must not hit the cube's entry.
    settings.box = immersiveCabinBox();
    EXPECT_NE(bakeInputHash(settings), loaded.inputHash);
    // A damaged entry is rebuilt, not trusted.
    std::filesystem::resize_file(first.cachePath, 100);
    settings.box = CaveBox{};
    BakeReport third;
    const CubeMap rebuilt = cachedCubeMap(settings, &third);
    EXPECT_FALSE(third.wasLoadedFromCache);
    EXPECT_EQ(rebuilt.rgba, baked.rgba);
    unsetenv("CVC_CACHE_DIR");
}

}  // namespace
}  // namespace conformal
