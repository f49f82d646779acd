/// @brief Least-squares holomorphic quadratic fits per vertex and their barycentric blend.
#include "conformal/holomorphic_interpolation.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

using Complex = std::complex<double>;

/// Fits delta ~ a w + b w^2 to samples (w_j, delta_j) by complex least squares; falls back to
/// b = 0 when the samples cannot tell the quadratic term apart.
void fitQuadratic(const std::vector<Complex>& w, const std::vector<Complex>& delta, Complex& a, Complex& b) {
    double s11 = 0.0, s22 = 0.0;
    Complex s12(0.0), r1(0.0), r2(0.0);
    for (std::size_t j = 0; j < w.size(); ++j) {
        const Complex w2 = w[j] * w[j];
        s11 += std::norm(w[j]);
        s22 += std::norm(w2);
        s12 += std::conj(w[j]) * w2;
        r1 += std::conj(w[j]) * delta[j];
        r2 += std::conj(w2) * delta[j];
    }
    a = Complex(0.0);
    b = Complex(0.0);
    if (!(s11 > 0.0)) return;
    const double det = s11 * s22 - std::norm(s12);
    constexpr double kRelativeConditioning = 1e-6;
    if (w.size() >= 3 && det > kRelativeConditioning * s11 * s22) {
        a = (s22 * r1 - s12 * r2) / det;
        b = (s11 * r2 - std::conj(s12) * r1) / det;
    } else {
        a = r1 / s11;
    }
}

std::vector<std::vector<int>> neighboursOf(const TriangleMesh& mesh) {
    std::vector<std::vector<int>> neighbours(mesh.positions.size());
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            for (const int other : {tri[(k + 1) % 3], tri[(k + 2) % 3]}) {
                auto& list = neighbours[tri[k]];
                bool isKnown = false;
                for (const int n : list) isKnown = isKnown || n == other;
                if (!isKnown) list.push_back(other);
            }
        }
    }
    return neighbours;
}

/// Per triangle, the singular point within kSingularReach mesh spacings of one of its
/// vertices, or -1.
std::vector<int> singularTriangles(const TriangleMesh& mesh, const std::vector<SingularPoint>& singular,
                                   const std::vector<std::vector<int>>& neighbours) {
    constexpr double kSingularReach = 2.5;
    std::vector<int> ofVertex(mesh.positions.size(), -1);
    for (std::size_t k = 0; k < singular.size(); ++k) {
        const glm::dvec3 centre = mesh.positions[singular[k].vertex];
        double spacing = 0.0;
        for (const int j : neighbours[singular[k].vertex]) spacing += glm::length(mesh.positions[j] - centre);
        spacing /= static_cast<double>(std::max<std::size_t>(neighbours[singular[k].vertex].size(), 1));
        // Walk outwards from the singular vertex so that only its own side of a slit is taken.
        std::vector<int> front = {singular[k].vertex};
        ofVertex[singular[k].vertex] = static_cast<int>(k);
        for (std::size_t i = 0; i < front.size(); ++i) {
            for (const int j : neighbours[front[i]]) {
                if (ofVertex[j] >= 0 || glm::length(mesh.positions[j] - centre) > kSingularReach * spacing) continue;
                ofVertex[j] = static_cast<int>(k);
                front.push_back(j);
            }
        }
    }
    std::vector<int> ofTriangle(mesh.triangles.size(), -1);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (const int v : mesh.triangles[t]) {
            if (ofVertex[v] >= 0) ofTriangle[t] = ofVertex[v];
        }
    }
    return ofTriangle;
}

}  // namespace

