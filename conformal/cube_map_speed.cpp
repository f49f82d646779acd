#include "conformal/cube_map_speed.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "conformal/cube_map.h"
#include "conformal/parallel_for.h"

namespace conformal {

namespace {

/// Angle between two unit vectors from their chord c, rounded up: 2 asin(c / 2) <= c (1 + c^2 / 20)
/// for c <= 1 (the series is c + c^3 / 24 + 3 c^5 / 640 + ...), without the asin where it is.
double angleFromChordAtLeast(double chord) {
    return chord <= 1.0 ? chord * (1.0 + chord * chord / 20.0) : 2.0 * std::asin(std::min(1.0, 0.5 * chord));
}

/// Per texel of a size^2-per-face cube map, the largest angle ratio to its neighbours to the
/// right, below and on the two diagonals beyond them (each pair once: the other half of the
/// neighbours are those texels' own pairs). `widestSceneAngle` gets the largest scene angle.
std::vector<double> texelSpeeds(int n, std::span<const float> rgba, double& widestSceneAngle) {
    auto sceneAt = [&](int face, int i, int j) {
        const std::size_t at = ((static_cast<std::size_t>(face) * n + j) * n + i) * 4;
        const glm::dvec3 v(rgba[at], rgba[at + 1], rgba[at + 2]);
        const double length = glm::length(v);
        return length > 0.0 ? v / length : glm::dvec3(0.0);
    };
    auto displayAt = [n](int face, int i, int j) {
        return glm::normalize(directionFromCubeFace(face, (i + 0.5) / n, (j + 0.5) / n));
    };
    std::vector<double> speeds(6u * static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
    std::vector<double> widestPerRow(6u * static_cast<std::size_t>(n), 0.0);
    const int neighbours[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    parallelFor(6 * n, [&](int row) {
        const int face = row / n, j = row % n;
        double widest = 0.0;
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 display = displayAt(face, i, j);
            const glm::dvec3 scene = sceneAt(face, i, j);
            double speed = 0.0;
            for (const auto& offset : neighbours) {
                int otherFace = face, oi = i + offset[0], oj = j + offset[1];
                // Beyond an edge, the adjacent face's texel that seamless filtering reads there,
                // at the place in this face's plane where the filter puts it.
                const glm::dvec3 otherDisplay = displayAt(face, oi, oj);
                if (oi < 0 || oj < 0 || oi >= n || oj >= n) {
                    const CubeFaceCoordinate other = cubeFaceFromDirection(otherDisplay);
                    otherFace = other.face;
                    oi = std::clamp(static_cast<int>(std::floor(other.s * n)), 0, n - 1);
                    oj = std::clamp(static_cast<int>(std::floor(other.t * n)), 0, n - 1);
                }
                // The display chord is at most the angle and the scene angle is rounded up, so the
                // ratio errs on the large side.
                const double displayChord = glm::length(otherDisplay - display);
                const double sceneAngle = angleFromChordAtLeast(glm::length(sceneAt(otherFace, oi, oj) - scene));
                widest = std::max(widest, sceneAngle);
                if (displayChord > 0.0) speed = std::max(speed, sceneAngle / displayChord);
            }
            speeds[static_cast<std::size_t>(row) * n + i] = speed;
        }
        widestPerRow[static_cast<std::size_t>(row)] = widest;
    });
    for (double widest : widestPerRow) widestSceneAngle = std::max(widestSceneAngle, widest);
    return speeds;
}

}  // namespace

SpeedBoundMap speedBoundMap(int size, std::span<const float> rgba, int coarseSize) {
    if (size < 2 || coarseSize < 2 ||
        rgba.size() != 6u * static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 4u) {
        throw std::invalid_argument("cube map of size " + std::to_string(size) + " holds " + std::to_string(rgba.size()) +
                                    " floats, expected 6 * size^2 * 4");
    }
    const int n = size;
    const int g = std::min(coarseSize, n);
    double widestSceneAngle = 0.0;
    const std::vector<double> speeds = texelSpeeds(n, rgba, widestSceneAngle);
    // Between texels the shader interpolates unit vectors bilinearly and normalises: the
    // interpolant is no shorter than the cosine of half the widest angle it spans (a cell's
    // diagonal spans at most sqrt(2) neighbour angles). Oblique to the grid, the rate of a
    // bilinear interpolant is at most sqrt(2) times its largest rate along an edge.
    const double shortest = std::cos(std::min(0.5 * std::sqrt(2.0) * widestSceneAngle, 1.5));
    const double factor = std::sqrt(2.0) / std::max(shortest, 0.07);

    // Coarse cells: the largest fine speed in each and its centre direction; the widest angle a
    // cell spans (twice the largest centre-to-corner angle).
    const std::size_t cells = 6u * static_cast<std::size_t>(g) * static_cast<std::size_t>(g);
    std::vector<double> cellSpeed(cells, 0.0);
    std::vector<glm::dvec3> cellCentre(cells);
    double widestCell = 0.0;
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const std::size_t cell = (static_cast<std::size_t>(face) * g + j * g / n) * g + i * g / n;
                cellSpeed[cell] = std::max(cellSpeed[cell], speeds[(static_cast<std::size_t>(face) * n + j) * n + i]);
            }
        }
        for (int cj = 0; cj < g; ++cj) {
            for (int ci = 0; ci < g; ++ci) {
                const std::size_t cell = (static_cast<std::size_t>(face) * g + cj) * g + ci;
                cellCentre[cell] = glm::normalize(directionFromCubeFace(face, (ci + 0.5) / g, (cj + 0.5) / g));
                for (int corner = 0; corner < 4; ++corner) {
                    const glm::dvec3 c = glm::normalize(
                        directionFromCubeFace(face, (ci + (corner & 1)) / double(g), (cj + (corner >> 1)) / double(g)));
                    widestCell = std::max(widestCell, 2.0 * std::acos(std::clamp(glm::dot(c, cellCentre[cell]), -1.0, 1.0)));
                }
            }
        }
    }
    // A bilinear lookup at d mixes cells whose centres lie within a cell's width of d: each
    // cell's bound covers its own directions and a reach plus two cell widths beyond them.
    const double reach = kSpeedBoundReachRadians + 2.0 * widestCell;
    SpeedBoundMap bounds;
    bounds.size = g;
    bounds.rgba.resize(cells * 4);
    // Cells whose centres are closer than two cell radii and the reach may share a direction
    // within the reach (compared as cosines: one dot product a pair).
    const double cosineApart = std::cos(std::min(widestCell + reach, 3.14159265358979323846));
    parallelFor(static_cast<int>(cells), [&](int cell) {
        const auto k = static_cast<std::size_t>(cell);
        double bound = 0.0;
        for (std::size_t other = 0; other < cells; ++other) {
            if (glm::dot(cellCentre[k], cellCentre[other]) >= cosineApart) bound = std::max(bound, cellSpeed[other]);
        }
        std::fill_n(bounds.rgba.begin() + static_cast<std::ptrdiff_t>(4 * k), 4, static_cast<float>(bound * factor));
    });
    for (std::size_t k = 0; k < cells; ++k) bounds.largest = std::max(bounds.largest, double(bounds.rgba[4 * k]));
    return bounds;
}

}  // namespace conformal
