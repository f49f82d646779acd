/// @brief Discrete Ricci flow by Newton's method: finds the discrete conformal metric of a
/// triangle mesh with prescribed vertex curvatures (Petkov et al. 2011, Algorithm 1).
#pragma once

#include <array>
#include <stdexcept>
#include <vector>

#include "conformal/triangle_mesh.h"

namespace conformal {

/// The discrete conformal structure the flow deforms.
enum class DiscreteMetric {
    /// Vertex scaling (discrete Yamabe): l_ij = exp((u_i + u_j) / 2) l0_ij. Its Hessian is the
    /// cotangent Laplacian.
    VertexScaling,
    /// Circle packing with the circles' mutual angles fitted to the mesh (Thurston; inversive
    /// distance where circles do not meet): l_ij^2 = g_i^2 + g_j^2 + 2 I_ij g_i g_j with
    /// g_i = exp(u_i), radii 0.6 x the mean incident edge length and I_ij fitted so that
    /// the initial metric reproduces the mesh exactly.
    CirclePacking,
};

struct RicciFlowSettings {
    DiscreteMetric metric = DiscreteMetric::VertexScaling;
    double tolerance = 1e-10;  ///< stop when max_i |Kbar_i - K_i| is below this (radians)
    int maxIterations = 100;   ///< Newton steps before giving up
};

/// The flat (or target-curvature) metric the flow found.
struct RicciFlowResult {
    std::vector<double> logScale;                       ///< u per vertex
    std::vector<std::array<double, 3>> edgeLengths;     ///< per triangle, edge opposite corner k
    std::vector<std::array<double, 3>> cornerAngles;    ///< per triangle, angle at corner k
    int iterations = 0;
    int factorisations = 0;           ///< Hessian factorisations (steps near the end reuse one)
    int stepHalvings = 0;             ///< total step halvings the step control needed
    double maxCurvatureError = 0.0;   ///< max_i |Kbar_i - K_i| at the end (radians)
};

/// Raised when the flow cannot reach the tolerance: the message says why (step control
/// exhausted, solver failure, iteration limit) and the residual reached.
class RicciFlowError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Runs the flow from the mesh's own edge lengths to the target Gaussian curvatures
/// `targetCurvature` (#V, radians; interior K = 2 pi - angle sum, boundary K = pi - angle sum,
/// so 0 on the boundary asks for a geodesic boundary). The targets must satisfy Gauss-Bonnet
/// (sum = 2 pi chi). One vertex is pinned (u = 0) to fix the global scale. Every Newton step
/// is halved until all triangles keep their triangle inequalities, no value is NaN and the
/// curvature residual's 2-norm decreases. Throws RicciFlowError on failure.
/// `initialLogScale` (#V, optional) starts the flow from that u instead of 0, e.g. from a
/// coarser mesh's solution; it is ignored when it would break a triangle.
RicciFlowResult flowToTargetCurvature(const TriangleMesh& mesh,
                                      const std::vector<double>& targetCurvature,
                                      const RicciFlowSettings& settings,
                                      const std::vector<double>* initialLogScale = nullptr);

/// Angles (radians) of a triangle with side lengths a, b, c (side k opposite corner k), by the
/// half-angle formula, which stays accurate for needle-like triangles. Returns false when the
/// lengths violate a strict triangle inequality or are not finite.
bool triangleAnglesFromLengths(const std::array<double, 3>& lengths, std::array<double, 3>& angles);

}  // namespace conformal
