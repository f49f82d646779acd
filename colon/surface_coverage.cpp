#include "colon/surface_coverage.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <thread>

#include "colon/colon_error.h"

namespace colon {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool isFiniteHit(const float* p) { return p[3] > 0.5f && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

glm::dvec3 positionOf(const float* p) { return {p[0], p[1], p[2]}; }

/// Union-find over elements, for the unseen patches.
class DisjointSets {
public:
    explicit DisjointSets(std::size_t n) : mParent(n) { std::iota(mParent.begin(), mParent.end(), 0u); }
    uint32_t find(uint32_t x) {
        while (mParent[x] != x) {
            mParent[x] = mParent[mParent[x]];
            x = mParent[x];
        }
        return x;
    }
    void join(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) mParent[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<uint32_t> mParent;
};

}  // namespace

SurfaceCoverage::SurfaceCoverage(const WallSurface& surface, const CoverageSettings& settings)
    : mSurface(&surface), mSettings(settings) {
    if (!(settings.maxFootprintMm2 > 0.0) || !std::isfinite(settings.maxFootprintMm2)) {
        throw ColonError("coverage: the largest footprint per pixel must be a positive number of mm^2");
    }
    if (!(settings.maxViewAngleDeg > 0.0 && settings.maxViewAngleDeg <= 90.0)) {
        throw ColonError("coverage: the largest viewing angle must be in (0, 90] degrees");
    }
    if (surface.size() == 0 || !(surface.totalAreaMm2 > 0.0)) throw ColonError("coverage: the wall surface is empty");
    mCosMaxAngle = std::cos(settings.maxViewAngleDeg * kPi / 180.0);
    mSeen.assign(surface.size(), 0);

    // Cells of the snapping distance: a hit's search for its nearest element scans at most
    // 3 x 3 x 3 of them and little beyond the sphere it asks for (the scan over candidates is the
    // cost of coverage). On a large wall the cells grow until the grid holds at most kMaxCells.
    constexpr double kMaxCells = 32.0 * 1024.0 * 1024.0;
    const double elementMm = std::sqrt(surface.totalAreaMm2 / static_cast<double>(surface.size()));
    mSnapMm = std::max(1.5 * elementMm, 1e-3);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const auto& c : surface.centreMm) {
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
    }
    mGridOrigin = lo;
    const glm::dvec3 extent = hi - lo;
    mCellMm = std::max(mSnapMm, std::cbrt((extent.x + mSnapMm) * (extent.y + mSnapMm) * (extent.z + mSnapMm) / kMaxCells));
    for (int a = 0; a < 3; ++a) {
        const double cells = std::floor(extent[a] / mCellMm) + 1.0;
        if (!(cells <= 65536.0)) throw ColonError("coverage: the wall surface spans too many cells to index");
        mGridDims[static_cast<std::size_t>(a)] = static_cast<int>(cells);
    }
    const std::size_t cellCount = static_cast<std::size_t>(mGridDims[0]) * static_cast<std::size_t>(mGridDims[1]) *
                                  static_cast<std::size_t>(mGridDims[2]);
    const auto cellOf = [&](const glm::dvec3& p) {
        const glm::ivec3 c = glm::ivec3(glm::floor((p - mGridOrigin) / mCellMm));
        return static_cast<std::size_t>(c.x) +
               static_cast<std::size_t>(mGridDims[0]) *
                   (static_cast<std::size_t>(c.y) + static_cast<std::size_t>(mGridDims[1]) * static_cast<std::size_t>(c.z));
    };
    mCellStart.assign(cellCount + 1, 0);
    for (const auto& c : surface.centreMm) ++mCellStart[cellOf(c) + 1];
    std::partial_sum(mCellStart.begin(), mCellStart.end(), mCellStart.begin());
    mCellElements.resize(surface.size());
    std::vector<uint32_t> fill(mCellStart.begin(), mCellStart.end() - 1);
    for (uint32_t e = 0; e < surface.size(); ++e) mCellElements[fill[cellOf(surface.centreMm[e])]++] = e;
    mCellUnseen.resize(cellCount);
    for (std::size_t c = 0; c < cellCount; ++c) mCellUnseen[c] = mCellStart[c + 1] - mCellStart[c];
    mCellCentres.resize(surface.size());
    for (std::size_t n = 0; n < mCellElements.size(); ++n) mCellCentres[n] = glm::vec3(surface.centreMm[mCellElements[n]]);
}

bool SurfaceCoverage::cellRange(const glm::dvec3& pointMm, double radiusMm, std::array<int, 3>& first,
                                std::array<int, 3>& last) const {
    const glm::dvec3 lo = (pointMm - radiusMm - mGridOrigin) / mCellMm;
    const glm::dvec3 hi = (pointMm + radiusMm - mGridOrigin) / mCellMm;
    for (int a = 0; a < 3; ++a) {
        const auto axis = static_cast<std::size_t>(a);
        const double maxCell = mGridDims[axis] - 1;
        // Cell c spans [c, c + 1) in these units: the last one reaches maxCell + 1.
        if (!(hi[a] >= 0.0) || !(lo[a] < maxCell + 1.0)) return false;
        first[axis] = static_cast<int>(std::floor(std::max(lo[a], 0.0)));
        last[axis] = static_cast<int>(std::floor(std::min(hi[a], maxCell)));
    }
    return true;
}

template <typename Visit>
void SurfaceCoverage::forEachElementNear(const glm::dvec3& pointMm, double radiusMm, Visit&& visit) const {
    std::array<int, 3> first{}, last{};
    if (!cellRange(pointMm, radiusMm, first, last)) return;
    // Single precision: centres are stored so, and the scan is the cost of coverage.
    const glm::vec3 point(pointMm);
    const auto radius2 = static_cast<float>(radiusMm * radiusMm);
    for (int z = first[2]; z <= last[2]; ++z) {
        for (int y = first[1]; y <= last[1]; ++y) {
            for (int x = first[0]; x <= last[0]; ++x) {
                const std::size_t cell = cellIndex(x, y, z);
                for (uint32_t n = mCellStart[cell]; n < mCellStart[cell + 1]; ++n) {
                    const glm::vec3 d = mCellCentres[n] - point;
                    const float distance2 = glm::dot(d, d);
                    if (distance2 <= radius2) visit(mCellElements[n], distance2);
                }
            }
        }
    }
}

int SurfaceCoverage::nearestElement(const glm::dvec3& pointMm, double maxMm) const {
    int nearest = -1;
    double best = std::numeric_limits<double>::max();
    forEachElementNear(pointMm, maxMm, [&](uint32_t e, float distance2) {
        if (distance2 < best) {
            best = distance2;
            nearest = static_cast<int>(e);
        }
    });
    return nearest;
}

double SurfaceCoverage::addView(const CoverageView& view) {
    const std::size_t pixels = static_cast<std::size_t>(std::max(view.width, 0)) * static_cast<std::size_t>(std::max(view.height, 0));
    if (view.width < 1 || view.height < 1 || view.hitMm.size() != 4 * pixels) {
        throw ColonError("coverage: a view of " + std::to_string(view.width) + "x" + std::to_string(view.height) +
                         " pixels came with " + std::to_string(view.hitMm.size() / 4) + " hit positions");
    }
    // Rows in bands on a few threads: an element is marked by whichever pixel reaches it first,
    // and the set marked does not depend on which.
    const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
    const int bands = std::min(threads, view.height);
    std::vector<std::thread> workers;
    for (int b = 1; b < bands; ++b) {
        workers.emplace_back([this, &view, b, bands] { addRows(view, view.height * b / bands, view.height * (b + 1) / bands); });
    }
    addRows(view, 0, view.height / bands);
    for (auto& worker : workers) worker.join();
    const double before = mSeenAreaMm2;
    resumSeenArea();
    return mSeenAreaMm2 - before;
}

void SurfaceCoverage::resumSeenArea() {
    // In element order, so the figure is the same whatever the threads did.
    mSeenAreaMm2 = 0.0;
    for (std::size_t e = 0; e < mSeen.size(); ++e) mSeenAreaMm2 += mSeen[e] != 0 ? mSurface->areaMm2[e] : 0.0;
}

bool SurfaceCoverage::markElement(uint32_t e) {
    if (std::atomic_ref<uint8_t>(mSeen[e]).exchange(1, std::memory_order_relaxed) != 0) return false;
    const glm::ivec3 c = glm::ivec3(glm::floor((mSurface->centreMm[e] - mGridOrigin) / mCellMm));
    std::atomic_ref<uint32_t>(mCellUnseen[cellIndex(c.x, c.y, c.z)]).fetch_sub(1, std::memory_order_relaxed);
    return true;
}

double SurfaceCoverage::markSeen(std::span<const uint32_t> elements) {
    for (uint32_t e : elements) {
        if (e >= mSeen.size()) {
            throw ColonError("coverage: element " + std::to_string(e) + " of " + std::to_string(mSeen.size()) +
                             " marked seen");
        }
    }
    for (uint32_t e : elements) markElement(e);
    const double before = mSeenAreaMm2;
    resumSeenArea();
    return mSeenAreaMm2 - before;
}

void SurfaceCoverage::addRows(const CoverageView& view, int rowBegin, int rowEnd) {
    const float* hits = view.hitMm.data();
    const auto at = [&](int x, int y) {
        return hits + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(view.width) + static_cast<std::size_t>(x));
    };
    // The shorter of the steps to the two neighbours along one image axis that hit too: across
    // a silhouette, the neighbour on the same surface is the nearer one.
    const auto step = [&](int x, int y, int dx, int dy, glm::dvec3& out) {
        const glm::dvec3 here = positionOf(at(x, y));
        double best = std::numeric_limits<double>::max();
        for (int sign : {1, -1}) {
            const int nx = x + sign * dx, ny = y + sign * dy;
            if (nx < 0 || ny < 0 || nx >= view.width || ny >= view.height || !isFiniteHit(at(nx, ny))) continue;
            const glm::dvec3 d = positionOf(at(nx, ny)) - here;
            const double length2 = glm::dot(d, d);
            if (length2 < best) {
                best = length2;
                out = d;
            }
        }
        return best < std::numeric_limits<double>::max();
    };
    for (int y = rowBegin; y < rowEnd; ++y) {
        for (int x = 0; x < view.width; ++x) {
            if (!isFiniteHit(at(x, y))) continue;
            glm::dvec3 across{0.0}, down{0.0};
            if (!step(x, y, 1, 0, across) || !step(x, y, 0, 1, down)) continue;
            const double footprint = glm::length(glm::cross(across, down));
            if (!(footprint <= mSettings.maxFootprintMm2)) continue;
            const glm::dvec3 hit = positionOf(at(x, y));
            const double radius = 0.5 * std::max(glm::length(across + down), glm::length(across - down));
            const double reach = std::max(radius, mSnapMm);
            // Where every element in reach was seen already (most pixels, after the first
            // frames), there is nothing to mark.
            std::array<int, 3> first{}, last{};
            if (!cellRange(hit, reach, first, last)) continue;
            bool isAnyUnseen = false;
            for (int cz = first[2]; cz <= last[2] && !isAnyUnseen; ++cz) {
                for (int cy = first[1]; cy <= last[1] && !isAnyUnseen; ++cy) {
                    for (int cx = first[0]; cx <= last[0] && !isAnyUnseen; ++cx) {
                        isAnyUnseen = std::atomic_ref<uint32_t>(mCellUnseen[cellIndex(cx, cy, cz)]).load(std::memory_order_relaxed) > 0;
                    }
                }
            }
            if (!isAnyUnseen) continue;
            // The nearest element within the snapping distance, then the footprint's disc.
            uint32_t nearest = 0;
            float nearestDistance2 = std::numeric_limits<float>::max();
            forEachElementNear(hit, mSnapMm, [&](uint32_t e, float distance2) {
                if (distance2 < nearestDistance2) {
                    nearestDistance2 = distance2;
                    nearest = e;
                }
            });
            if (nearestDistance2 == std::numeric_limits<float>::max()) continue;  // the hit is not on the colon wall
            const glm::dvec3 sheet = mSurface->normal[nearest];
            const auto mark = [&](uint32_t e) {
                std::atomic_ref<uint8_t> seen(mSeen[e]);
                if (seen.load(std::memory_order_relaxed) != 0) return;
                const glm::dvec3 toEye = view.eyeMm - mSurface->centreMm[e];
                const double toEyeLength = glm::length(toEye);
                if (!(toEyeLength > 0.0)) return;
                if (glm::dot(mSurface->normal[e], toEye) < mCosMaxAngle * toEyeLength) return;
                if (glm::dot(mSurface->normal[e], sheet) <= 0.0) return;
                markElement(e);
            };
            mark(nearest);
            if (radius > 0.0) forEachElementNear(hit, radius, [&](uint32_t e, float) { mark(e); });
        }
    }
}

