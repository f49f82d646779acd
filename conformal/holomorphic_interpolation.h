/// @brief Interpolation of the disk maps between mesh vertices by blended local holomorphic
/// quadratics, so that the interpolated map stays conformal to second order (plain
/// barycentric interpolation is only first order: its Jacobian jumps from triangle to triangle
/// and K - 1 is of the order of the mesh spacing).
#pragma once

#include <complex>
#include <vector>

#include <glm/vec3.hpp>

#include "conformal/triangle_mesh.h"

namespace conformal {

/// A conformal chart of the unit sphere around a point p: stereographic projection from -p,
/// w = ((x . e1) + i (x . e2)) / (1 + x . p), with (e1, e2, p) right-handed.
struct SphereChart {
    glm::dvec3 centre{0.0, 0.0, 1.0};
    glm::dvec3 e1{1.0, 0.0, 0.0};
    glm::dvec3 e2{0.0, 1.0, 0.0};

    explicit SphereChart(const glm::dvec3& point);
    SphereChart() = default;
    std::complex<double> chartFromDirection(const glm::dvec3& x) const;
    glm::dvec3 directionFromChart(std::complex<double> w) const;
};

/// A boundary vertex where the disk map is not smooth: the domain's interior angle there is
/// theta on the sphere, so zeta - zeta_s ~ c w^(pi / theta) in the vertex's chart. Near it both
/// interpolants work in variables in which the map is smooth again.
struct SingularPoint {
    int vertex = -1;
    double exponent = 1.0;      ///< pi / theta
    double wedgeAngle = 0.0;    ///< argument, in the vertex's SphereChart, of the domain's bisector
    bool isInverseSmooth = false;  ///< the inverse is smooth there (exponent 1/2: a slit's tip)
};

/// A map from a sphere mesh to the plane (phi5 or phi6), known at the vertices. Each vertex k
/// gets f_k(w) = value_k + a_k w + b_k w^2 in its chart, fitted by least squares to its
/// neighbours' values; a point of triangle (i, j, l) with barycentric weights lambda gets
/// sum lambda_k f_k(w_k(x)). Triangles within two mesh spacings of a singular point s instead
/// interpolate V = ((zeta - zeta_s) e^{-i beta})^(1 / exponent), beta the inward normal's
/// argument at zeta_s on the unit circle, in which the map is smooth.
class SphereToPlaneInterpolant {
public:
    SphereToPlaneInterpolant() = default;
    SphereToPlaneInterpolant(const TriangleMesh& sphere, const std::vector<std::complex<double>>& values,
                             const std::vector<SingularPoint>& singular);
    std::complex<double> evaluate(int triangle, const glm::dvec3& barycentric,
                                  const glm::dvec3& direction) const;

private:
    const TriangleMesh* mMesh = nullptr;
    const std::vector<std::complex<double>>* mValues = nullptr;
    std::vector<SphereChart> mCharts;
    std::vector<std::complex<double>> mLinear;
    std::vector<std::complex<double>> mQuadratic;
    std::vector<SingularPoint> mSingular;
    std::vector<int> mSingularOfTriangle;  ///< index into mSingular, or -1
};

/// The inverse direction: a map from a planar (disk) mesh to the sphere, known at the
/// vertices. Vertex k gets w_k(z) = a_k (z - value_k) + b_k (z - value_k)^2 in the chart at
/// its direction; a point gets the normalised blend of the three charts' directions. Near a
/// singular point s the triangles interpolate U = (w_s e^{-i wedgeAngle})^exponent instead.
class PlaneToSphereInterpolant {
public:
    PlaneToSphereInterpolant() = default;
    PlaneToSphereInterpolant(const TriangleMesh& sphere, const std::vector<std::complex<double>>& values,
                             const std::vector<SingularPoint>& singular);
    glm::dvec3 evaluate(int triangle, const glm::dvec3& barycentric, std::complex<double> zeta) const;

private:
    const TriangleMesh* mMesh = nullptr;
    const std::vector<std::complex<double>>* mValues = nullptr;
    std::vector<SphereChart> mCharts;
    std::vector<std::complex<double>> mLinear;
    std::vector<std::complex<double>> mQuadratic;
    std::vector<SingularPoint> mSingular;
    std::vector<int> mSingularOfTriangle;  ///< index into mSingular, or -1
};

}  // namespace conformal
