/// @brief Newton's method on the discrete Ricci energy with step control, for the vertex-scaling
/// and circle-packing metrics, using the power-centre form of the Hessian (Zhang et al., "The
/// unified discrete surface Ricci flow", 2014): d theta_i / d u_j = h_ij / l_ij, where h_ij is
/// the signed distance from the triangle's power centre to edge ij.
#include "conformal/ricci_flow.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

/// The metric's fixed data: per triangle corner the base length (vertex scaling) or the
/// fitted inversive distance (circle packing) of the edge opposite that corner.
struct MetricData {
    DiscreteMetric metric = DiscreteMetric::VertexScaling;
    std::vector<std::array<double, 3>> edgeConstant;
};

bool lengthsFromLogScale(const TriangleMesh& mesh, const MetricData& data,
                         const std::vector<double>& u, std::vector<std::array<double, 3>>& lengths,
                         std::vector<std::array<double, 3>>& angles) {
    const std::size_t triangleCount = mesh.triangles.size();
    bool isValid = true;
    for (std::size_t t = 0; t < triangleCount && isValid; ++t) {
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const double ua = u[tri[(k + 1) % 3]];
            const double ub = u[tri[(k + 2) % 3]];
            if (data.metric == DiscreteMetric::VertexScaling) {
                lengths[t][k] = std::exp(0.5 * (ua + ub)) * data.edgeConstant[t][k];
            } else {
                const double ga = std::exp(ua);
                const double gb = std::exp(ub);
                const double squared = ga * ga + gb * gb + 2.0 * data.edgeConstant[t][k] * ga * gb;
                lengths[t][k] = squared > 0.0 ? std::sqrt(squared) : 0.0;
            }
        }
        isValid = triangleAnglesFromLengths(lengths[t], angles[t]);
    }
    return isValid;
}

void curvatureFromAngles(const TriangleMesh& mesh, const std::vector<char>& isBoundary,
                         const std::vector<std::array<double, 3>>& angles,
                         std::vector<double>& curvature) {
    for (std::size_t v = 0; v < curvature.size(); ++v) {
        curvature[v] = isBoundary[v] ? std::numbers::pi : 2.0 * std::numbers::pi;
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) curvature[mesh.triangles[t][k]] -= angles[t][k];
    }
}

/// d theta_a / d u_b for the edge opposite each corner: 1/2 cot for vertex scaling, the power
/// centre's distance over the length for circle packing.
std::array<double, 3> edgeWeights(DiscreteMetric metric, const std::array<double, 3>& lengths,
                                  const std::array<double, 3>& angles,
                                  const std::array<double, 3>& logScale) {
    std::array<double, 3> weights{};
    if (metric == DiscreteMetric::VertexScaling) {
        for (int k = 0; k < 3; ++k) weights[k] = 0.5 / std::tan(angles[k]);
        return weights;
    }
    // Lay the triangle out: p0 at 0, p1 on the x axis, p2 above it.
    const double l0 = lengths[0];
    const double l1 = lengths[1];
    const double l2 = lengths[2];
    const double r0 = std::exp(2.0 * logScale[0]);
    const double r1 = std::exp(2.0 * logScale[1]);
    const double r2 = std::exp(2.0 * logScale[2]);
    const double p2x = l1 * std::cos(angles[0]);
    const double p2y = l1 * std::sin(angles[0]);
    // Power centre: equal power |o - p_i|^2 - r_i^2 with respect to the three circles.
    const double ox = (l2 * l2 + r0 - r1) / (2.0 * l2);
    const double oy = (0.5 * (l1 * l1 + r0 - r2) - ox * p2x) / p2y;
    const double e1x = p2x / l1;
    const double e1y = p2y / l1;
    const double fx = (p2x - l2) / l0;
    const double fy = p2y / l0;
    const double h0 = fx * oy - fy * (ox - l2);  // to edge p1 p2, positive toward p0
    const double h1 = e1y * ox - e1x * oy;      // to edge p0 p2, positive toward p1
    const double h2 = oy;                       // to edge p0 p1, positive toward p2
    weights[0] = h0 / l0;
    weights[1] = h1 / l1;
    weights[2] = h2 / l2;
    return weights;
}

double normOf(const std::vector<double>& values) {
    double sum = 0.0;
    for (const double v : values) sum += v * v;
    return std::sqrt(sum);
}

}  // namespace

bool triangleAnglesFromLengths(const std::array<double, 3>& lengths, std::array<double, 3>& angles) {
    const double a = lengths[0];
    const double b = lengths[1];
    const double c = lengths[2];
    const double s0 = -a + b + c;
    const double s1 = a - b + c;
    const double s2 = a + b - c;
    const double perimeter = a + b + c;
    if (!(s0 > 0.0 && s1 > 0.0 && s2 > 0.0 && std::isfinite(perimeter))) return false;
    // tan(A / 2) = sqrt((s - b)(s - c) / (s (s - a))), written with the doubled terms.
    angles[0] = 2.0 * std::atan(std::sqrt(s1 * s2 / (perimeter * s0)));
    angles[1] = 2.0 * std::atan(std::sqrt(s0 * s2 / (perimeter * s1)));
    angles[2] = 2.0 * std::atan(std::sqrt(s0 * s1 / (perimeter * s2)));
    return true;
}

