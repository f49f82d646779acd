/// @brief Surface coverage: which parts of the colon wall a fly-through showed to the reader
/// well enough to use, from the first-hit positions of the rendered pixels, and the patches it
/// never showed, largest first.
///
/// A surface element (a polygon of colon/wall_surface.h) counts as seen when a pixel's first
/// hit lands on it with
///  - a footprint of at most CoverageSettings::maxFootprintMm2 of wall per pixel, measured
///    from the hit positions of the pixel's neighbours (so it holds for any ray construction,
///    bent or straight, and includes the foreshortening of an oblique view), and
///  - a viewing angle of at most CoverageSettings::maxViewAngleDeg between the element's normal
///    and the direction back to the eye.
/// A pixel marks the element nearest its hit and every element within half the diagonal of its
/// footprint (a disc that covers the pixel's parallelogram on the wall, so neighbouring pixels
/// leave no gaps between their hits), provided it faces the eye as above and lies on the same
/// side of the wall as the nearest one. Seen is an OR over views, so the result does not
/// depend on their order.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "colon/wall_surface.h"

namespace colon {

struct CoverageSettings {
    /// 4 mm^2: 2 mm per pixel on the wall, so a 6 mm polyp (the size from which CT
    /// colonography reports polyps) spans at least three pixels across.
    double maxFootprintMm2 = 4.0;
    /// 80 degrees: beyond it the wall is foreshortened more than 1 : 5.8 (cos 80), a polyp's
    /// outline flattens into a line and its side hides the wall behind it.
    double maxViewAngleDeg = 80.0;
};

/// The pixels of one rendered image: 4 floats per pixel (x, y, z in volume millimetres, w = 1
/// for a hit), row-major from the top row, and the eye the rays left from.
struct CoverageView {
    int width = 0;
    int height = 0;
    std::span<const float> hitMm;
    glm::dvec3 eyeMm{0.0};
};

/// A connected region of elements never seen.
struct UnseenPatch {
    double areaMm2 = 0.0;
    glm::dvec3 centreMm{0.0};   ///< the element centre nearest the patch's area-weighted mean
    glm::dvec3 normal{0.0};     ///< the area-weighted mean normal (unit; into the lumen)
    std::vector<uint32_t> elements;
};

class SurfaceCoverage {
public:
    /// `surface` must outlive this object. Throws ColonError for settings out of range.
    SurfaceCoverage(const WallSurface& surface, const CoverageSettings& settings);

    /// Marks what `view` shows; returns the wall area (mm^2) it showed for the first time.
    /// Throws ColonError for a view whose hit array does not match its size.
    double addView(const CoverageView& view);

    /// Marks `elements` seen (what another process's views showed, say); returns the area
    /// they add. Throws ColonError for an element the surface lacks.
    double markSeen(std::span<const uint32_t> elements);

    [[nodiscard]] double seenAreaMm2() const { return mSeenAreaMm2; }
    [[nodiscard]] double wallAreaMm2() const { return mSurface->totalAreaMm2; }
    [[nodiscard]] double percent() const { return 100.0 * mSeenAreaMm2 / mSurface->totalAreaMm2; }
    [[nodiscard]] const std::vector<uint8_t>& seen() const { return mSeen; }
    [[nodiscard]] const WallSurface& surface() const { return *mSurface; }

    /// Connected regions (elements sharing a vertex) of unseen elements with at least
    /// `minAreaMm2`, largest first.
    [[nodiscard]] std::vector<UnseenPatch> unseenPatches(double minAreaMm2) const;

    /// The element whose centre is nearest `pointMm` within `maxMm`, or -1.
    [[nodiscard]] int nearestElement(const glm::dvec3& pointMm, double maxMm) const;

private:
    /// Cells overlapping the cube of half-side radiusMm about pointMm, clipped to the grid;
    /// false when the cube misses the grid (or the point is not finite).
    bool cellRange(const glm::dvec3& pointMm, double radiusMm, std::array<int, 3>& first, std::array<int, 3>& last) const;
    [[nodiscard]] std::size_t cellIndex(int x, int y, int z) const {
        return static_cast<std::size_t>(x) +
               static_cast<std::size_t>(mGridDims[0]) *
                   (static_cast<std::size_t>(y) + static_cast<std::size_t>(mGridDims[1]) * static_cast<std::size_t>(z));
    }
    template <typename Visit>
    void forEachElementNear(const glm::dvec3& pointMm, double radiusMm, Visit&& visit) const;

    /// Marks what the pixels of rows [rowBegin, rowEnd) of `view` show (threads share mSeen).
    void addRows(const CoverageView& view, int rowBegin, int rowEnd);
    /// Marks element e seen if it was not (safe from several threads); true when it was not.
    bool markElement(uint32_t e);
    /// mSeenAreaMm2 summed again in element order (the same figure whatever order marked them).
    void resumSeenArea();

    const WallSurface* mSurface;
    CoverageSettings mSettings;
    double mCosMaxAngle;
    double mSnapMm;  // farthest a hit may lie from its nearest element (else it is not on the colon wall)
    std::vector<uint8_t> mSeen;
    double mSeenAreaMm2 = 0.0;
    // Element centres binned in a uniform grid of cubes of mCellMm.
    glm::dvec3 mGridOrigin{0.0};
    double mCellMm = 1.0;
    std::array<int, 3> mGridDims{0, 0, 0};
    std::vector<uint32_t> mCellStart;  // CSR: elements of cell c are mCellElements[mCellStart[c] .. mCellStart[c+1])
    std::vector<uint32_t> mCellElements;
    std::vector<uint32_t> mCellUnseen;  // elements of each cell not yet seen: a search of seen cells stops at once
    std::vector<glm::vec3> mCellCentres;  // the centres of mCellElements, in the same order: one cache line serves a cell
};

}  // namespace colon
