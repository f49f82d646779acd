#include "volumes/colon_phantom.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "volumes/parallel_for.h"

namespace volumes {
namespace {

/// Free space a pedunculated polyp's head leaves around the centreline (mm).
constexpr double kCentrelineClearanceMm = 1.5;


constexpr double kPi = 3.14159265358979323846;
/// Centreline vertices are this far apart along the curve.
constexpr double kCentrelineStepMm = 1.0;
/// Voxels are classified in slabs of this many z layers (bounded scratch memory, one per thread).
constexpr int kSlabLayers = 16;

[[noreturn]] void fail(const std::string& problem) {
    throw VolumeError("colon phantom: " + problem);
}

/// Catmull-Rom spline through `points`, sampled every ~kCentrelineStepMm along its length.
std::vector<glm::dvec3> smoothPolyline(const std::vector<glm::dvec3>& points) {
    std::vector<glm::dvec3> dense;
    const int spans = static_cast<int>(points.size()) - 1;
    for (int i = 0; i < spans; ++i) {
        const glm::dvec3 p0 = points[static_cast<std::size_t>(std::max(i - 1, 0))];
        const glm::dvec3 p1 = points[static_cast<std::size_t>(i)];
        const glm::dvec3 p2 = points[static_cast<std::size_t>(i + 1)];
        const glm::dvec3 p3 = points[static_cast<std::size_t>(std::min(i + 2, spans))];
        for (int s = 0; s < 200; ++s) {
            const double t = s / 200.0, t2 = t * t, t3 = t2 * t;
            dense.push_back(0.5 * ((2.0 * p1) + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                                   (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3));
        }
    }
    dense.push_back(points.back());
    // Resample at even arc length.
    std::vector<glm::dvec3> even{dense.front()};
    double carried = 0.0;
    for (std::size_t i = 1; i < dense.size(); ++i) {
        glm::dvec3 from = dense[i - 1];
        double length = glm::length(dense[i] - from);
        while (carried + length >= kCentrelineStepMm) {
            const double t = (kCentrelineStepMm - carried) / length;
            from = from + t * (dense[i] - from);
            even.push_back(from);
            length = glm::length(dense[i] - from);
            carried = 0.0;
        }
        carried += length;
    }
    if (glm::length(even.back() - dense.back()) > 0.25 * kCentrelineStepMm) even.push_back(dense.back());
    return even;
}

/// The centreline with arc lengths and a rotation-minimising frame (Wang et al. 2008, double
/// reflection), so "angle around the centreline" does not twist along the tube.
struct Centreline {
    std::vector<glm::dvec3> points, tangents, normals;
    std::vector<double> arcMm;

    explicit Centreline(std::vector<glm::dvec3> polyline) : points(std::move(polyline)) {
        const std::size_t n = points.size();
        arcMm.assign(n, 0.0);
        for (std::size_t i = 1; i < n; ++i) arcMm[i] = arcMm[i - 1] + glm::length(points[i] - points[i - 1]);
        tangents.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            tangents[i] = glm::normalize(points[std::min(i + 1, n - 1)] - points[i == 0 ? 0 : i - 1]);
        }
        normals.resize(n);
        const glm::dvec3 t0 = tangents[0];
        const glm::dvec3 helper = std::abs(t0.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        normals[0] = glm::normalize(glm::cross(t0, glm::cross(helper, t0)));
        for (std::size_t i = 0; i + 1 < n; ++i) {
            const glm::dvec3 v1 = points[i + 1] - points[i];
            const double c1 = glm::dot(v1, v1);
            const glm::dvec3 rL = normals[i] - (2.0 / c1) * glm::dot(v1, normals[i]) * v1;
            const glm::dvec3 tL = tangents[i] - (2.0 / c1) * glm::dot(v1, tangents[i]) * v1;
            const glm::dvec3 v2 = tangents[i + 1] - tL;
            const double c2 = glm::dot(v2, v2);
            glm::dvec3 next = c2 > 1e-20 ? rL - (2.0 / c2) * glm::dot(v2, rL) * v2 : rL;
            next -= glm::dot(next, tangents[i + 1]) * tangents[i + 1];
            normals[i + 1] = glm::normalize(next);
        }
    }
    double length() const { return arcMm.back(); }

    /// Point, tangent and normal at arc length s (clamped), interpolated between vertices.
    void frameAt(double s, glm::dvec3& point, glm::dvec3& tangent, glm::dvec3& normal) const {
        s = std::clamp(s, 0.0, length());
        const std::size_t i =
            std::min<std::size_t>(std::upper_bound(arcMm.begin(), arcMm.end(), s) - arcMm.begin(), points.size() - 1);
        const std::size_t a = i == 0 ? 0 : i - 1;
        const double span = arcMm[i] - arcMm[a];
        const double t = span > 0.0 ? (s - arcMm[a]) / span : 0.0;
        point = glm::mix(points[a], points[i], t);
        tangent = glm::normalize(glm::mix(tangents[a], tangents[i], t));
        normal = glm::mix(normals[a], normals[i], t);
        normal = glm::normalize(normal - glm::dot(normal, tangent) * tangent);
    }
};

struct Fold {
    double arcMm;
    double angleRad;
};

struct PolypSolid {
    PolypTruth truth;
    glm::dvec3 stalkStart{0.0}, stalkEnd{0.0};
    double stalkRadiusMm = 0.0;
};

double segmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, double& t) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

/// Signed distance to the polyps' union (negative inside a polyp).
double polypDistance(const std::vector<PolypSolid>& polyps, const glm::dvec3& p) {
    double d = std::numeric_limits<double>::max();
    for (const PolypSolid& polyp : polyps) {
        d = std::min(d, glm::length(p - polyp.truth.centreMm) - polyp.truth.radiusMm);
        if (polyp.truth.kind == PolypKind::Pedunculated) {
            double t = 0.0;
            d = std::min(d, segmentDistance(p, polyp.stalkStart, polyp.stalkEnd, t) - polyp.stalkRadiusMm);
        }
    }
    return d;
}

/// How far the lumen wall is pulled in by haustral folds at arc s and angle theta (mm).
double foldIntrusion(const ColonPhantomSpec& spec, const std::vector<Fold>& folds, double s, double theta) {
    double intrusion = 0.0;
    for (const Fold& fold : folds) {
        const double x = (s - fold.arcMm) / spec.foldHalfWidthMm;
        if (std::abs(x) >= 1.0) continue;
        // Semilunar: the ridge spans two thirds of the circumference, deepest opposite its gap.
        const double around = std::clamp((std::cos(theta - fold.angleRad) + 0.5) / 0.8, 0.0, 1.0);
        intrusion = std::max(intrusion, spec.foldDepthMm * (1.0 - x * x) * around);
    }
    return intrusion;
}

/// Counter-based Gaussian noise: voxel n always gets the same value for a seed, whichever
/// thread computes it.
double gaussianAt(std::uint64_t seed, std::uint64_t n) {
    auto mix = [](std::uint64_t z) {
        z += 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    };
    const std::uint64_t a = mix(seed * 0x632be59bd9b4e019ULL ^ n);
    const std::uint64_t b = mix(a);
    const double u1 = (static_cast<double>(a >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    const double u2 = static_cast<double>(b >> 11) * (1.0 / 9007199254740992.0);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

}  // namespace

std::vector<PolypSpec> ColonPhantomSpec::defaultPolyps() {
    return {{PolypKind::Sessile, 6.0, 0.15, 30.0, 0.0},
            {PolypKind::Pedunculated, 8.0, 0.33, 150.0, 1.5},
            {PolypKind::Sessile, 3.0, 0.50, 270.0, 0.0},
            {PolypKind::Sessile, 12.0, 0.68, 90.0, 0.0},
            {PolypKind::Pedunculated, 6.0, 0.85, 210.0, 3.0}};
}

ColonPhantom makeColonPhantom(const ColonPhantomSpec& spec) {
    ColonPhantom phantom;
    Volume& volume = phantom.volume;
    volume.dims = spec.grid.dims;
    volume.spacingMm = spec.grid.spacingMm;
    validateGeometry(volume, "colon phantom grid");
    const glm::dvec3 extent = glm::dvec3(volume.dims[0] - 1, volume.dims[1] - 1, volume.dims[2] - 1) * volume.spacingMm;
    const double outerMm = spec.lumenRadiusMm + spec.wallThicknessMm;
    if (!(spec.lumenRadiusMm > 2.0) || !(spec.wallThicknessMm > 0.0) || !(spec.fatThicknessMm >= 0.0) ||
        !(spec.edgeWidthMm > 0.0) || !(spec.noiseSigmaHu >= 0.0) || !(spec.foldSpacingMm > 0.0)) {
        fail("radii, thicknesses, spacing of folds and edge width must be positive, noise non-negative");
    }

    // Centreline: ascending colon, hepatic flexure, transverse colon, splenic flexure,
    // descending colon, as fractions of the grid's extent.
    const std::vector<glm::dvec3> controls = {{0.28, 0.50, 0.13}, {0.24, 0.42, 0.34}, {0.30, 0.58, 0.58},
                                              {0.36, 0.48, 0.80}, {0.55, 0.40, 0.84}, {0.70, 0.56, 0.72},
                                              {0.76, 0.46, 0.48}, {0.72, 0.52, 0.26}, {0.74, 0.48, 0.13}};
    std::vector<glm::dvec3> scaled;
    for (const glm::dvec3& c : controls) scaled.push_back(c * extent);
    const Centreline line(smoothPolyline(scaled));
    for (const glm::dvec3& p : line.points) {
        for (int a = 0; a < 3; ++a) {
            if (p[a] < outerMm || p[a] > extent[a] - outerMm) {
                fail("the grid (" + std::to_string(extent.x) + " x " + std::to_string(extent.y) + " x " +
                     std::to_string(extent.z) + " mm) is too small for a tube of outer radius " +
                     std::to_string(outerMm) + " mm (use more voxels, larger spacing or a smaller lumen)");
            }
        }
    }
    phantom.centrelineMm = line.points;

    // Polyps: on the wall at their arc and angle, base normal pointing into the lumen.
    std::vector<PolypSolid> polyps;
    for (const PolypSpec& p : spec.polyps) {
        if (!(p.diameterMm >= 3.0 && p.diameterMm <= 15.0))
            fail("polyp diameter " + std::to_string(p.diameterMm) + " mm is outside 3..15 mm");
        if (!(p.arcFraction >= 0.0 && p.arcFraction <= 1.0))
            fail("polyp position " + std::to_string(p.arcFraction) + " is outside 0..1");
        if (!std::isfinite(p.angleDeg)) fail("polyp angle is not finite");
        PolypSolid solid;
        PolypTruth& truth = solid.truth;
        truth.kind = p.kind;
        truth.radiusMm = 0.5 * p.diameterMm;
        truth.arcLengthMm = p.arcFraction * line.length();
        glm::dvec3 point, tangent, normal;
        line.frameAt(truth.arcLengthMm, point, tangent, normal);
        const glm::dvec3 binormal = glm::cross(tangent, normal);
        const double theta = p.angleDeg * kPi / 180.0;
        const glm::dvec3 outward = std::cos(theta) * normal + std::sin(theta) * binormal;
        truth.baseMm = point + spec.lumenRadiusMm * outward;
        truth.baseNormal = -outward;
        if (p.kind == PolypKind::Sessile) {
            truth.centreMm = truth.baseMm;  // half the sphere stands in the lumen: a hemisphere
        } else {
            // The head must stop short of the centreline, so a fly-through along it stays in air.
            if (!(p.stalkLengthMm >= 0.5) || p.stalkLengthMm + p.diameterMm > spec.lumenRadiusMm - kCentrelineClearanceMm) {
                fail("a pedunculated polyp of " + std::to_string(p.diameterMm) + " mm on a " +
                     std::to_string(p.stalkLengthMm) + " mm stalk would reach the centreline of a lumen " +
                     std::to_string(2.0 * spec.lumenRadiusMm) + " mm across (stalk + diameter must be at most " +
                     std::to_string(spec.lumenRadiusMm - kCentrelineClearanceMm) + " mm)");
            }
            truth.stalkLengthMm = p.stalkLengthMm;
            truth.centreMm = truth.baseMm + (p.stalkLengthMm + truth.radiusMm) * truth.baseNormal;
            solid.stalkStart = truth.baseMm - spec.wallThicknessMm * 0.5 * truth.baseNormal;
            solid.stalkEnd = truth.centreMm;
            solid.stalkRadiusMm = std::max(1.0, 0.3 * truth.radiusMm);
        }
        polyps.push_back(solid);
        phantom.polyps.push_back(truth);
    }

    // Folds: evenly spaced, turning by a third of a turn each, kept clear of the polyps.
    std::vector<Fold> folds;
    int foldIndex = 0;
    for (double s = 0.5 * spec.foldSpacingMm; s < line.length() - 0.5 * spec.foldSpacingMm;
         s += spec.foldSpacingMm, ++foldIndex) {
        const bool isClear = std::none_of(polyps.begin(), polyps.end(), [&](const PolypSolid& p) {
            return std::abs(p.truth.arcLengthMm - s) < p.truth.radiusMm + spec.foldHalfWidthMm + 3.0;
        });
        if (isClear) {
            folds.push_back({s, foldIndex * 2.0 * kPi / 3.0});
            phantom.foldArcLengthsMm.push_back(s);
        }
    }

    // Classify voxels slab by slab: nearest centreline point in a band around the tube, then
    // HU from the signed distances.
    const double bandMm = outerMm + spec.fatThicknessMm + 2.0 * spec.edgeWidthMm;
    volume.hu.assign(volume.voxelCount(), spec.tissueHu);
    std::vector<float> noise(spec.noiseSigmaHu > 0.0 ? volume.voxelCount() : 0);
    const int slabs = (volume.dims[2] + kSlabLayers - 1) / kSlabLayers;
    const std::size_t layerVoxels = static_cast<std::size_t>(volume.dims[0]) * volume.dims[1];
    const glm::dvec3 spacing = volume.spacingMm;
    parallelFor(slabs, [&](int slab) {
        const int k0 = slab * kSlabLayers, k1 = std::min(k0 + kSlabLayers, volume.dims[2]);
        std::vector<float> bestDistance(layerVoxels * static_cast<std::size_t>(k1 - k0),
                                        std::numeric_limits<float>::max());
        std::vector<float> bestArc(bestDistance.size(), 0.0f);
        for (std::size_t i = 0; i + 1 < line.points.size(); ++i) {
            const glm::dvec3 a = line.points[i], b = line.points[i + 1];
            const glm::dvec3 lo = glm::min(a, b) - bandMm, hi = glm::max(a, b) + bandMm;
            const int kLo = std::max(k0, static_cast<int>(std::ceil(lo.z / spacing.z)));
            const int kHi = std::min(k1 - 1, static_cast<int>(std::floor(hi.z / spacing.z)));
            if (kLo > kHi) continue;
            const int jLo = std::max(0, static_cast<int>(std::ceil(lo.y / spacing.y)));
            const int jHi = std::min(volume.dims[1] - 1, static_cast<int>(std::floor(hi.y / spacing.y)));
            const int iLo = std::max(0, static_cast<int>(std::ceil(lo.x / spacing.x)));
            const int iHi = std::min(volume.dims[0] - 1, static_cast<int>(std::floor(hi.x / spacing.x)));
            const double segmentLength = glm::length(b - a);
            for (int k = kLo; k <= kHi; ++k)
                for (int j = jLo; j <= jHi; ++j)
                    for (int iv = iLo; iv <= iHi; ++iv) {
                        double t = 0.0;
                        const double d = segmentDistance(glm::dvec3(iv, j, k) * spacing, a, b, t);
                        const std::size_t at = static_cast<std::size_t>(iv) +
                                               static_cast<std::size_t>(volume.dims[0]) *
                                                   (j + static_cast<std::size_t>(volume.dims[1]) * (k - k0));
                        if (d < bestDistance[at]) {
                            bestDistance[at] = static_cast<float>(d);
                            bestArc[at] = static_cast<float>(line.arcMm[i] + t * segmentLength);
                        }
                    }
        }
        for (int k = k0; k < k1; ++k)
            for (int j = 0; j < volume.dims[1]; ++j)
                for (int iv = 0; iv < volume.dims[0]; ++iv) {
                    const std::size_t local =
                        static_cast<std::size_t>(iv) + static_cast<std::size_t>(volume.dims[0]) *
                                                           (j + static_cast<std::size_t>(volume.dims[1]) * (k - k0));
                    const std::size_t n = volume.linearIndex(iv, j, k);
                    if (!noise.empty()) noise[n] = static_cast<float>(gaussianAt(spec.seed, n));
                    if (bestDistance[local] > bandMm) continue;  // plain soft tissue
                    const glm::dvec3 p = glm::dvec3(iv, j, k) * spacing;
                    glm::dvec3 point, tangent, normal;
                    line.frameAt(bestArc[local], point, tangent, normal);
                    const glm::dvec3 radial = p - point;
                    const double theta =
                        std::atan2(glm::dot(radial, glm::cross(tangent, normal)), glm::dot(radial, normal));
                    const double lumenDistance =
                        bestDistance[local] - (spec.lumenRadiusMm - foldIntrusion(spec, folds, bestArc[local], theta));
                    const double polyp = polypDistance(polyps, p);
                    const double airDistance = std::max(lumenDistance, -polyp);
                    // Tissue value: wall, then the fat band, then soft tissue; polyps are tissue.
                    const double e = spec.edgeWidthMm;
                    const double fatWeight =
                        std::clamp((lumenDistance - spec.wallThicknessMm) / e + 0.5, 0.0, 1.0) *
                        std::clamp((spec.wallThicknessMm + spec.fatThicknessMm - lumenDistance) / e + 0.5, 0.0, 1.0);
                    double tissue = spec.tissueHu + fatWeight * (spec.fatHu - spec.tissueHu);
                    tissue += std::clamp(0.5 - polyp / e, 0.0, 1.0) * (spec.tissueHu - tissue);
                    const double airWeight = std::clamp(0.5 - airDistance / e, 0.0, 1.0);
                    volume.hu[n] = static_cast<int16_t>(std::lround(tissue + airWeight * (spec.lumenHu - tissue)));
                }
    });

    // CT-like noise: white Gaussian smoothed by [1 2 1]/4 along each axis (correlated over a
    // voxel or two, as reconstruction kernels make it), rescaled to the requested sigma.
    if (!noise.empty()) {
        const std::array<std::size_t, 3> strides{1, static_cast<std::size_t>(volume.dims[0]), layerVoxels};
        for (int axis = 0; axis < 3; ++axis) {
            const int n = volume.dims[static_cast<std::size_t>(axis)];
            if (n < 3) continue;
            const std::size_t stride = strides[static_cast<std::size_t>(axis)];
            std::vector<float> line1(static_cast<std::size_t>(n));
            for (std::size_t start = 0; start < noise.size(); ++start) {
                // `start` is the first voxel of a line along `axis`.
                if ((start / stride) % static_cast<std::size_t>(n) != 0) continue;
                for (int v = 0; v < n; ++v) line1[static_cast<std::size_t>(v)] = noise[start + v * stride];
                for (int v = 0; v < n; ++v) {
                    const float left = line1[static_cast<std::size_t>(std::max(v - 1, 0))];
                    const float right = line1[static_cast<std::size_t>(std::min(v + 1, n - 1))];
                    noise[start + v * stride] =
                        0.25f * left + 0.5f * line1[static_cast<std::size_t>(v)] + 0.25f * right;
                }
            }
        }
        const double gain = spec.noiseSigmaHu / std::pow(std::sqrt(6.0 / 16.0), 3.0);
        for (std::size_t n = 0; n < noise.size(); ++n) {
            const double v = volume.hu[n] + gain * noise[n];
            volume.hu[n] = static_cast<int16_t>(std::clamp(std::lround(v), -1024L, 3071L));
        }
    }
    validateVolume(volume, "colon phantom");
    return phantom;
}

std::string colonTruthJson(const ColonPhantomSpec& spec, const ColonPhantom& phantom) {
    auto vec = [](const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    nlohmann::json truth;
    truth["frame"] = "volume millimetres: voxel (i, j, k) has its centre at (i, j, k) * spacing_mm";
    truth["geometry"] = "analytic signed distances to the centreline polyline, fold ridges, polyp spheres and stalks";
    truth["dims"] = phantom.volume.dims;
    truth["spacing_mm"] = vec(phantom.volume.spacingMm);
    truth["hu"] = {{"lumen", spec.lumenHu}, {"wall_and_tissue", spec.tissueHu}, {"fat", spec.fatHu}};
    truth["noise_sigma_hu"] = spec.noiseSigmaHu;
    truth["seed"] = spec.seed;
    truth["lumen_radius_mm"] = spec.lumenRadiusMm;
    truth["wall_thickness_mm"] = spec.wallThicknessMm;
    truth["fat_thickness_mm"] = spec.fatThicknessMm;
    truth["edge_width_mm"] = spec.edgeWidthMm;
    nlohmann::json centreline = nlohmann::json::array();
    for (const glm::dvec3& p : phantom.centrelineMm) centreline.push_back(vec(p));
    truth["centreline_mm"] = centreline;
    truth["fold_arc_lengths_mm"] = phantom.foldArcLengthsMm;
    truth["fold"] = {{"depth_mm", spec.foldDepthMm}, {"half_width_mm", spec.foldHalfWidthMm}};
    nlohmann::json polyps = nlohmann::json::array();
    for (const PolypTruth& p : phantom.polyps) {
        polyps.push_back({{"kind", p.kind == PolypKind::Sessile ? "sessile" : "pedunculated"},
                          {"diameter_mm", 2.0 * p.radiusMm},
                          {"radius_mm", p.radiusMm},
                          {"centre_mm", vec(p.centreMm)},
                          {"base_mm", vec(p.baseMm)},
                          {"base_normal", vec(p.baseNormal)},
                          {"arc_length_mm", p.arcLengthMm},
                          {"stalk_length_mm", p.stalkLengthMm}});
    }
    truth["polyps"] = polyps;
    return truth.dump(1) + "\n";
}

PolypSpec parsePolypSpec(const std::string& text) {
    auto failSpec = [&](const std::string& problem) {
        throw VolumeError("polyp '" + text + "': " + problem +
                          " (expected KIND:DIAMETER_MM:POSITION:ANGLE_DEG[:STALK_MM], e.g. sessile:6:0.3:45)");
    };
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (parts.size() < 6) {
        const std::size_t end = text.find(':', start);
        parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos) break;
        start = end + 1;
    }
    if (parts.size() < 4 || parts.size() > 5) failSpec("needs 4 or 5 fields");
    PolypSpec spec;
    if (parts[0] == "sessile") {
        spec.kind = PolypKind::Sessile;
    } else if (parts[0] == "pedunculated") {
        spec.kind = PolypKind::Pedunculated;
    } else {
        failSpec("kind '" + parts[0] + "' is neither sessile nor pedunculated");
    }
    auto number = [&](const std::string& field, const char* what) {
        double value = 0.0;
        const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
        if (field.empty() || result.ec != std::errc{} || result.ptr != field.data() + field.size() ||
            !std::isfinite(value)) {
            failSpec(std::string(what) + " '" + field + "' is not a number");
        }
        return value;
    };
    spec.diameterMm = number(parts[1], "diameter");
    spec.arcFraction = number(parts[2], "position");
    spec.angleDeg = number(parts[3], "angle");
    if (parts.size() == 5) spec.stalkLengthMm = number(parts[4], "stalk length");
    if (spec.diameterMm < 3.0 || spec.diameterMm > 15.0) failSpec("diameter must be 3..15 mm");
    if (spec.arcFraction < 0.0 || spec.arcFraction > 1.0) failSpec("position must be 0..1 along the centreline");
    return spec;
}

}  // namespace volumes
