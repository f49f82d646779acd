#include "colon/polyp_shape_prediction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace colon {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// An orthonormal pair perpendicular to the unit vector `n`.
void tangentPair(const glm::dvec3& n, glm::dvec3& a, glm::dvec3& b) {
    const glm::dvec3 other = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    a = glm::normalize(other - glm::dot(other, n) * n);
    b = glm::cross(n, a);
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

/// The map at `d`, or nothing (a zero vector) where the display does not show `d`.
glm::dvec3 mapAt(const SceneFromDisplay& map, const glm::dvec3& d) {
    const glm::dvec3 s = map(d);
    const double length = glm::length(s);
    return length > 0.0 && std::isfinite(length) ? s / length : glm::dvec3(0.0);
}

/// The map's derivative at `d` along the tangent pair (a, b): two columns, by central differences.
bool derivativeAt(const SceneFromDisplay& map, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
                  glm::dvec3& alongA, glm::dvec3& alongB) {
    constexpr double h = 2e-4;  // radians: a fraction of a 1024^2 cube map's texel, which is 1.5e-3
    const glm::dvec3 ap = mapAt(map, glm::normalize(d + h * a)), am = mapAt(map, glm::normalize(d - h * a));
    const glm::dvec3 bp = mapAt(map, glm::normalize(d + h * b)), bm = mapAt(map, glm::normalize(d - h * b));
    if (ap == glm::dvec3(0.0) || am == glm::dvec3(0.0) || bp == glm::dvec3(0.0) || bm == glm::dvec3(0.0)) return false;
    alongA = (ap - am) / (2.0 * h);
    alongB = (bp - bm) / (2.0 * h);
    return true;
}

/// The display direction the map sends to `scene`: the best of a search over the sphere, then
/// Newton's method on the tangent plane (least squares, each step halved until it helps).
/// Returns the angle left between its image and `scene`.
double invert(const SceneFromDisplay& map, const glm::dvec3& scene, glm::dvec3& display) {
    // A Fibonacci sphere of directions: about 1.6 degrees apart.
    constexpr int kSearch = 16000;
    double best = std::numeric_limits<double>::max();
    // Takes `candidate` as the display direction where the map sends it nearer `scene` than the
    // best so far; a direction the map shows nothing at is passed over.
    const auto isTakenAsNearer = [&](const glm::dvec3& candidate) {
        const glm::dvec3 s = mapAt(map, candidate);
        if (s == glm::dvec3(0.0)) return false;
        const double angle = angleBetween(s, scene);
        if (angle >= best) return false;
        best = angle;
        display = candidate;
        return true;
    };
    for (int i = 0; i < kSearch; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / kSearch;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = i * kPi * (3.0 - std::sqrt(5.0));
        isTakenAsNearer(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
    }
    if (best == std::numeric_limits<double>::max()) return best;
    for (int iteration = 0; iteration < 40 && best > 1e-10; ++iteration) {
        glm::dvec3 a, b, alongA, alongB;
        tangentPair(display, a, b);
        if (!derivativeAt(map, display, a, b, alongA, alongB)) break;
        const glm::dvec3 residual = scene - mapAt(map, display);
        const glm::dmat2 normal(glm::dot(alongA, alongA), glm::dot(alongA, alongB), glm::dot(alongA, alongB),
                                glm::dot(alongB, alongB));
        if (!(std::abs(glm::determinant(normal)) > 1e-24)) break;
        glm::dvec2 step = glm::inverse(normal) * glm::dvec2(glm::dot(alongA, residual), glm::dot(alongB, residual));
        if (glm::length(step) > 0.2) step *= 0.2 / glm::length(step);
        bool isBetter = false;
        for (int halving = 0; halving < 12 && !isBetter; ++halving, step *= 0.5) {
            isBetter = isTakenAsNearer(glm::normalize(display + step.x * a + step.y * b));
        }
        if (!isBetter) break;
    }
    return best;
}

/// The view of `polyp` (its frame's origin the viewpoint), sampled on the tangent plane at
/// `centre` over [-halfWidth, halfWidth]^2 (gnomonic coordinates) through `map`: each sample's
/// display direction, solid angle and hit on the polyp. `isTouchingBorder` says whether the
/// polyp's image reaches the grid's outermost ring.
std::vector<ViewSample> sampledView(const SceneFromDisplay& map, const glm::dvec3& centre, double halfWidth,
                                    const PolypSurface& polyp, int across, bool& isTouchingBorder) {
    glm::dvec3 a, b;
    tangentPair(centre, a, b);
    const double cell = 2.0 * halfWidth / across;
    std::vector<ViewSample> samples;
    samples.reserve(static_cast<std::size_t>(across) * static_cast<std::size_t>(across) / 2);
    isTouchingBorder = false;
    for (int j = 0; j < across; ++j) {
        for (int i = 0; i < across; ++i) {
            const double u = -halfWidth + (i + 0.5) * cell, v = -halfWidth + (j + 0.5) * cell;
            const glm::dvec3 d = glm::normalize(centre + u * a + v * b);
            const glm::dvec3 s = mapAt(map, d);
            if (s == glm::dvec3(0.0)) continue;
            glm::dvec3 hit;
            if (!firstPolypHit(polyp, glm::dvec3(0.0), s, hit)) continue;
            ViewSample sample;
            sample.direction = d;
            const double q = 1.0 + u * u + v * v;
            sample.solidAngleSr = cell * cell / (q * std::sqrt(q));
            sample.isHit = true;
            sample.hitMm = hit;
            samples.push_back(sample);
            if (i == 0 || j == 0 || i == across - 1 || j == across - 1) isTouchingBorder = true;
        }
    }
    return samples;
}

/// The measures of the polyp's view through `map`, on a grid grown until the image fits; the
/// painted grid faces the line of sight to its aim point.
ShapeMeasures measuredView(const SceneFromDisplay& map, const glm::dvec3& centre, double halfWidth,
                           const PolypSurface& polyp, int across, double& extentRad) {
    const double tolerance = 1e-9 * std::max(1.0, glm::length(polyp.centreMm));
    const glm::dvec3 lineOfSight = glm::normalize(polypAimPointOf(polyp));
    for (int attempt = 0;; ++attempt) {
        bool isTouchingBorder = false;
        const std::vector<ViewSample> samples = sampledView(map, centre, halfWidth, polyp, across, isTouchingBorder);
        if (isTouchingBorder && attempt < 4 && halfWidth < 1.5) {
            halfWidth = std::min(1.6 * halfWidth, 1.5);
            continue;
        }
        extentRad = 0.0;
        for (const ViewSample& sample : samples) extentRad = std::max(extentRad, angleBetween(sample.direction, centre));
        return measurePolypShape(samples, polyp, tolerance, lineOfSight);
    }
}

}  // namespace

PredictedShape predictPolypShape(const SceneFromDisplay& sceneFromDisplay, const PolypSurface& polyp, int samplesAcross) {
    // A ball about the aim point that holds the polyp: its sphere, or a sessile or flat polyp's
    // cap (its base's radius and half its height about the cap's middle).
    const glm::dvec3 aim = polypAimPointOf(polyp);
    double bound = polyp.sphereRadius();
    if (polyp.isSessile) {
        const double capHeight = polyp.sphereRadius() - glm::dot(polyp.baseMm - polyp.centreMm, polyp.baseNormal);
        bound = std::sqrt(0.25 * polyp.diameterMm * polyp.diameterMm + 0.25 * capHeight * capHeight);
    }
    const double distance = glm::length(aim);
    if (!(distance > bound) || !std::isfinite(distance) || !(std::asin(bound / distance) <= kPi / 6.0)) {
        throw std::invalid_argument("polyp shape prediction: the polyp must lie off the viewpoint, within 30 degrees of its aim");
    }
    if (samplesAcross < 32) throw std::invalid_argument("polyp shape prediction: at least 32 samples across");
    const glm::dvec3 scene = aim / distance;
    const double extent = std::asin(bound / distance);
    PredictedShape prediction;
    double unused = 0.0;
    const SceneFromDisplay identity = [](const glm::dvec3& d) { return d; };
    prediction.reference = measuredView(identity, scene, 1.3 * std::tan(extent), polyp, samplesAcross, unused);

    glm::dvec3 display(0.0);
    if (!(invert(sceneFromDisplay, scene, display) < 1e-6)) return prediction;
    prediction.isFound = true;
    prediction.displayDirection = display;
    // The grid's first size from the map's least stretch there (the image's longest radius).
    glm::dvec3 a, b, alongA, alongB;
    tangentPair(display, a, b);
    double leastStretch = 1.0;
    if (derivativeAt(sceneFromDisplay, display, a, b, alongA, alongB)) {
        const double aa = glm::dot(alongA, alongA), bb = glm::dot(alongB, alongB), ab = glm::dot(alongA, alongB);
        const double half = 0.5 * (aa + bb), root = std::sqrt(std::max(0.0, 0.25 * (aa - bb) * (aa - bb) + ab * ab));
        leastStretch = std::sqrt(std::max(half - root, 1e-12));
    }
    const double halfWidth = std::min(1.3 * std::tan(extent) / leastStretch, 1.5);
    prediction.view = measuredView(sceneFromDisplay, display, halfWidth, polyp, samplesAcross, prediction.displayRadiusRad);
    const auto relative = [](double value, double reference) { return std::abs(value - reference) / reference; };
    if (prediction.view.pixels >= 3 && prediction.reference.pixels >= 3) {
        prediction.aspectError = relative(prediction.view.aspect, prediction.reference.aspect);
        prediction.circularityError = relative(prediction.view.circularity, prediction.reference.circularity);
        prediction.gridAngleErrorDeg = std::abs(prediction.view.gridAngleDeg - prediction.reference.gridAngleDeg);
    }
    return prediction;
}

PredictedShape predictPolypShape(const SceneFromDisplay& sceneFromDisplay, const glm::dvec3& sceneDirection,
                                 double angularRadiusRad, int samplesAcross) {
    if (!(glm::length(sceneDirection) > 0.0) || !std::isfinite(glm::length(sceneDirection))) {
        throw std::invalid_argument("polyp shape prediction: the polyp's direction is zero or not finite");
    }
    if (!(angularRadiusRad > 0.0 && angularRadiusRad <= kPi / 6.0)) {
        throw std::invalid_argument("polyp shape prediction: the angular radius must be in (0, 30] degrees");
    }
    // A sphere at unit distance, whole (as a pedunculated polyp's head): a circle seen from here.
    PolypSurface sphere;
    sphere.isSessile = false;
    sphere.diameterMm = 2.0 * std::sin(angularRadiusRad);
    sphere.centreMm = glm::normalize(sceneDirection);
    sphere.baseMm = sphere.centreMm;
    sphere.baseNormal = -sphere.centreMm;
    return predictPolypShape(sceneFromDisplay, sphere, samplesAcross);
}

}  // namespace colon