SphereChart::SphereChart(const glm::dvec3& point) : centre(glm::normalize(point)) {
    const glm::dvec3 helper = std::abs(centre.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    e1 = glm::normalize(glm::cross(helper, centre));
    e2 = glm::cross(centre, e1);
}

Complex SphereChart::chartFromDirection(const glm::dvec3& x) const {
    return Complex(glm::dot(x, e1), glm::dot(x, e2)) / (1.0 + glm::dot(x, centre));
}

glm::dvec3 SphereChart::directionFromChart(Complex w) const {
    const double r2 = std::norm(w);
    return ((1.0 - r2) * centre + 2.0 * (w.real() * e1 + w.imag() * e2)) / (1.0 + r2);
}

SphereToPlaneInterpolant::SphereToPlaneInterpolant(const TriangleMesh& sphere, const std::vector<Complex>& values,
                                                   const std::vector<SingularPoint>& singular)
    : mMesh(&sphere), mValues(&values), mSingular(singular) {
    const auto neighbours = neighboursOf(sphere);
    mSingularOfTriangle = singularTriangles(sphere, singular, neighbours);
    const std::size_t n = sphere.positions.size();
    mCharts.resize(n);
    mLinear.assign(n, Complex(0.0));
    mQuadratic.assign(n, Complex(0.0));
    std::vector<Complex> w;
    std::vector<Complex> delta;
    for (std::size_t v = 0; v < n; ++v) {
        mCharts[v] = SphereChart(sphere.positions[v]);
        w.clear();
        delta.clear();
        for (const int j : neighbours[v]) {
            w.push_back(mCharts[v].chartFromDirection(sphere.positions[j]));
            delta.push_back(values[j] - values[v]);
        }
        fitQuadratic(w, delta, mLinear[v], mQuadratic[v]);
    }
}

Complex SphereToPlaneInterpolant::evaluate(int triangle, const glm::dvec3& barycentric,
                                           const glm::dvec3& direction) const {
    const auto& tri = mMesh->triangles[triangle];
    const auto& values = *mValues;
    if (const int s = mSingularOfTriangle[triangle]; s >= 0) {
        // zeta - zeta_s ~ w^exponent: interpolate its exponent-th root, which is smooth.
        const SingularPoint& point = mSingular[s];
        const Complex apex = values[point.vertex];
        const Complex inward = -apex / std::abs(apex);
        Complex root(0.0);
        for (int k = 0; k < 3; ++k) {
            const Complex offset = (values[tri[k]] - apex) / inward;
            if (std::abs(offset) > 0.0) root += barycentric[k] * std::pow(offset, 1.0 / point.exponent);
        }
        return apex + inward * (std::abs(root) > 0.0 ? std::pow(root, point.exponent) : Complex(0.0));
    }
    Complex sum(0.0);
    for (int k = 0; k < 3; ++k) {
        const int v = tri[k];
        const Complex w = mCharts[v].chartFromDirection(direction);
        sum += barycentric[k] * (values[v] + w * (mLinear[v] + w * mQuadratic[v]));
    }
    return sum;
}

PlaneToSphereInterpolant::PlaneToSphereInterpolant(const TriangleMesh& sphere, const std::vector<Complex>& values,
                                                   const std::vector<SingularPoint>& singular)
    : mMesh(&sphere), mValues(&values), mSingular(singular) {
    const auto neighbours = neighboursOf(sphere);
    mSingularOfTriangle = singularTriangles(sphere, singular, neighbours);
    const std::size_t n = sphere.positions.size();
    mCharts.resize(n);
    mLinear.assign(n, Complex(0.0));
    mQuadratic.assign(n, Complex(0.0));
    std::vector<Complex> z;
    std::vector<Complex> w;
    for (std::size_t v = 0; v < n; ++v) {
        mCharts[v] = SphereChart(sphere.positions[v]);
        z.clear();
        w.clear();
        for (const int j : neighbours[v]) {
            z.push_back(values[j] - values[v]);
            w.push_back(mCharts[v].chartFromDirection(sphere.positions[j]));
        }
        fitQuadratic(z, w, mLinear[v], mQuadratic[v]);
    }
}

glm::dvec3 PlaneToSphereInterpolant::evaluate(int triangle, const glm::dvec3& barycentric, Complex zeta) const {
    const auto& tri = mMesh->triangles[triangle];
    const auto& values = *mValues;
    const auto& positions = mMesh->positions;
    if (const int s = mSingularOfTriangle[triangle]; s >= 0 && !mSingular[s].isInverseSmooth) {
        // w_s ~ (zeta - zeta_s)^(1 / exponent): interpolate w_s^exponent, which is smooth.
        const SingularPoint& point = mSingular[s];
        const SphereChart& chart = mCharts[point.vertex];
        const Complex bisector = std::polar(1.0, point.wedgeAngle);
        Complex power(0.0);
        for (int k = 0; k < 3; ++k) {
            const Complex w = chart.chartFromDirection(positions[tri[k]]) / bisector;
            if (std::abs(w) > 0.0) power += barycentric[k] * std::pow(w, point.exponent);
        }
        const Complex w = std::abs(power) > 0.0 ? std::pow(power, 1.0 / point.exponent) : Complex(0.0);
        return glm::normalize(chart.directionFromChart(w * bisector));
    }
    glm::dvec3 sum(0.0);
    for (int k = 0; k < 3; ++k) {
        const int v = tri[k];
        const Complex z = zeta - values[v];
        sum += barycentric[k] * mCharts[v].directionFromChart(z * (mLinear[v] + z * mQuadratic[v]));
    }
    return glm::normalize(sum);
}

}  // namespace conformal
