#include "colon/polyp_candidates.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <optional>
#include <thread>

#include "colon/colon_error.h"
#include "colon/surface_curvature.h"
#include "colon/surface_measure.h"
#include "colon/surface_view.h"
#include "colon/volume_sampling.h"

namespace colon {
namespace {

/// Elements that share a vertex, as lists per element.
std::vector<std::vector<uint32_t>> elementNeighbours(const WallSurface& wall) {
    std::vector<std::vector<uint32_t>> byVertex(wall.vertices.size());
    for (uint32_t e = 0; e < wall.size(); ++e) {
        for (uint32_t v : wall.quads[e]) byVertex[v].push_back(e);
    }
    std::vector<std::vector<uint32_t>> neighbours(wall.size());
    for (uint32_t e = 0; e < wall.size(); ++e) {
        for (uint32_t v : wall.quads[e]) {
            for (uint32_t other : byVertex[v]) {
                if (other != e) neighbours[e].push_back(other);
            }
        }
        std::sort(neighbours[e].begin(), neighbours[e].end());
        neighbours[e].erase(std::unique(neighbours[e].begin(), neighbours[e].end()), neighbours[e].end());
    }
    return neighbours;
}

/// Step 1 on two threads: the shape at every element's centre (nothing where it is undefined).
std::vector<std::optional<SurfaceShape>> elementShapes(const volumes::Volume& volume, const WallSurface& wall,
                                                       double sigmaMm, double isoHu) {
    std::vector<std::optional<SurfaceShape>> shapes(wall.size());
    const auto work = [&](std::size_t first, std::size_t last) {
        for (std::size_t e = first; e < last; ++e) shapes[e] = surfaceShapeAt(volume, wall.centreMm[e], sigmaMm, isoHu);
    };
    const std::size_t half = wall.size() / 2;
    std::thread other(work, half, wall.size());
    work(0, half);
    other.join();
    return shapes;
}

/// The features of a set of elements (steps 4 and 6): area, centre, normal, means, elongation.
PolypCandidate capFeatures(const WallSurface& wall, const std::vector<std::optional<SurfaceShape>>& shapes,
                           const std::vector<uint32_t>& elements) {
    PolypCandidate cap;
    cap.elements = static_cast<int>(elements.size());
    glm::dvec3 weightedCentre(0.0), weightedNormal(0.0);
    for (uint32_t e : elements) {
        const double a = wall.areaMm2[e];
        cap.capAreaMm2 += a;
        weightedCentre += a * wall.centreMm[e];
        weightedNormal += a * wall.normal[e];
        cap.shapeIndex += a * shapes[e]->shapeIndex;
        cap.curvedness += a * shapes[e]->curvedness;
    }
    cap.centreMm = weightedCentre / cap.capAreaMm2;
    const double normalLength = glm::length(weightedNormal);
    cap.normal = normalLength > 0.0 ? weightedNormal / normalLength : wall.normal[elements.front()];
    cap.shapeIndex /= cap.capAreaMm2;
    cap.curvedness /= cap.capAreaMm2;
    // Elongation: the spread of the element centres across the normal, along its two principal
    // axes (the eigenvalues of the 2x2 second moment on the tangent plane).
    const glm::dvec3 axis = std::abs(cap.normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 t1 = glm::normalize(glm::cross(cap.normal, axis));
    const glm::dvec3 t2 = glm::cross(cap.normal, t1);
    double suu = 0.0, suv = 0.0, svv = 0.0;
    for (uint32_t e : elements) {
        const glm::dvec3 d = wall.centreMm[e] - cap.centreMm;
        const double u = glm::dot(d, t1), v = glm::dot(d, t2), a = wall.areaMm2[e];
        suu += a * u * u;
        suv += a * u * v;
        svv += a * v * v;
    }
    const double mean = 0.5 * (suu + svv);
    const double spread = std::sqrt(0.25 * (suu - svv) * (suu - svv) + suv * suv);
    const double small = mean - spread;
    cap.elongation = small > 0.0 ? std::sqrt((mean + spread) / small) : 1e9;
    return cap;
}

/// How far the lumen reaches from `fromMm` along `direction` before tissue (at most `limitMm`).
double freeDistanceMm(const volumes::Volume& volume, const glm::dvec3& fromMm, const glm::dvec3& direction,
                      double isoHu, double limitMm) {
    const double step = 0.25 * std::min({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});
    const glm::dvec3 extent = glm::dvec3(volume.dims[0] - 1, volume.dims[1] - 1, volume.dims[2] - 1) * volume.spacingMm;
    const auto steps = static_cast<long>(std::ceil(limitMm / step));
    for (long n = 1; n <= steps; ++n) {
        const glm::dvec3 p = fromMm + (static_cast<double>(n) * step) * direction;
        if (glm::any(glm::lessThan(p, glm::dvec3(0.0))) || glm::any(glm::greaterThan(p, extent))) return static_cast<double>(n) * step;
        if (trilinearHu(volume, p) >= isoHu) return static_cast<double>(n) * step;
    }
    return limitMm;
}

/// Step 5: the diameter from a view down the cap's normal; false where none can be had.
bool measureCap(const volumes::Volume& volume, double isoHu, PolypCandidate& cap) {
    const double estimateMm = std::max(3.0, 2.0 * std::sqrt(cap.capAreaMm2 / (2.0 * M_PI)));
    // The cap's centre of area lies under its surface (inside the bump): the surface point is
    // where the normal through it leaves the tissue.
    const double step = 0.25 * std::min({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});
    glm::dvec3 surface = cap.centreMm;
    for (int n = 0; n < 400 && trilinearHu(volume, surface) >= isoHu; ++n) surface += step * cap.normal;
    if (trilinearHu(volume, surface) >= isoHu) return false;
    cap.centreMm = surface;
    // Start the free run a little off the surface.
    const glm::dvec3 start = surface + 0.5 * cap.normal;
    if (trilinearHu(volume, start) >= isoHu) return false;
    const double freeMm = freeDistanceMm(volume, start, cap.normal, isoHu, 60.0);
    const double distance = std::min({2.5 * estimateMm, 0.7 * freeMm, 40.0});
    if (distance < 2.0) return false;
    SurfaceViewRequest view;
    view.eyeMm = start + distance * cap.normal;
    view.lookAtMm = cap.centreMm;
    view.up = std::abs(cap.normal.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    view.fovDeg = std::clamp(2.0 * std::atan(1.5 * estimateMm / distance) * 180.0 / M_PI, 10.0, 120.0);
    view.size = 128;
    view.isoHu = isoHu;
    view.maxDistanceMm = distance + 4.0 * estimateMm;
    try {
        const HitImage image = surfaceView(volume, view);
        const PatchDiameter measured = polypDiameter(image, view.size / 2, view.size / 2);
        cap.diameterMm = measured.diameterMm;
        cap.sphereCentreMm = measured.sphereCentreMm;
        cap.sphereRadiusMm = measured.sphereRadiusMm;
    } catch (const ColonError&) {
        return false;  // the centre ray missed, or the patch there is too small to measure
    }
    cap.viewEyeMm = view.eyeMm;
    return true;
}

void requireSettings(const CandidateSettings& s) {
    const bool inRange = std::isfinite(s.isoHu) && s.smoothingMm > 0.0 && s.smoothingMm <= 10.0 &&
                         s.growShapeIndex > 0.5 && s.growShapeIndex <= s.seedShapeIndex && s.seedShapeIndex < 1.0 &&
                         s.minCurvedness > 0.0 && s.minCurvedness < s.maxCurvedness && s.minCapAreaMm2 >= 0.0 &&
                         s.maxElongation >= 1.0 && s.minDiameterMm >= 0.0 && s.maxCandidates >= 1 &&
                         s.maxCandidates <= 10000;
    if (!inRange) throw ColonError("candidates: settings out of range");
}

}  // namespace

double candidateSmoothingMm(const CandidateSettings& settings, const volumes::Volume& volume) {
    const double largestSpacing = std::max({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});
    return std::max(settings.smoothingMm, 0.75 * largestSpacing);
}

CandidateSearch findPolypCandidates(const volumes::Volume& volume, const WallSurface& wall,
                                    const CandidateSettings& settings, const CandidateProgress& progress) {
    requireSettings(settings);
    if (wall.size() == 0) throw ColonError("candidates: the colon wall has no surface elements");
    const auto say = [&](const std::string& step) {
        if (progress) progress(step);
    };
    CandidateSearch search;
    search.wallElements = wall.size();
    search.wallAreaMm2 = wall.totalAreaMm2;

    const double sigmaMm = candidateSmoothingMm(settings, volume);
    say("shape index and curvedness of " + std::to_string(wall.size()) + " wall elements");
    const auto shapes = elementShapes(volume, wall, sigmaMm, settings.isoHu);
    const auto neighbours = elementNeighbours(wall);

    // Step 2: hysteresis regions from the seeds.
    say("cap regions");
    const auto isSeed = [&](uint32_t e) {
        return shapes[e] && shapes[e]->shapeIndex >= settings.seedShapeIndex &&
               shapes[e]->curvedness >= settings.minCurvedness && shapes[e]->curvedness <= settings.maxCurvedness;
    };
    const auto grows = [&](uint32_t e) {
        return shapes[e] && shapes[e]->shapeIndex >= settings.growShapeIndex &&
               shapes[e]->curvedness >= settings.minCurvedness;
    };
    std::vector<int> regionOf(wall.size(), -1);
    std::vector<std::vector<uint32_t>> regions;
    for (uint32_t seed = 0; seed < wall.size(); ++seed) {
        if (regionOf[seed] >= 0 || !isSeed(seed)) continue;
        const int id = static_cast<int>(regions.size());
        regions.emplace_back();
        std::deque<uint32_t> queue{seed};
        regionOf[seed] = id;
        while (!queue.empty()) {
            const uint32_t e = queue.front();
            queue.pop_front();
            regions.back().push_back(e);
            for (uint32_t n : neighbours[e]) {
                if (regionOf[n] < 0 && grows(n)) {
                    regionOf[n] = id;
                    queue.push_back(n);
                }
            }
        }
    }

    // Step 3: merge regions nearer than the sum of their equivalent radii (union-find).
    std::vector<PolypCandidate> caps;
    for (const auto& r : regions) caps.push_back(capFeatures(wall, shapes, r));
    std::vector<std::size_t> root(caps.size());
    std::iota(root.begin(), root.end(), 0);
    const auto find = [&](std::size_t i) {
        while (root[i] != i) i = root[i] = root[root[i]];
        return i;
    };
    const auto radius = [](const PolypCandidate& c) { return std::sqrt(c.capAreaMm2 / (2.0 * M_PI)); };
    for (std::size_t a = 0; a < caps.size(); ++a) {
        for (std::size_t b = a + 1; b < caps.size(); ++b) {
            if (glm::length(caps[a].centreMm - caps[b].centreMm) < radius(caps[a]) + radius(caps[b])) {
                root[find(a)] = find(b);
            }
        }
    }
    std::vector<std::vector<uint32_t>> merged(caps.size());
    for (std::size_t r = 0; r < regions.size(); ++r) {
        auto& into = merged[find(r)];
        into.insert(into.end(), regions[r].begin(), regions[r].end());
    }

    // Steps 4 to 6.
    say("measuring the caps");
    for (const auto& elements : merged) {
        if (elements.empty()) continue;
        ++search.capRegions;
        PolypCandidate cap = capFeatures(wall, shapes, elements);
        if (cap.capAreaMm2 < settings.minCapAreaMm2) {
            ++search.droppedSmall;
            continue;
        }
        if (cap.elongation > settings.maxElongation) {
            ++search.droppedElongated;
            continue;
        }
        if (!measureCap(volume, settings.isoHu, cap) || cap.diameterMm < settings.minDiameterMm) {
            ++search.droppedUnmeasured;
            continue;
        }
        const double capness = std::clamp((cap.shapeIndex - settings.growShapeIndex) / (1.0 - settings.growShapeIndex), 0.0, 1.0);
        const double fill = std::min(1.0, cap.capAreaMm2 / (0.25 * M_PI * cap.diameterMm * cap.diameterMm));
        cap.score = capness * fill / cap.elongation;
        search.candidates.push_back(cap);
    }
    std::sort(search.candidates.begin(), search.candidates.end(), [](const PolypCandidate& a, const PolypCandidate& b) {
        if (a.score != b.score) return a.score > b.score;
        return a.diameterMm > b.diameterMm;
    });
    if (search.candidates.size() > static_cast<std::size_t>(settings.maxCandidates)) {
        search.droppedBeyondLimit = static_cast<int>(search.candidates.size()) - settings.maxCandidates;
        search.candidates.resize(static_cast<std::size_t>(settings.maxCandidates));
    }
    return search;
}

}  // namespace colon
