#include "colon/polyp_shape.h"

#include <algorithm>
#include <cmath>

namespace colon {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// An orthonormal basis of the plane perpendicular to `normal`, its first axis as close to
/// `hint` as it can be; e2 = e1 x normal, so that looking along `normal` with e1 to the right,
/// e2 points up.
void tangentBasis(const glm::dvec3& normal, const glm::dvec3& hint, glm::dvec3& e1, glm::dvec3& e2) {
    glm::dvec3 a = hint - glm::dot(hint, normal) * normal;
    if (glm::length(a) < 1e-9) {
        const glm::dvec3 other = std::abs(normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        a = other - glm::dot(other, normal) * normal;
    }
    e1 = glm::normalize(a);
    e2 = glm::cross(e1, normal);
}

/// Least-squares gradient of f over points p (weights w): f ~ f0 + g . (p - mean).
glm::dvec2 fittedGradient(const std::vector<glm::dvec2>& p, const std::vector<double>& f, const std::vector<double>& w) {
    double sw = 0.0;
    glm::dvec2 mean(0.0);
    double meanF = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        sw += w[i];
        mean += w[i] * p[i];
        meanF += w[i] * f[i];
    }
    mean /= sw;
    meanF /= sw;
    glm::dmat2 normal(0.0);
    glm::dvec2 rhs(0.0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const glm::dvec2 d = p[i] - mean;
        normal += w[i] * glm::outerProduct(d, d);
        rhs += w[i] * (f[i] - meanF) * d;
    }
    if (std::abs(glm::determinant(normal)) < 1e-300) return glm::dvec2(0.0);
    return glm::inverse(normal) * rhs;
}

}  // namespace

double polypToleranceMm(const glm::dvec3& spacingMm) {
    return 0.25 * std::max({spacingMm.x, spacingMm.y, spacingMm.z}) + 0.1;
}

ShapeMeasures measurePolypShape(const std::vector<ViewSample>& samples, const PolypSurface& polyp, double toleranceMm,
                                const glm::dvec3& gridNormal) {
    ShapeMeasures measures;
    std::vector<const ViewSample*> onPolyp;
    glm::dvec3 sum(0.0);
    for (const ViewSample& sample : samples) {
        if (!sample.isHit || !isOnPolyp(polyp, sample.hitMm, toleranceMm)) continue;
        onPolyp.push_back(&sample);
        sum += sample.solidAngleSr * sample.direction;
    }
    measures.pixels = static_cast<int>(onPolyp.size());
    measures.pixelsAcross = 2.0 * std::sqrt(static_cast<double>(onPolyp.size()) / kPi);
    if (onPolyp.size() < 3 || !(glm::length(sum) > 0.0)) return measures;
    const glm::dvec3 centre = glm::normalize(sum);
    measures.centreDirection = centre;
    glm::dvec3 e1, e2;
    tangentBasis(centre, glm::dvec3(1.0, 0.0, 0.0), e1, e2);

    // Gnomonic projection: a pixel of solid angle dOmega at angle t from the centre covers
    // dOmega / cos^3 t of the tangent plane.
    std::vector<glm::dvec2> points;
    std::vector<double> weights, capU, capV;
    glm::dvec3 t1, t2;
    tangentBasis(glm::normalize(gridNormal), glm::dvec3(0.0, 0.0, 1.0), t1, t2);
    for (const ViewSample* sample : onPolyp) {
        const double c = glm::dot(sample->direction, centre);
        if (!(c > 0.05)) continue;  // beyond 87 degrees of the centre: not one polyp's view
        points.push_back(glm::dvec2(glm::dot(sample->direction, e1), glm::dot(sample->direction, e2)) / c);
        weights.push_back(sample->solidAngleSr / (c * c * c));
        const glm::dvec3 offset = sample->hitMm - polyp.centreMm;
        capU.push_back(glm::dot(offset, t1));
        capV.push_back(glm::dot(offset, t2));
    }
    double area = 0.0;
    glm::dvec2 mean(0.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        area += weights[i];
        mean += weights[i] * points[i];
    }
    mean /= area;
    double sxx = 0.0, syy = 0.0, sxy = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::dvec2 d = points[i] - mean;
        sxx += weights[i] * d.x * d.x;
        syy += weights[i] * d.y * d.y;
        sxy += weights[i] * d.x * d.y;
    }
    // Eigenvalues of [[sxx, sxy], [sxy, syy]] (second moments, not normalised by the area).
    const double half = 0.5 * (sxx + syy);
    const double root = std::sqrt(std::max(0.0, 0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy));
    const double major = half + root, minor = std::max(half - root, 1e-300);
    measures.areaSr = area;
    measures.aspect = std::sqrt(major / minor);
    double orientation = 0.5 * std::atan2(2.0 * sxy, sxx - syy) * 180.0 / kPi;
    if (orientation < 0.0) orientation += 180.0;
    measures.orientationDeg = orientation;
    measures.circularity = area * area / (2.0 * kPi * (sxx + syy));
    // The grid's angle where it is painted: at the cap's middle (within half the polyp's radius
    // of its centroid), where the cap's coordinates are close to linear in the view; over the
    // whole polyp the fit would also measure how the sphere curves away at its rim.
    const double nearCentre = 0.5 * std::sqrt(area / kPi);
    std::vector<glm::dvec2> centralPoints;
    std::vector<double> centralWeights, centralU, centralV;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (glm::length(points[i] - mean) > nearCentre) continue;
        centralPoints.push_back(points[i]);
        centralWeights.push_back(weights[i]);
        centralU.push_back(capU[i]);
        centralV.push_back(capV[i]);
    }
    if (centralPoints.size() < 3) {
        centralPoints = points;
        centralWeights = weights;
        centralU = capU;
        centralV = capV;
    }
    const glm::dvec2 gu = fittedGradient(centralPoints, centralU, centralWeights);
    const glm::dvec2 gv = fittedGradient(centralPoints, centralV, centralWeights);
    const double lengths = glm::length(gu) * glm::length(gv);
    measures.gridAngleDeg =
        lengths > 0.0 ? std::acos(std::clamp(glm::dot(gu, gv) / lengths, -1.0, 1.0)) * 180.0 / kPi : 0.0;
    return measures;
}