RicciFlowResult flowToTargetCurvature(const TriangleMesh& mesh,
                                      const std::vector<double>& targetCurvature,
                                      const RicciFlowSettings& settings,
                                      const std::vector<double>* initialLogScale) {
    const std::size_t vertexCount = mesh.positions.size();
    const std::size_t triangleCount = mesh.triangles.size();
    if (targetCurvature.size() != vertexCount) {
        throw RicciFlowError("Ricci flow: " + std::to_string(targetCurvature.size()) +
                             " target curvatures for " + std::to_string(vertexCount) + " vertices");
    }
    if (triangleCount == 0) throw RicciFlowError("Ricci flow: the mesh has no triangles");
    const std::vector<int> twins = twinHalfEdges(mesh);
    const std::vector<char> isBoundary = boundaryVertexFlags(mesh, twins);

    // Fixed data of the metric, fitted so that u0 reproduces the mesh's edge lengths.
    MetricData data;
    data.metric = settings.metric;
    data.edgeConstant.resize(triangleCount);
    std::vector<double> u(vertexCount, 0.0);
    std::vector<std::array<double, 3>> lengths(triangleCount);
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            lengths[t][k] = glm::length(mesh.positions[tri[(k + 2) % 3]] -
                                        mesh.positions[tri[(k + 1) % 3]]);
        }
    }
    if (settings.metric == DiscreteMetric::CirclePacking) {
        std::vector<double> lengthSum(vertexCount, 0.0);
        std::vector<int> lengthCount(vertexCount, 0);
        for (std::size_t t = 0; t < triangleCount; ++t) {
            for (int k = 0; k < 3; ++k) {
                for (int end : {(k + 1) % 3, (k + 2) % 3}) {
                    lengthSum[mesh.triangles[t][end]] += lengths[t][k];
                    ++lengthCount[mesh.triangles[t][end]];
                }
            }
        }
        constexpr double kRadiusFraction = 0.6;
        for (std::size_t v = 0; v < vertexCount; ++v) {
            if (lengthCount[v] > 0) u[v] = std::log(kRadiusFraction * lengthSum[v] / lengthCount[v]);
        }
    }
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (settings.metric == DiscreteMetric::VertexScaling) {
                data.edgeConstant[t][k] = lengths[t][k];
            } else {
                const double ga = std::exp(u[tri[(k + 1) % 3]]);
                const double gb = std::exp(u[tri[(k + 2) % 3]]);
                const double l = lengths[t][k];
                data.edgeConstant[t][k] = (l * l - ga * ga - gb * gb) / (2.0 * ga * gb);
            }
        }
    }

    RicciFlowResult result;
    result.cornerAngles.resize(triangleCount);
    if (!lengthsFromLogScale(mesh, data, u, lengths, result.cornerAngles)) {
        throw RicciFlowError("Ricci flow: the input mesh has a degenerate triangle");
    }
    if (initialLogScale != nullptr && initialLogScale->size() == vertexCount) {
        std::vector<double> guess = u;
        for (std::size_t v = 0; v < vertexCount; ++v) {
            if (std::isfinite((*initialLogScale)[v])) guess[v] += (*initialLogScale)[v];
        }
        std::vector<std::array<double, 3>> guessLengths(triangleCount);
        std::vector<std::array<double, 3>> guessAngles(triangleCount);
        if (lengthsFromLogScale(mesh, data, guess, guessLengths, guessAngles)) {
            u.swap(guess);
            lengths.swap(guessLengths);
            result.cornerAngles.swap(guessAngles);
        }
    }
    std::vector<double> curvature(vertexCount);
    std::vector<double> residual(vertexCount);
    auto updateResidual = [&](const std::vector<std::array<double, 3>>& angles) {
        curvatureFromAngles(mesh, isBoundary, angles, curvature);
        double maxError = 0.0;
        for (std::size_t v = 0; v < vertexCount; ++v) {
            residual[v] = curvature[v] - targetCurvature[v];
            maxError = std::max(maxError, std::abs(residual[v]));
        }
        return maxError;
    };
    double maxError = updateResidual(result.cornerAngles);

    // The pinned vertex's row and column are replaced by the identity.
    const int pinned = static_cast<int>(std::distance(
        isBoundary.begin(), std::find(isBoundary.begin(), isBoundary.end(), 0)));
    const int pinnedVertex = pinned < static_cast<int>(vertexCount) ? pinned : 0;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    bool isAnalysed = false;
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(9 * triangleCount + 1);
    std::vector<double> trialU(vertexCount);
    std::vector<std::array<double, 3>> trialLengths(triangleCount);
    std::vector<std::array<double, 3>> trialAngles(triangleCount);

    constexpr double kReuseFactorisationBelow = 1e-3;
    bool mustRefactorise = true;
    double previousMax = maxError;
    while (!(maxError < settings.tolerance)) {
        if (result.iterations >= settings.maxIterations) {
            std::ostringstream message;
            message << "Ricci flow: no convergence after " << result.iterations
                    << " Newton steps; max curvature error " << maxError << " rad (tolerance "
                    << settings.tolerance << ")";
            throw RicciFlowError(message.str());
        }
        // Near the solution the Hessian hardly changes: keep its factorisation (a chord step,
        // linear convergence at a small rate) as long as each step cuts the residual tenfold.
        const bool isStaleEnough = isAnalysed && maxError < kReuseFactorisationBelow && !mustRefactorise;
        if (!isStaleEnough) {
        // Hessian d K / d u: a Laplacian with the metric's edge weights.
        triplets.clear();
        for (std::size_t t = 0; t < triangleCount; ++t) {
            const auto& tri = mesh.triangles[t];
            const std::array<double, 3> scale = {u[tri[0]], u[tri[1]], u[tri[2]]};
            const auto weights = edgeWeights(settings.metric, lengths[t], result.cornerAngles[t], scale);
            for (int k = 0; k < 3; ++k) {
                const int a = tri[(k + 1) % 3];
                const int b = tri[(k + 2) % 3];
                const double w = weights[k];
                if (a != pinnedVertex) triplets.emplace_back(a, a, w);
                if (b != pinnedVertex) triplets.emplace_back(b, b, w);
                if (a != pinnedVertex && b != pinnedVertex) {
                    triplets.emplace_back(a, b, -w);
                    triplets.emplace_back(b, a, -w);
                }
            }
        }
        triplets.emplace_back(pinnedVertex, pinnedVertex, 1.0);
        Eigen::SparseMatrix<double> hessian(static_cast<Eigen::Index>(vertexCount),
                                            static_cast<Eigen::Index>(vertexCount));
        hessian.setFromTriplets(triplets.begin(), triplets.end());
        if (!isAnalysed) {
            solver.analyzePattern(hessian);
            isAnalysed = true;
        }
        solver.factorize(hessian);
        if (solver.info() != Eigen::Success) {
            throw RicciFlowError("Ricci flow: sparse Cholesky factorisation of the Hessian failed "
                                 "at Newton step " + std::to_string(result.iterations));
        }
        ++result.factorisations;
        }
        Eigen::VectorXd rhs(static_cast<Eigen::Index>(vertexCount));
        for (std::size_t v = 0; v < vertexCount; ++v) rhs[static_cast<Eigen::Index>(v)] = -residual[v];
        rhs[pinnedVertex] = 0.0;
        const Eigen::VectorXd step = solver.solve(rhs);
        if (solver.info() != Eigen::Success || !step.allFinite()) {
            throw RicciFlowError("Ricci flow: the Newton system could not be solved at step " +
                                 std::to_string(result.iterations));
        }

        // Step control: halve until every triangle is valid and the residual decreases.
        const double residualNorm = normOf(residual);
        double fraction = 1.0;
        constexpr int kMaxHalvings = 60;
        int halvings = 0;
        bool isStepFound = true;
        for (;; ++halvings) {
            if (halvings > kMaxHalvings && isStaleEnough) {
                // A reused factorisation may point the wrong way: refactorise here and retry.
                isStepFound = false;
                break;
            }
            if (halvings > kMaxHalvings) {
                std::ostringstream message;
                message << "Ricci flow: step control failed at Newton step " << result.iterations
                        << " (no step keeps the triangles valid and lowers the residual); max "
                           "curvature error "
                        << maxError << " rad";
                throw RicciFlowError(message.str());
            }
            for (std::size_t v = 0; v < vertexCount; ++v) {
                trialU[v] = u[v] + fraction * step[static_cast<Eigen::Index>(v)];
            }
            if (lengthsFromLogScale(mesh, data, trialU, trialLengths, trialAngles)) {
                std::vector<double> savedResidual = residual;
                const double trialMax = updateResidual(trialAngles);
                // Near round-off the 2-norm of a million residuals stops falling before the
                // largest one does, so a smaller maximum counts as progress too.
                if (std::isfinite(trialMax) && (normOf(residual) < residualNorm || trialMax < maxError ||
                                                trialMax < settings.tolerance)) {
                    maxError = trialMax;
                    break;
                }
                residual = std::move(savedResidual);
            }
            fraction *= 0.5;
        }
        result.stepHalvings += halvings;
        if (!isStepFound) {
            mustRefactorise = true;
            continue;
        }
        mustRefactorise = halvings > 0 || maxError > 0.1 * previousMax;
        previousMax = maxError;
        u.swap(trialU);
        lengths.swap(trialLengths);
        result.cornerAngles.swap(trialAngles);
        ++result.iterations;
    }
    result.logScale = std::move(u);
    result.edgeLengths = std::move(lengths);
    result.maxCurvatureError = maxError;
    return result;
}

}  // namespace conformal
