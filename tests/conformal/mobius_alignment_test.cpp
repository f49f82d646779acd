#include <gtest/gtest.h>

#include "conformal/mobius_alignment.h"

namespace conformal {
namespace {

using Complex = std::complex<double>;

TEST(MobiusAlignment, SendsThreeBoundaryPointsAndKeepsTheDisk) {
    const std::array<Complex, 3> from = {std::polar(1.0, 0.3), std::polar(1.0, 1.9), std::polar(1.0, 3.5)};
    const Mobius m = mobiusAligningCorners(from);
    EXPECT_NEAR(std::abs(m(from[0]) - Complex(1, 0)), 0.0, 1e-14);
    EXPECT_NEAR(std::abs(m(from[1]) - Complex(0, 1)), 0.0, 1e-14);
    EXPECT_NEAR(std::abs(m(from[2]) - Complex(-1, 0)), 0.0, 1e-14);
    for (double a = 0.0; a < 6.28; a += 0.1) EXPECT_NEAR(std::abs(m(std::polar(1.0, a))), 1.0, 1e-13);
    EXPECT_LT(std::abs(m(Complex(0.1, -0.2))), 1.0);
    const Mobius inverse = m.inverse();
    EXPECT_NEAR(std::abs(inverse(m(Complex(0.3, 0.4))) - Complex(0.3, 0.4)), 0.0, 1e-14);
    EXPECT_THROW(mobiusAligningCorners({from[0], from[0], from[2]}), std::invalid_argument);
}

}  // namespace
}  // namespace conformal
