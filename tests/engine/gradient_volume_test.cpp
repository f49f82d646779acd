// The gradient volume's half floats against an independent decoding: for every central
// difference of two int16 voxels, the stored half must be the one nearest d / 2 (ties to even).
// The B-spline's values at the voxels (computed separably, slice by slice) against the direct
// 27-term sum of the definition. That the gradient volume's normals equal the volume's taps is
// tested in normals_test.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "engine/render/gradient_volume.h"

namespace {

/// The value of IEEE half-float bits (normal numbers and zeros; the encoder makes no others).
double decodeHalf(uint16_t bits) {
    const double sign = (bits & 0x8000u) != 0 ? -1.0 : 1.0;
    const int exponent = (bits >> 10) & 0x1F;
    const int fraction = bits & 0x3FF;
    if (exponent == 0 && fraction == 0) return sign * 0.0;
    EXPECT_GT(exponent, 0) << "subnormal half " << bits;
    EXPECT_LT(exponent, 31) << "infinite or NaN half " << bits;
    return sign * std::ldexp(1.0 + fraction / 1024.0, exponent - 15);
}

TEST(GradientVolume, HalfFloatsAreTheNearestToEveryCentralDifference) {
    int inexact = 0;
    for (int d = -65535; d <= 65535; ++d) {
        const uint16_t bits = engine::halfFloatBitsOfHalf(d);
        const double exact = 0.5 * d;
        const double stored = decodeHalf(bits);
        // Half floats of magnitude in [2^e, 2^(e+1)) lie 2^(e-10) apart: nearest means within half
        // of that, of the magnitude of the exact value's binade.
        const double magnitude = std::abs(exact);
        const int binade = magnitude < 1.0 ? -1 : static_cast<int>(std::floor(std::log2(magnitude)));
        const double spacing = std::ldexp(1.0, binade - 10);
        const double error = std::abs(stored - exact);
        ASSERT_LE(error, 0.5 * spacing) << "d = " << d << ": " << stored << " for " << exact;
        if (error == 0.5 * spacing) {
            ASSERT_EQ(bits & 1u, 0u) << "d = " << d << ": a tie must round to the even half";
        }
        if (error > 0.0) ++inexact;
        ASSERT_EQ(std::signbit(stored), d < 0) << "d = " << d;
    }
    // Below 2048 (|d| < 4096) every value is exact; above, the halves carry 11 significant bits.
    EXPECT_GT(inexact, 0);
    EXPECT_EQ(engine::halfFloatBitsOfHalf(1), 0x3800u);       // 0.5
    EXPECT_EQ(engine::halfFloatBitsOfHalf(-2), 0xBC00u);      // -1
    EXPECT_EQ(engine::halfFloatBitsOfHalf(65535), 0x7800u);   // 32767.5 rounds to 32768
    EXPECT_THROW((void)engine::halfFloatBitsOfHalf(65536), std::invalid_argument);
}

TEST(GradientVolume, HalfFloatsOfFloatsAreTheNearest) {
    std::mt19937 random(5);
    std::normal_distribution<float> gradient(0.0f, 400.0f);
    std::vector<float> values = {0.0f, -0.0f, 1.0f, -2.0f, 0.5f, 1e-6f, -3e-7f, 6e-8f, 65504.0f, -65504.0f, 2049.0f,
                                 2051.0f, 1.0f + 1.0f / 2048.0f, 1.0f + 3.0f / 2048.0f};  // two ties
    for (int i = 0; i < 200000; ++i) values.push_back(gradient(random));
    for (int i = 0; i < 2000; ++i) values.push_back(std::ldexp(gradient(random), -20));  // subnormal halves
    for (const float value : values) {
        const uint16_t bits = engine::halfFloatBits(value);
        const int exponent = (bits >> 10) & 0x1F;
        const int fraction = bits & 0x3FF;
        const double stored = ((bits & 0x8000u) != 0 ? -1.0 : 1.0) *
                              (exponent == 0 ? std::ldexp(fraction / 1024.0, -14)
                                             : std::ldexp(1.0 + fraction / 1024.0, exponent - 15));
        const double magnitude = std::abs(static_cast<double>(value));
        const int binade = magnitude < std::ldexp(1.0, -14) ? -14 : static_cast<int>(std::floor(std::log2(magnitude)));
        const double spacing = std::ldexp(1.0, binade - 10);
        const double error = std::abs(stored - value);
        ASSERT_LE(error, 0.5 * spacing) << value << " stored as " << stored;
        if (error == 0.5 * spacing) {
            ASSERT_EQ(bits & 1u, 0u) << value << ": a tie must round to the even half";
        }
        if (value != 0.0f) {
            ASSERT_EQ(std::signbit(stored), std::signbit(value)) << value;
        }
    }
    EXPECT_EQ(engine::halfFloatBits(1.0f + 1.0f / 2048.0f), 0x3C00u);  // the tie rounds down to even
    EXPECT_EQ(engine::halfFloatBits(1.0f + 3.0f / 2048.0f), 0x3C02u);  // and up to even
    EXPECT_EQ(engine::halfFloatBits(65520.0f), 0x7C00u);               // past the largest half: infinity
    EXPECT_EQ(engine::halfFloatBits(-0.0f), 0x8000u);
}

TEST(GradientVolume, BSplineAtVoxelsIsTheSmoothedCentralDifferences) {
    // A small volume of random HU, odd sizes and a side of one voxel, so every face clamps.
    for (const std::array<int, 3> dims : {std::array<int, 3>{7, 5, 4}, std::array<int, 3>{3, 1, 6}}) {
        volumes::Volume volume;
        volume.dims = dims;
        volume.spacingMm = {1.0, 1.0, 1.0};
        volume.hu.resize(volume.voxelCount());
        std::mt19937 random(17);
        std::uniform_int_distribution<int> hu(-1024, 3071);
        for (auto& v : volume.hu) v = static_cast<int16_t>(hu(random));
        const auto clampTo = [](int i, int n) { return std::clamp(i, 0, n - 1); };
        const auto at = [&](int x, int y, int z) {
            return static_cast<double>(volume.hu[volume.linearIndex(clampTo(x, dims[0]), clampTo(y, dims[1]),
                                                                    clampTo(z, dims[2]))]);
        };
        // The central difference along `axis` at a voxel whose indices are clamped first, as the
        // sampler clamps each tap of the B-spline's blend.
        const auto central = [&](int x, int y, int z, int axis) {
            x = clampTo(x, dims[0]);
            y = clampTo(y, dims[1]);
            z = clampTo(z, dims[2]);
            const int dx = axis == 0, dy = axis == 1, dz = axis == 2;
            return 0.5 * (at(x + dx, y + dy, z + dz) - at(x - dx, y - dy, z - dz));
        };
        const double weight[3] = {1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0};
        std::vector<float> slice(3 * static_cast<std::size_t>(dims[0]) * dims[1]);
        for (int z = 0; z < dims[2]; ++z) {
            engine::bsplineGradientsOfSlice(volume, z, slice);
            for (int y = 0; y < dims[1]; ++y) {
                for (int x = 0; x < dims[0]; ++x) {
                    for (int axis = 0; axis < 3; ++axis) {
                        double expected = 0.0;
                        for (int c = -1; c <= 1; ++c) {
                            for (int b = -1; b <= 1; ++b) {
                                for (int a = -1; a <= 1; ++a) {
                                    expected += weight[a + 1] * weight[b + 1] * weight[c + 1] *
                                                central(x + a, y + b, z + c, axis);
                                }
                            }
                        }
                        const float got = slice[3 * (static_cast<std::size_t>(y) * dims[0] + x) + axis];
                        ASSERT_NEAR(got, expected, 1e-3 + 1e-5 * std::abs(expected))
                            << "voxel " << x << " " << y << " " << z << " axis " << axis;
                    }
                }
            }
        }
    }
    volumes::Volume volume;
    volume.dims = {2, 2, 2};
    volume.hu.assign(8, 0);
    std::vector<float> wrong(5);
    EXPECT_THROW(engine::bsplineGradientsOfSlice(volume, 0, wrong), std::invalid_argument);
    std::vector<float> right(12);
    EXPECT_THROW(engine::bsplineGradientsOfSlice(volume, 2, right), std::invalid_argument);
}

}  // namespace
