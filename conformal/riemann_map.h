/// @brief The Riemann map of a topological disk mesh onto the unit disk, by the paper's route:
/// punch a hole, flow to a flat metric with geodesic boundaries, slice, flatten, exponentiate.
#pragma once

#include <complex>
#include <vector>

#include "conformal/ricci_flow.h"
#include "conformal/triangle_mesh.h"

namespace conformal {

/// What the construction measured on its way.
struct RiemannMapReport {
    RicciFlowResult flow;             ///< the flow on the punched mesh (lengths, iterations)
    double outerRadiusError = 0.0;    ///< max | |w| - 1 | over the outer boundary's vertices
    double innerRadius = 0.0;         ///< radius of the punched hole's image circle
    double seamMismatch = 0.0;        ///< max |w| difference between a vertex's layout copies
    std::vector<double> vertexLogScale;  ///< the flow's u per vertex of the input mesh (NaN in the hole)
};

/// Maps the vertices of `mesh` (a triangulated topological disk, CCW seen from outside) to the
/// closed unit disk conformally, with `centreVertex` (interior) sent to about 0 and the rotation
/// left free. A round hole around `centreVertex` is removed; the remaining annulus gets, by Ricci flow,
/// the flat metric with zero curvature everywhere (both boundaries geodesic), so it is a flat
/// cylinder; it is cut along a shortest edge path between its boundaries, laid out in the
/// plane (a strip, periodic by a translation T), scaled by 2 pi i / T and mapped by exp onto an
/// annulus whose outer circle is the unit circle. The hole is filled by a holomorphic
/// polynomial (in the centre's stereographic chart, so `mesh` must lie on the unit sphere)
/// fitted to the rings around it, which also removes the rim's forced roundness.
/// Returns #V disk positions. Throws RicciFlowError or std::runtime_error on failure.
/// `holeAngle` is the hole's angular radius (radians) around the centre on the unit sphere:
/// 0 (the default) removes just the centre's star. `initialLogScale` (#V, optional, NaN
/// allowed) starts the flow near its solution, e.g. from vertexLogScale of a coarser mesh.
std::vector<std::complex<double>> diskFromMesh(const TriangleMesh& mesh, int centreVertex,
                                               const RicciFlowSettings& settings,
                                               RiemannMapReport* report = nullptr,
                                               double holeAngle = 0.0,
                                               const std::vector<double>* initialLogScale = nullptr);

}  // namespace conformal
