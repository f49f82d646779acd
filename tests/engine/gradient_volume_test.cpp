// The gradient volume's half floats against an independent decoding: for every central
// difference of two int16 voxels, the stored half must be the one nearest d / 2 (ties to even).
// That the gradient volume's normals equal the volume's taps is tested in normals_test.cpp.
#include <cmath>
#include <cstdint>
#include <stdexcept>

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

}  // namespace