RgbaImage tangentPlaneCrop(const std::vector<ViewSample>& samples, const glm::dvec3& centreDirection,
                           const glm::dvec3& right, double halfWidth, int size) {
    RgbaImage image{size, size, std::vector<uint8_t>(static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 4, 0)};
    glm::dvec3 e1, e2;
    tangentBasis(centreDirection, right, e1, e2);
    // Nearest sample per output pixel: splat every sample, keep the one nearest the pixel's centre.
    std::vector<double> best(static_cast<std::size_t>(size) * static_cast<std::size_t>(size), 1e300);
    const double scale = 0.5 * size / halfWidth;
    for (const ViewSample& sample : samples) {
        const double c = glm::dot(sample.direction, centreDirection);
        if (!(c > 0.1)) continue;
        const glm::dvec2 p = glm::dvec2(glm::dot(sample.direction, e1), glm::dot(sample.direction, e2)) / c;
        // Columns along e1 (the view's right), rows down along -e2 (its up).
        const double x = 0.5 * size + p.x * scale, y = 0.5 * size - p.y * scale;
        const double footprint = std::sqrt(sample.solidAngleSr) / (c * c) * scale;  // the pixel's size here
        const int reach = std::clamp(static_cast<int>(std::ceil(footprint)), 1, 8);
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
                const int column = static_cast<int>(std::floor(x)) + dx, row = static_cast<int>(std::floor(y)) + dy;
                if (column < 0 || row < 0 || column >= size || row >= size) continue;
                const double distance = std::hypot(column + 0.5 - x, row + 0.5 - y);
                if (distance > footprint + 0.75) continue;
                const std::size_t at = static_cast<std::size_t>(row) * static_cast<std::size_t>(size) + static_cast<std::size_t>(column);
                if (distance >= best[at]) continue;
                best[at] = distance;
                std::copy(sample.rgba.begin(), sample.rgba.end(), image.rgba.begin() + static_cast<std::ptrdiff_t>(at * 4));
            }
    }
    for (std::size_t n = 3; n < image.rgba.size(); n += 4) image.rgba[n] = 255;
    return image;
}

}  // namespace colon
