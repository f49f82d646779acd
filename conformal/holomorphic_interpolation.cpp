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

std::vector<char> linearTriangles(const TriangleMesh& mesh, const std::vector<char>& isSingular) {
    std::vector<char> isLinear(mesh.triangles.size(), 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (const int v : mesh.triangles[t]) isLinear[t] = isLinear[t] || isSingular[v];
    }
    return isLinear;
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
                                                   const std::vector<char>& isSingular)
    : mMesh(&sphere), mValues(&values), mIsLinearTriangle(linearTriangles(sphere, isSingular)) {
    const auto neighbours = neighboursOf(sphere);
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
    Complex sum(0.0);
    for (int k = 0; k < 3; ++k) {
        const int v = tri[k];
        Complex value = values[v];
        if (!mIsLinearTriangle[triangle]) {
            const Complex w = mCharts[v].chartFromDirection(direction);
            value += w * (mLinear[v] + w * mQuadratic[v]);
        }
        sum += barycentric[k] * value;
    }
    return sum;
}

PlaneToSphereInterpolant::PlaneToSphereInterpolant(const TriangleMesh& sphere, const std::vector<Complex>& values,
                                                   const std::vector<char>& isSingular)
    : mMesh(&sphere), mValues(&values), mIsLinearTriangle(linearTriangles(sphere, isSingular)) {
    const auto neighbours = neighboursOf(sphere);
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
    glm::dvec3 sum(0.0);
    for (int k = 0; k < 3; ++k) {
        const int v = tri[k];
        if (mIsLinearTriangle[triangle]) {
            sum += barycentric[k] * positions[v];
        } else {
            const Complex z = zeta - values[v];
            sum += barycentric[k] * mCharts[v].directionFromChart(z * (mLinear[v] + z * mQuadratic[v]));
        }
    }
    return glm::normalize(sum);
}

}  // namespace conformal
