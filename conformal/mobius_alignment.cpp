/// @brief Möbius transformations from three point pairs, as 2 x 2 complex matrices.
#include "conformal/mobius_alignment.h"

#include <stdexcept>

namespace conformal {

namespace {

using Complex = std::complex<double>;

Mobius compose(const Mobius& outer, const Mobius& inner) {
    return {outer.a * inner.a + outer.b * inner.c, outer.a * inner.b + outer.b * inner.d,
            outer.c * inner.a + outer.d * inner.c, outer.c * inner.b + outer.d * inner.d};
}

/// Sends p0 -> 0, p1 -> 1, p2 -> infinity.
Mobius crossRatioMap(const std::array<Complex, 3>& p) {
    if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2]) {
        throw std::invalid_argument("Möbius transformation: the three points must be distinct");
    }
    return {p[1] - p[2], -p[0] * (p[1] - p[2]), p[1] - p[0], -p[2] * (p[1] - p[0])};
}

}  // namespace

Mobius Mobius::inverse() const { return {d, -b, -c, a}; }

Mobius mobiusFromThreePoints(const std::array<Complex, 3>& from, const std::array<Complex, 3>& to) {
    const Mobius m = compose(crossRatioMap(to).inverse(), crossRatioMap(from));
    // Normalise so that the coefficients stay of order one.
    const Complex det = m.a * m.d - m.b * m.c;
    const Complex root = std::sqrt(det);
    return {m.a / root, m.b / root, m.c / root, m.d / root};
}

Mobius mobiusAligningCorners(const std::array<Complex, 3>& cornerImages) {
    return mobiusFromThreePoints(cornerImages, {Complex(1.0, 0.0), Complex(0.0, 1.0), Complex(-1.0, 0.0)});
}

}  // namespace conformal
