/// @brief Möbius transformations of the unit disk, fixed by where three boundary points go.
#pragma once

#include <array>
#include <complex>

namespace conformal {

/// z -> (a z + b) / (c z + d).
struct Mobius {
    std::complex<double> a{1.0, 0.0};
    std::complex<double> b{0.0, 0.0};
    std::complex<double> c{0.0, 0.0};
    std::complex<double> d{1.0, 0.0};

    std::complex<double> operator()(std::complex<double> z) const { return (a * z + b) / (c * z + d); }
    Mobius inverse() const;
};

/// The Möbius transformation sending from[k] to to[k] (k = 0, 1, 2), through cross ratios.
/// When both triples lie on the unit circle in the same cyclic order it is an automorphism of
/// the unit disk. Throws std::invalid_argument when points coincide.
Mobius mobiusFromThreePoints(const std::array<std::complex<double>, 3>& from,
                             const std::array<std::complex<double>, 3>& to);

/// The alignment the paper uses: ceiling corners 0, 1, 2 go to 1, i, -1.
Mobius mobiusAligningCorners(const std::array<std::complex<double>, 3>& cornerImages);

}  // namespace conformal
