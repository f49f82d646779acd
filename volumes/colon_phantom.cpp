#include "volumes/colon_phantom.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>

#include "volumes/parallel_for.h"
#include "volumes/phantom_polyps.h"
#include "volumes/phantom_tube.h"
#include "volumes/polyline.h"

namespace volumes {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// Voxels are classified in slabs of this many z layers (bounded scratch memory, one per thread).
constexpr int kSlabLayers = 16;

[[noreturn]] void fail(const std::string& problem) {
    throw VolumeError("colon phantom: " + problem);
}

/// SplitMix64's finaliser: a counter-based hash, so value n depends only on (seed, n).
std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/// Counter-based Gaussian noise: voxel n always gets the same value for a seed, whichever
/// thread computes it.
double gaussianAt(std::uint64_t seed, std::uint64_t n) {
    const std::uint64_t a = mix(seed * 0x632be59bd9b4e019ULL ^ n);
    const std::uint64_t b = mix(a);
    const double u1 = (static_cast<double>(a >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    const double u2 = static_cast<double>(b >> 11) * (1.0 / 9007199254740992.0);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

/// Uniform in [-1, 1) from (seed, n); its own multiplier keeps it independent of the noise.
double signedUnitAt(std::uint64_t seed, std::uint64_t n) {
    const std::uint64_t h = mix(seed * 0xd1342543de82ef95ULL ^ n);
    return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

std::string mm(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f mm", value);
    return text;
}

/// The centreline's control points in millimetres: ascending colon, hepatic flexure,
/// transverse colon, splenic flexure, descending colon (fractions of the grid's extent).
/// A shape seed moves each point by a hashed offset, then keeps it `marginMm` inside the grid;
/// the offsets (x at most 0.05 of the extent) cannot bring the caecum (x 0.28) to the left of
/// the rectal end (x 0.74), so the colon keeps its handedness.
std::vector<glm::dvec3> controlPointsMm(std::uint64_t shapeSeed, const glm::dvec3& extent, double marginMm) {
    const std::vector<glm::dvec3> controls = {{0.28, 0.50, 0.13}, {0.24, 0.42, 0.34}, {0.30, 0.58, 0.58},
                                              {0.36, 0.48, 0.80}, {0.55, 0.40, 0.84}, {0.70, 0.56, 0.72},
                                              {0.76, 0.46, 0.48}, {0.72, 0.52, 0.26}, {0.74, 0.48, 0.13}};
    const glm::dvec3 amplitude(0.05, 0.05, 0.03);
    std::vector<glm::dvec3> points;
    for (std::size_t i = 0; i < controls.size(); ++i) {
        glm::dvec3 c = controls[i];
        if (shapeSeed != 0) {
            for (int a = 0; a < 3; ++a) c[a] += amplitude[a] * signedUnitAt(shapeSeed, 3 * i + static_cast<std::size_t>(a));
        }
        glm::dvec3 p = c * extent;
        if (shapeSeed != 0) p = glm::clamp(p, glm::dvec3(marginMm), glm::max(extent - marginMm, glm::dvec3(marginMm)));
        points.push_back(p);
    }
    return points;
}

/// A collapse after validation: the lumen is closed over [closedStartMm, closedEndMm].
struct Collapse {
    double closedStartMm, closedEndMm;
    double taperStartMm() const { return closedStartMm - kCollapseTaperMm; }
    double taperEndMm() const { return closedEndMm + kCollapseTaperMm; }
};

/// Signed distance (mm, negative inside) to the body's elliptic outline in the x-y plane,
/// to first order: (q - 1) / |grad q| with q the ellipse's normalised radius.
double bodyDistance(const BodyTruth& body, double x, double y) {
    const double u = (x - body.centreMm.x) / body.semiAxesMm.x, v = (y - body.centreMm.y) / body.semiAxesMm.y;
    const double q = std::sqrt(u * u + v * v);
    if (q < 1e-9) return -std::min(body.semiAxesMm.x, body.semiAxesMm.y);
    const double gradient = std::hypot(u / body.semiAxesMm.x, v / body.semiAxesMm.y) / q;
    return (q - 1.0) / gradient;
}

/// The same first-order signed distance for a lung's ellipsoid.
double lungDistance(const LungTruth& lung, const glm::dvec3& p) {
    const glm::dvec3 u = (p - lung.centreMm) / lung.semiAxesMm;
    const double q = glm::length(u);
    if (q < 1e-9) return -std::min({lung.semiAxesMm.x, lung.semiAxesMm.y, lung.semiAxesMm.z});
    return (q - 1.0) / (glm::length(u / lung.semiAxesMm) / q);
}

/// Lung bases as a scan of the abdomen cuts them: two ellipsoids centred above the top face,
/// posterior (large y) and lateral, where the colon does not reach (fractions of the extent).
std::vector<LungTruth> lungBases(const glm::dvec3& extent) {
    const glm::dvec3 semiAxes = glm::dvec3(0.12, 0.08, 0.30) * extent;
    const double y = 0.78 * extent.y, z = 1.12 * extent.z;
    return {{"right", {0.30 * extent.x, y, z}, semiAxes}, {"left", {0.70 * extent.x, y, z}, semiAxes}};
}

/// Points on the part of a lung inside the grid: its ellipsoid surface below the top face and
/// the disc where the top face cuts it, about every millimetre. Whatever is nearest to the
/// lung lies nearest to one of these (to within the sampling step).
std::vector<glm::dvec3> lungBoundarySamples(const LungTruth& lung, double topMm) {
    std::vector<glm::dvec3> samples;
    const double largest = std::max({lung.semiAxesMm.x, lung.semiAxesMm.y, lung.semiAxesMm.z});
    const int around = std::max(16, static_cast<int>(std::ceil(2.0 * kPi * largest)));
    for (int a = 0; a <= around / 2; ++a) {
        const double polar = kPi * a / (around / 2);
        for (int b = 0; b < around; ++b) {
            const double azimuth = 2.0 * kPi * b / around;
            const glm::dvec3 p = lung.centreMm + lung.semiAxesMm * glm::dvec3(std::sin(polar) * std::cos(azimuth),
                                                                               std::sin(polar) * std::sin(azimuth),
                                                                               std::cos(polar));
            if (p.z <= topMm) samples.push_back(p);
        }
    }
    const double h = (topMm - lung.centreMm.z) / lung.semiAxesMm.z;
    if (std::abs(h) < 1.0) {
        const double scale = std::sqrt(1.0 - h * h);
        const int rings = static_cast<int>(std::ceil(largest * scale));
        for (int r = 0; r <= rings; ++r)
            for (int b = 0; b < around; ++b) {
                const double azimuth = 2.0 * kPi * b / around, f = scale * r / std::max(rings, 1);
                samples.push_back({lung.centreMm.x + f * lung.semiAxesMm.x * std::cos(azimuth),
                                   lung.centreMm.y + f * lung.semiAxesMm.y * std::sin(azimuth), topMm});
            }
    }
    return samples;
}

double polylineDistance(const std::vector<glm::dvec3>& line, const glm::dvec3& p) {
    double best = std::numeric_limits<double>::max(), t = 0.0;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, distanceToSegmentMm(p, line[i], line[i + 1], &t));
    return best;
}

/// Smallest lung-to-tube gap (mm): from the lungs to the outside of the colon's fat band.
double lungClearanceMm(const std::vector<LungTruth>& lungs, const std::vector<glm::dvec3>& line, double tubeMm,
                       double topMm) {
    double clearance = std::numeric_limits<double>::max();
    for (const LungTruth& lung : lungs)
        for (const glm::dvec3& p : lungBoundarySamples(lung, topMm))
            clearance = std::min(clearance, polylineDistance(line, p) - tubeMm);
    return clearance;
}

/// Does a polyp (on the wall at its arc, `radius` either side) reach into the arc range [a, b]?
bool polypOverlaps(const PolypTruth& polyp, double a, double b) {
    return std::abs(polyp.arcLengthMm - std::clamp(polyp.arcLengthMm, a, b)) < polyp.radiusMm;
}

/// What surrounds the colon, applied voxel by voxel after the tube: collapsed stretches and
/// fluid pools change what fills the lumen, lungs and the body outline what lies around it.
struct Anatomy {
    double lumenRadiusMm = 0.0, edgeWidthMm = 1.0;
    std::vector<Collapse> collapses;
    std::vector<FluidPoolTruth> pools;
    std::vector<LungTruth> lungs;
    bool hasBody = false;
    BodyTruth body;

    /// Radius of the air lumen at arc s: the full radius, tapering smoothly (smoothstep) to
    /// -edgeWidth in a collapse, so that not even the partial-volume ramp leaves air there.
    double airRadiusAt(double s) const {
        double closing = 0.0;  // 0: open, 1: closed
        for (const Collapse& c : collapses) {
            const double gap = std::max({c.closedStartMm - s, s - c.closedEndMm, 0.0}) / kCollapseTaperMm;
            if (gap < 1.0) closing = std::max(closing, 1.0 - gap * gap * (3.0 - 2.0 * gap));
        }
        return lumenRadiusMm - closing * (lumenRadiusMm + edgeWidthMm);
    }

    /// How much of a lumen voxel at arc s and height y is fluid (0..1): below the pool's level,
    /// with the partial-volume ramp across the level and at the pool's ends.
    double fluidFraction(double s, double y) const {
        double fraction = 0.0;
        for (const FluidPoolTruth& pool : pools) {
            const double e = edgeWidthMm;
            fraction = std::max(fraction, std::clamp(0.5 + (y - pool.levelYMm) / e, 0.0, 1.0) *
                                              std::clamp(0.5 + (s - pool.startArcMm) / e, 0.0, 1.0) *
                                              std::clamp(0.5 + (pool.endArcMm - s) / e, 0.0, 1.0));
        }
        return fraction;
    }

    /// Lungs replace the tissue around them; outside the body is air.
    double surround(const glm::dvec3& p, double hu, double lungHu, double airHu) const {
        for (const LungTruth& lung : lungs) {
            hu += std::clamp(0.5 - lungDistance(lung, p) / edgeWidthMm, 0.0, 1.0) * (lungHu - hu);
        }
        if (hasBody) hu += std::clamp(0.5 + bodyDistance(body, p.x, p.y) / edgeWidthMm, 0.0, 1.0) * (airHu - hu);
        return hu;
    }
};

/// The arc range over which a collapse leaves no air on the centreline: where the air radius
/// is below -edgeWidth / 2 (the partial-volume ramp's reach), found on the smoothstep taper.
std::array<double, 2> airlessArcRange(const Anatomy& anatomy, const Collapse& c) {
    double inside = 0.0, outside = kCollapseTaperMm;  // distance beyond the closed part
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (inside + outside);
        (anatomy.airRadiusAt(c.closedEndMm + mid) <= -0.5 * anatomy.edgeWidthMm ? inside : outside) = mid;
    }
    return {c.closedStartMm - inside, c.closedEndMm + inside};
}

/// Fails for collapse and pool parameters that cannot make sense, before any geometry.
void validateAnatomySpec(const ColonPhantomSpec& spec) {
    for (const CollapseSpec& c : spec.collapses) {
        if (!(c.arcFraction > 0.0 && c.arcFraction < 1.0))
            fail("collapse position " + std::to_string(c.arcFraction) + " is outside 0..1 (exclusive)");
        if (!(c.lengthMm > 0.0 && c.lengthMm < 1000.0))
            fail("collapse length " + std::to_string(c.lengthMm) + " mm must be positive (and under 1 m)");
    }
    for (const FluidPoolSpec& f : spec.fluidPools) {
        if (!(f.arcFraction >= 0.0 && f.arcFraction <= 1.0))
            fail("fluid pool position " + std::to_string(f.arcFraction) + " is outside 0..1");
        if (!(f.lengthMm > 0.0 && f.lengthMm < 1000.0))
            fail("fluid pool length " + std::to_string(f.lengthMm) + " mm must be positive (and under 1 m)");
        if (!(f.depthMm > 0.0 && f.depthMm < 2.0 * spec.lumenRadiusMm))
            fail("fluid pool depth " + std::to_string(f.depthMm) + " mm must be positive and less than the lumen's " +
                 std::to_string(2.0 * spec.lumenRadiusMm) + " mm diameter");
    }
}

/// Collapses along the centreline; each must leave open lumen on both sides, so that it splits
/// the air in two, and must not overlap another.
std::vector<Collapse> placeCollapses(const ColonPhantomSpec& spec, const Centreline& line) {
    std::vector<Collapse> collapses;
    for (const CollapseSpec& c : spec.collapses) {
        const double centre = c.arcFraction * line.length();
        const Collapse collapse{centre - 0.5 * c.lengthMm, centre + 0.5 * c.lengthMm};
        if (collapse.taperStartMm() < 5.0 || collapse.taperEndMm() > line.length() - 5.0) {
            fail("a collapse of " + mm(c.lengthMm) + " at position " + std::to_string(c.arcFraction) + " (with its " +
                 mm(kCollapseTaperMm) + " tapers) must leave 5 mm of open lumen at both ends of the " +
                 mm(line.length()) + " colon");
        }
        for (const Collapse& other : collapses) {
            if (collapse.taperStartMm() < other.taperEndMm() && other.taperStartMm() < collapse.taperEndMm())
                fail("collapses at " + mm(centre) + " and " + mm(0.5 * (other.closedStartMm + other.closedEndMm)) +
                     " overlap (tapers included)");
        }
        collapses.push_back(collapse);
    }
    return collapses;
}

/// Fluid pools with their levels: `depth` above the lowest point (largest y) of the lumen
/// surface in the pool's arc range. A pool may not reach into a collapse, where there is no
/// lumen to hold it.
std::vector<FluidPoolTruth> placeFluidPools(const ColonPhantomSpec& spec, const Centreline& line,
                                            const std::vector<Collapse>& collapses) {
    std::vector<FluidPoolTruth> pools;
    for (const FluidPoolSpec& f : spec.fluidPools) {
        const double centre = f.arcFraction * line.length();
        FluidPoolTruth pool;
        pool.startArcMm = std::max(0.0, centre - 0.5 * f.lengthMm);
        pool.endArcMm = std::min(line.length(), centre + 0.5 * f.lengthMm);
        double lowestMm = -std::numeric_limits<double>::max();
        for (std::size_t i = 0; i < line.points.size(); ++i) {
            if (line.arcMm[i] >= pool.startArcMm && line.arcMm[i] <= pool.endArcMm)
                lowestMm = std::max(lowestMm, line.points[i].y + spec.lumenRadiusMm);
        }
        pool.levelYMm = lowestMm - f.depthMm;
        for (const Collapse& c : collapses) {
            if (pool.startArcMm < c.taperEndMm() && c.taperStartMm() < pool.endArcMm)
                fail("the fluid pool over " + mm(pool.startArcMm) + " .. " + mm(pool.endArcMm) +
                     " reaches into the collapse over " + mm(c.taperStartMm()) + " .. " + mm(c.taperEndMm()));
        }
        pools.push_back(pool);
    }
    return pools;
}

/// The body outline; the colon with its fat band must lie inside it, clear of its ramp.
BodyTruth placeBody(const glm::dvec3& extent, const Centreline& line, double tubeMm, double edgeWidthMm) {
    const BodyTruth body{glm::dvec2(0.5 * extent.x, 0.5 * extent.y), glm::dvec2(0.48 * extent.x, 0.46 * extent.y)};
    for (const glm::dvec3& p : line.points) {
        for (int a = 0; a < 32; ++a) {
            const double angle = 2.0 * kPi * a / 32.0;
            if (bodyDistance(body, p.x + tubeMm * std::cos(angle), p.y + tubeMm * std::sin(angle)) > -edgeWidthMm)
                fail("the colon and its fat band (" + mm(tubeMm) + " around the centreline) do not fit inside the body outline");
        }
    }
    return body;
}

/// Lung bases; they must stay kMinLungClearanceMm clear of the colon's fat band and, with a
/// body, inside it, so neither the colon's air nor the air outside ever touches them.
std::vector<LungTruth> placeLungs(const glm::dvec3& extent, const Centreline& line, double tubeMm,
                                  const BodyTruth* body, double edgeWidthMm, double& clearanceMm) {
    constexpr double kMinLungClearanceMm = 3.0;
    std::vector<LungTruth> lungs = lungBases(extent);
    clearanceMm = lungClearanceMm(lungs, line.points, tubeMm, extent.z);
    if (clearanceMm < kMinLungClearanceMm) {
        fail("the lung bases come within " + mm(clearanceMm) + " of the colon's fat band; they need " +
             mm(kMinLungClearanceMm) + " of clearance (try another shape seed, or no lungs)");
    }
    for (const LungTruth& lung : lungs)
        for (const glm::dvec3& p : lungBoundarySamples(lung, extent.z)) {
            const bool inGrid = p.x >= 2.0 * edgeWidthMm && p.x <= extent.x - 2.0 * edgeWidthMm &&
                                p.y >= 2.0 * edgeWidthMm && p.y <= extent.y - 2.0 * edgeWidthMm;
            if (!inGrid || (body && bodyDistance(*body, p.x, p.y) > -2.0 * edgeWidthMm))
                fail("the " + lung.side + " lung base does not fit inside the body");
        }
    return lungs;
}

/// Everything around the colon that the spec turns on, with its ground truth in `phantom`.
Anatomy placeAnatomy(const ColonPhantomSpec& spec, const Centreline& line, const glm::dvec3& extent,
                     ColonPhantom& phantom) {
    Anatomy anatomy;
    anatomy.lumenRadiusMm = spec.lumenRadiusMm;
    anatomy.edgeWidthMm = spec.edgeWidthMm;
    const double tubeMm = spec.lumenRadiusMm + spec.wallThicknessMm + spec.fatThicknessMm;
    anatomy.collapses = placeCollapses(spec, line);
    for (const Collapse& c : anatomy.collapses) phantom.collapsedArcMm.push_back(airlessArcRange(anatomy, c));
    anatomy.pools = placeFluidPools(spec, line, anatomy.collapses);
    phantom.fluidPools = anatomy.pools;
    anatomy.hasBody = spec.hasBody;
    if (spec.hasBody) anatomy.body = placeBody(extent, line, tubeMm, spec.edgeWidthMm);
    phantom.body = anatomy.body;
    if (spec.hasLung) {
        anatomy.lungs = placeLungs(extent, line, tubeMm, spec.hasBody ? &anatomy.body : nullptr, spec.edgeWidthMm,
                                   phantom.lungClearanceMm);
    }
    phantom.lungs = anatomy.lungs;
    return anatomy;
}

}  // namespace

std::vector<PolypSpec> ColonPhantomSpec::defaultPolyps() {
    return {{PolypKind::Sessile, 6.0, 0.15, 30.0, 0.0},
            {PolypKind::Pedunculated, 8.0, 0.33, 150.0, 1.5},
            {PolypKind::Sessile, 3.0, 0.50, 270.0, 0.0},
            {PolypKind::Sessile, 12.0, 0.68, 90.0, 0.0},
            {PolypKind::Pedunculated, 6.0, 0.85, 210.0, 3.0}};
}

ColonPhantomSpec ColonPhantomSpec::withAnatomy(ColonPhantomSpec base) {
    base.hasBody = true;
    base.hasLung = true;
    // Arc lengths for the default colon at 128^3 x 1.2 mm (291 mm; 256^3 x 0.6 mm is within 1%):
    // the collapse closes over 116..128 mm (tapers 111..133, no air on the centreline
    // 115.7..128.9), between the polyps at 0.33 (96 mm, 8 mm across) and 0.50 (146 mm, 3 mm).
    // The pool covers 49..89 mm, round the hepatic flexure, where the colon sags lowest
    // (largest y) so the fluid gathers as it would, half-way between the polyps at 0.15
    // (44 mm, 6 mm) and 0.33; the gap stays wider than 40 mm for shape seeds that shorten the
    // colon by up to 10%.
    base.collapses = {{0.42, 12.0}};
    base.fluidPools = {{0.238, 40.0, 6.0}};
    return base;
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

    validateAnatomySpec(spec);

    // Centreline from the caecum (ascending colon, patient's right) to the rectal end
    // (descending colon, left).
    const Centreline line(smoothPolyline(controlPointsMm(spec.shapeSeed, extent, outerMm + spec.fatThicknessMm)));
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

    // Listed polyps: on the wall at their arc and angle, base normal pointing into the lumen.
    // Random ones are laid out once the folds are placed, since some stand on them.
    if (spec.randomPolypCount < 0 || spec.randomPolypCount > kMaxRandomPolyps) {
        fail(std::to_string(spec.randomPolypCount) + " random polyps asked for; 1.." +
             std::to_string(kMaxRandomPolyps) + " fit in the colon (0: the listed polyps)");
    }
    const bool isRandomLayout = spec.randomPolypCount > 0;
    std::vector<PolypSolid> polyps;
    for (const PolypSpec& p : isRandomLayout ? std::vector<PolypSpec>() : spec.polyps) {
        if (!(p.diameterMm >= 3.0 && p.diameterMm <= 15.0))
            fail("polyp diameter " + std::to_string(p.diameterMm) + " mm is outside 3..15 mm");
        if (!(p.arcFraction >= 0.0 && p.arcFraction <= 1.0))
            fail("polyp position " + std::to_string(p.arcFraction) + " is outside 0..1");
        if (!std::isfinite(p.angleDeg)) fail("polyp angle is not finite");
        const PolypPlacement placement{p.kind, p.diameterMm, p.arcFraction * line.length(), p.angleDeg,
                                       p.stalkLengthMm, false};
        polyps.push_back(makePolypSolid(spec, line, {}, placement));
        phantom.polyps.push_back(polyps.back().truth);
    }

    Anatomy anatomy = placeAnatomy(spec, line, extent, phantom);
    const auto requireClearOfAnatomy = [&] {
        for (const PolypTruth& polyp : phantom.polyps) {
            for (const Collapse& c : anatomy.collapses) {
                if (polypOverlaps(polyp, c.taperStartMm(), c.taperEndMm()))
                    fail("a polyp at " + mm(polyp.arcLengthMm) + " along the colon lies in the collapse over " +
                         mm(c.taperStartMm()) + " .. " + mm(c.taperEndMm()) + " (there is no lumen there to see it in)");
            }
            for (const FluidPoolTruth& pool : anatomy.pools) {
                if (polypOverlaps(polyp, pool.startArcMm, pool.endArcMm))
                    fail("a polyp at " + mm(polyp.arcLengthMm) + " along the colon lies in the fluid pool over " +
                         mm(pool.startArcMm) + " .. " + mm(pool.endArcMm) + " (its truth assumes it stands in air)");
            }
        }
    };
    requireClearOfAnatomy();

    // Folds: evenly spaced, turning by a third of a turn each, kept clear of the listed polyps
    // (none for a random layout: its folds stay where they are without polyps) and of
    // collapses (a fold in a closed lumen would only blur where it closes).
    std::vector<Fold> folds;
    int foldIndex = 0;
    for (double s = 0.5 * spec.foldSpacingMm; s < line.length() - 0.5 * spec.foldSpacingMm;
         s += spec.foldSpacingMm, ++foldIndex) {
        const bool isClear = std::none_of(polyps.begin(), polyps.end(), [&](const PolypSolid& p) {
            return std::abs(p.truth.arcLengthMm - s) < p.truth.radiusMm + spec.foldHalfWidthMm + 3.0;
        }) && std::none_of(anatomy.collapses.begin(), anatomy.collapses.end(), [&](const Collapse& c) {
            return s > c.taperStartMm() - spec.foldHalfWidthMm - 3.0 && s < c.taperEndMm() + spec.foldHalfWidthMm + 3.0;
        });
        if (isClear) {
            folds.push_back({s, foldIndex * 2.0 * kPi / 3.0});
            phantom.foldArcLengthsMm.push_back(s);
        }
    }

    if (isRandomLayout) {
        std::vector<std::array<double, 2>> blockedArcMm;
        for (const Collapse& c : anatomy.collapses) blockedArcMm.push_back({c.taperStartMm(), c.taperEndMm()});
        for (const FluidPoolTruth& pool : anatomy.pools) blockedArcMm.push_back({pool.startArcMm, pool.endArcMm});
        polyps = layOutRandomSolids(spec, line, folds, blockedArcMm);
        for (const PolypSolid& solid : polyps) phantom.polyps.push_back(solid.truth);
        requireClearOfAnatomy();
    }

    // Classify voxels slab by slab: nearest centreline point in a band around the tube, then
    // HU from the signed distances.
    const double bandMm = outerMm + spec.fatThicknessMm + 2.0 * spec.edgeWidthMm;
    volume.hu.assign(volume.voxelCount(), spec.tissueHu);
    std::vector<float> noise(spec.noiseSigmaHu > 0.0 ? volume.voxelCount() : 0);
    const int slabs = (volume.dims[2] + kSlabLayers - 1) / kSlabLayers;
    const std::size_t layerVoxels = static_cast<std::size_t>(volume.dims[0]) * volume.dims[1];
    const glm::dvec3 spacing = volume.spacingMm;
    const bool hasSurroundings = anatomy.hasBody || !anatomy.lungs.empty();
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
                        const double d = distanceToSegmentMm(glm::dvec3(iv, j, k) * spacing, a, b, &t);
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
                    const glm::dvec3 p = glm::dvec3(iv, j, k) * spacing;
                    if (bestDistance[local] > bandMm) {  // plain soft tissue, unless lung or outside
                        if (hasSurroundings)
                            volume.hu[n] = static_cast<int16_t>(
                                std::lround(anatomy.surround(p, spec.tissueHu, spec.lungHu, spec.lumenHu)));
                        continue;
                    }
                    glm::dvec3 point, tangent, normal;
                    line.frameAt(bestArc[local], point, tangent, normal);
                    const glm::dvec3 radial = p - point;
                    const double theta =
                        std::atan2(glm::dot(radial, glm::cross(tangent, normal)), glm::dot(radial, normal));
                    const double fold = foldIntrusion(spec, folds, bestArc[local], theta);
                    // The wall and fat keep their place in a collapse; only the air lumen closes.
                    const double lumenDistance = bestDistance[local] - (spec.lumenRadiusMm - fold);
                    const double openDistance = bestDistance[local] - (anatomy.airRadiusAt(bestArc[local]) - fold);
                    const double polyp = polypDistance(polyps, p, bestDistance[local]);
                    const double airDistance = std::max(openDistance, -polyp);
                    // Tissue value: wall, then the fat band, then soft tissue; polyps are tissue.
                    const double e = spec.edgeWidthMm;
                    const double fatWeight =
                        std::clamp((lumenDistance - spec.wallThicknessMm) / e + 0.5, 0.0, 1.0) *
                        std::clamp((spec.wallThicknessMm + spec.fatThicknessMm - lumenDistance) / e + 0.5, 0.0, 1.0);
                    double tissue = spec.tissueHu + fatWeight * (spec.fatHu - spec.tissueHu);
                    tissue += std::clamp(0.5 - polyp / e, 0.0, 1.0) * (spec.tissueHu - tissue);
                    const double airWeight = std::clamp(0.5 - airDistance / e, 0.0, 1.0);
                    // Tagged fluid takes the place of air in the lumen's lowest part.
                    const double lumen =
                        spec.lumenHu + anatomy.fluidFraction(bestArc[local], p.y) * (spec.fluidHu - spec.lumenHu);
                    double hu = tissue + airWeight * (lumen - tissue);
                    if (hasSurroundings) hu = anatomy.surround(p, hu, spec.lungHu, spec.lumenHu);
                    volume.hu[n] = static_cast<int16_t>(std::lround(hu));
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

}  // namespace volumes