std::vector<UnseenPatch> SurfaceCoverage::unseenPatches(double minAreaMm2) const {
    const WallSurface& s = *mSurface;
    DisjointSets sets(s.size());
    std::vector<uint32_t> firstQuadOfVertex(s.vertices.size(), std::numeric_limits<uint32_t>::max());
    for (uint32_t e = 0; e < s.size(); ++e) {
        if (mSeen[e] != 0) continue;
        for (uint32_t v : s.quads[e]) {
            uint32_t& first = firstQuadOfVertex[v];
            if (first == std::numeric_limits<uint32_t>::max()) {
                first = e;
            } else {
                sets.join(first, e);
            }
        }
    }
    std::vector<int> patchOfRoot(s.size(), -1);
    std::vector<UnseenPatch> patches;
    for (uint32_t e = 0; e < s.size(); ++e) {
        if (mSeen[e] != 0) continue;
        const uint32_t root = sets.find(e);
        if (patchOfRoot[root] < 0) {
            patchOfRoot[root] = static_cast<int>(patches.size());
            patches.emplace_back();
        }
        UnseenPatch& patch = patches[static_cast<std::size_t>(patchOfRoot[root])];
        patch.elements.push_back(e);
        patch.areaMm2 += s.areaMm2[e];
        patch.centreMm += s.areaMm2[e] * s.centreMm[e];
        patch.normal += s.areaMm2[e] * s.normal[e];
    }
    std::erase_if(patches, [&](const UnseenPatch& p) { return p.areaMm2 < minAreaMm2; });
    for (UnseenPatch& patch : patches) {
        const glm::dvec3 mean = patch.centreMm / patch.areaMm2;
        const double normalLength = glm::length(patch.normal);
        patch.normal = normalLength > 0.0 ? patch.normal / normalLength : s.normal[patch.elements.front()];
        // The mean of a curved patch lies off the wall; report a point on it.
        uint32_t closest = patch.elements.front();
        double best = std::numeric_limits<double>::max();
        for (uint32_t e : patch.elements) {
            const double d = glm::length(s.centreMm[e] - mean);
            if (d < best) {
                best = d;
                closest = e;
            }
        }
        patch.centreMm = s.centreMm[closest];
    }
    std::sort(patches.begin(), patches.end(),
              [](const UnseenPatch& a, const UnseenPatch& b) { return a.areaMm2 > b.areaMm2; });
    return patches;
}

}  // namespace colon
