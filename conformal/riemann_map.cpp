/// @brief Riemann map onto the unit disk through a flat cylinder (Petkov et al. 2011, Sec. 4):
/// hole, Ricci flow, slice, layout, exponential map, hole filled at 0.
#include "conformal/riemann_map.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "conformal/holomorphic_interpolation.h"

namespace conformal {

namespace {

using Complex = std::complex<double>;

std::uint64_t undirectedKey(int a, int b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b));
    const auto hi = static_cast<std::uint64_t>(std::max(a, b));
    return (hi << 32) | lo;
}

/// The vertices' neighbours through the triangles' edges (compressed rows).
void vertexNeighbours(const TriangleMesh& mesh, std::vector<int>& offsets,
                      std::vector<int>& neighbours) {
    const std::size_t n = mesh.positions.size();
    offsets.assign(n + 1, 0);
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) offsets[tri[k] + 1] += 2;
    }
    for (std::size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
    neighbours.assign(offsets[n], -1);
    std::vector<int> fill(offsets.begin(), offsets.end() - 1);
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            neighbours[fill[tri[k]]++] = tri[(k + 1) % 3];
            neighbours[fill[tri[k]]++] = tri[(k + 2) % 3];
        }
    }
}

constexpr double kFilledSpacings = 3.0;   // replaced by the fit inside this
constexpr double kBlendedSpacings = 8.0;  // blended smoothly out to this
constexpr double kFittedSpacings = 12.0;  // fitted out to this

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

double meanNeighbourAngle(const TriangleMesh& mesh, int vertex) {
    double sum = 0.0;
    int count = 0;
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            if (tri[k] != vertex) continue;
            sum += angleBetween(mesh.positions[vertex], mesh.positions[tri[(k + 1) % 3]]);
            ++count;
        }
    }
    if (count == 0) {
        throw std::runtime_error("Riemann map: centre vertex " + std::to_string(vertex) +
                                 " belongs to no triangle");
    }
    return sum / count;
}

/// The annulus map sends the hole's rim to a circle, which the Riemann map does not quite do,
/// and the flat cylinder's metric varies fastest next to the rim, where the discretisation is
/// least accurate. Both errors are holomorphic near the hole and fade away from it: the values
/// within angle `filled` of the centre are replaced by a holomorphic polynomial in the centre's
/// stereographic chart, fitted by least squares to the values from `filled` out to `fitted`,
/// and blended into the computed values with a smooth step between `filled` and `blended` (a
/// sharp switch would leave a kink that the distortion measure sees).
void fillHole(const TriangleMesh& mesh, const glm::dvec3& centre, double filled, double blended,
              double fitted, const std::vector<char>& isHole, std::vector<Complex>& disk) {
    constexpr int kMaxDegree = 8;
    const SphereChart chart(centre);
    const double scale = std::tan(0.5 * fitted);  // chart radius of the fitted zone's edge
    std::vector<int> filledVertices;
    std::vector<Complex> samplePoints;
    std::vector<Complex> sampleValues;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const double angle = angleBetween(centre, mesh.positions[v]);
        if (angle < blended) filledVertices.push_back(static_cast<int>(v));
        if (angle >= filled && angle < fitted && !isHole[v]) {
            samplePoints.push_back(chart.chartFromDirection(mesh.positions[v]) / scale);
            sampleValues.push_back(disk[v]);
        }
    }
    // Four samples per coefficient at least; a coarse mesh gets a lower degree.
    const int degree = std::min(kMaxDegree, static_cast<int>(samplePoints.size()) / 4 - 1);
    if (degree < 1) return;
    Eigen::MatrixXcd normal = Eigen::MatrixXcd::Zero(degree + 1, degree + 1);
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(degree + 1);
    Eigen::VectorXcd powers(degree + 1);
    for (std::size_t k = 0; k < samplePoints.size(); ++k) {
        powers[0] = 1.0;
        for (int p = 1; p <= degree; ++p) powers[p] = powers[p - 1] * samplePoints[k];
        normal += powers.conjugate() * powers.transpose();
        rhs += powers.conjugate() * sampleValues[k];
    }
    const Eigen::VectorXcd coefficients = normal.ldlt().solve(rhs);
    if (!coefficients.allFinite()) return;
    for (const int v : filledVertices) {
        const Complex x = chart.chartFromDirection(mesh.positions[v]) / scale;
        Complex value(0.0);
        for (int k = degree; k >= 0; --k) value = value * x + coefficients[k];
        const double angle = angleBetween(centre, mesh.positions[v]);
        const double t = std::clamp((angle - filled) / (blended - filled), 0.0, 1.0);
        const double weight = isHole[v] ? 1.0 : 1.0 - t * t * (3.0 - 2.0 * t);
        disk[v] = weight * value + (1.0 - weight) * disk[v];
    }
}

}  // namespace

std::vector<Complex> diskFromMesh(const TriangleMesh& mesh, int centreVertex,
                                  const RicciFlowSettings& settings, RiemannMapReport* report,
                                  double holeAngle, const std::vector<double>* initialLogScale) {
    const int vertexCount = static_cast<int>(mesh.positions.size());
    if (centreVertex < 0 || centreVertex >= vertexCount) {
        throw std::runtime_error("Riemann map: centre vertex " + std::to_string(centreVertex) +
                                 " is not a vertex of the mesh");
    }

    if (!std::isfinite(holeAngle)) throw std::invalid_argument("Riemann map: the hole angle is not a finite number");
    // Punch the hole: the vertices within holeAngle of the centre (at least the centre).
    const glm::dvec3 centre = glm::normalize(mesh.positions[centreVertex]);
    const double spacing = meanNeighbourAngle(mesh, centreVertex);
    const double holeRadians = std::max(holeAngle, 0.0);
    std::vector<char> isHole(vertexCount, 0);
    for (int v = 0; v < vertexCount; ++v) {
        isHole[v] = v == centreVertex || angleBetween(centre, mesh.positions[v]) < holeRadians;
    }
    std::vector<char> isHoleRing(vertexCount, 0);
    TriangleMesh punched;
    punched.triangles.reserve(mesh.triangles.size());
    for (const auto& tri : mesh.triangles) {
        const bool touchesHole = isHole[tri[0]] || isHole[tri[1]] || isHole[tri[2]];
        if (!touchesHole) {
            punched.triangles.push_back(tri);
        } else {
            for (const int v : tri) {
                if (!isHole[v]) isHoleRing[v] = 1;
            }
        }
    }
    // Hole vertices leave the flow's mesh; the others keep their order.
    TriangleMesh flowMesh;
    std::vector<int> flowIndex(vertexCount, -1);
    std::vector<int> originalIndex;
    originalIndex.reserve(vertexCount);
    for (int v = 0; v < vertexCount; ++v) {
        if (isHole[v]) continue;
        flowIndex[v] = static_cast<int>(originalIndex.size());
        originalIndex.push_back(v);
        flowMesh.positions.push_back(mesh.positions[v]);
    }
    flowMesh.triangles.reserve(punched.triangles.size());
    for (const auto& tri : punched.triangles) {
        flowMesh.triangles.push_back({flowIndex[tri[0]], flowIndex[tri[1]], flowIndex[tri[2]]});
    }
    const std::vector<int> twins = twinHalfEdges(flowMesh);
    const std::vector<char> isBoundary = boundaryVertexFlags(flowMesh, twins);
    const int flowCount = static_cast<int>(flowMesh.positions.size());
    std::vector<char> isInner(flowCount, 0);
    for (int v = 0; v < flowCount; ++v) isInner[v] = isHoleRing[originalIndex[v]];
    for (int v = 0; v < flowCount; ++v) {
        if (isInner[v] && !isBoundary[v]) {
            throw std::runtime_error("Riemann map: the hole's rim is not a boundary loop");
        }
    }

    // Flat cylinder: zero curvature at every vertex, so both boundaries become geodesics.
    RiemannMapReport localReport;
    RiemannMapReport& out = report ? *report : localReport;
    std::vector<double> flowGuess;
    if (initialLogScale != nullptr && static_cast<int>(initialLogScale->size()) == vertexCount) {
        flowGuess.resize(flowCount);
        for (int v = 0; v < flowCount; ++v) flowGuess[v] = (*initialLogScale)[originalIndex[v]];
    }
    out.flow = flowToTargetCurvature(flowMesh, std::vector<double>(flowCount, 0.0), settings,
                                     flowGuess.empty() ? nullptr : &flowGuess);
    out.vertexLogScale.assign(vertexCount, std::numeric_limits<double>::quiet_NaN());
    for (int v = 0; v < flowCount; ++v) out.vertexLogScale[originalIndex[v]] = out.flow.logScale[v];
    const auto& lengths = out.flow.edgeLengths;
    const auto& angles = out.flow.cornerAngles;

    // Slice: a shortest edge path (fewest edges) from the hole's rim to the outer boundary
    // through interior vertices.
    std::vector<int> offsets;
    std::vector<int> neighbours;
    vertexNeighbours(flowMesh, offsets, neighbours);
    std::vector<int> parent(flowCount, -2);
    std::deque<int> queue;
    for (int v = 0; v < flowCount; ++v) {
        if (isInner[v]) {
            parent[v] = -1;
            queue.push_back(v);
        }
    }
    int outerEnd = -1;
    while (!queue.empty() && outerEnd < 0) {
        const int v = queue.front();
        queue.pop_front();
        for (int i = offsets[v]; i < offsets[v + 1]; ++i) {
            const int w = neighbours[i];
            if (parent[w] != -2) continue;
            if (isBoundary[w] && !isInner[w]) {
                parent[w] = v;
                outerEnd = w;
                break;
            }
            if (isBoundary[w]) continue;
            parent[w] = v;
            queue.push_back(w);
        }
    }
    if (outerEnd < 0) throw std::runtime_error("Riemann map: no path from the hole to the boundary");
    std::unordered_set<std::uint64_t> cutEdges;
    for (int v = outerEnd; parent[v] >= 0; v = parent[v]) cutEdges.insert(undirectedKey(v, parent[v]));

    // Layout: place triangles breadth-first across uncut edges; positions per corner.
    const std::size_t triangleCount = flowMesh.triangles.size();
    std::vector<std::array<Complex, 3>> corner(triangleCount);
    std::vector<char> isPlaced(triangleCount, 0);
    std::deque<int> triangleQueue;
    corner[0][0] = Complex(0.0, 0.0);
    corner[0][1] = Complex(lengths[0][2], 0.0);
    corner[0][2] = std::polar(lengths[0][1], angles[0][0]);
    isPlaced[0] = 1;
    triangleQueue.push_back(0);
    std::size_t placedCount = 1;
    while (!triangleQueue.empty()) {
        const int t = triangleQueue.front();
        triangleQueue.pop_front();
        for (int e = 0; e < 3; ++e) {
            const int twin = twins[3 * t + e];
            if (twin < 0) continue;
            const int s = twin / 3;
            if (isPlaced[s]) continue;
            const auto& tri = flowMesh.triangles[t];
            const int a = tri[e];
            const int b = tri[(e + 1) % 3];
            if (cutEdges.count(undirectedKey(a, b))) continue;
            // In s the edge runs b -> a (corner f to f + 1); its third corner g lies to the left
            // of b -> a, at the angle of s at b.
            const int f = twin % 3;
            const int g = (f + 2) % 3;
            const Complex pb = corner[t][(e + 1) % 3];
            const Complex pa = corner[t][e];
            const Complex direction = (pa - pb) / std::abs(pa - pb);
            corner[s][f] = pb;
            corner[s][(f + 1) % 3] = pa;
            // Edge b -> g is opposite corner (f + 1).
            corner[s][g] = pb + lengths[s][(f + 1) % 3] * direction * std::polar(1.0, angles[s][f]);
            isPlaced[s] = 1;
            ++placedCount;
            triangleQueue.push_back(s);
        }
    }
    if (placedCount != triangleCount) {
        throw std::runtime_error("Riemann map: the sliced mesh is not connected (" +
                                 std::to_string(placedCount) + " of " +
                                 std::to_string(triangleCount) + " triangles laid out)");
    }

    // The translation T between the slice's two sides.
    Complex translation(0.0, 0.0);
    {
        const int a = outerEnd;
        const int b = parent[outerEnd];
        for (std::size_t t = 0; t < triangleCount && translation == Complex(0.0, 0.0); ++t) {
            for (int e = 0; e < 3; ++e) {
                const auto& tri = flowMesh.triangles[t];
                if (tri[e] != a || tri[(e + 1) % 3] != b) continue;
                const int twin = twins[3 * t + e];
                if (twin < 0) break;
                translation = corner[t][e] - corner[twin / 3][(twin % 3 + 1) % 3];
                break;
            }
        }
    }
    if (std::abs(translation) == 0.0) throw std::runtime_error("Riemann map: the slice has no width");

    // Straighten the cylinder: zeta = 2 pi i z / T is periodic by 2 pi i; the outer boundary is
    // a vertical line, sent to the unit circle by exp.
    const Complex scale = Complex(0.0, 2.0 * std::numbers::pi) / translation;
    double innerSum = 0.0;
    double outerSum = 0.0;
    int innerCount = 0;
    int outerCount = 0;
    for (std::size_t t = 0; t < triangleCount; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int v = flowMesh.triangles[t][k];
            if (!isBoundary[v]) continue;
            const double re = (scale * corner[t][k]).real();
            if (isInner[v]) {
                innerSum += re;
                ++innerCount;
            } else {
                outerSum += re;
                ++outerCount;
            }
        }
    }
    const double sign = innerSum / innerCount > outerSum / outerCount ? -1.0 : 1.0;
    const double outerRe = sign * outerSum / outerCount;

    std::vector<Complex> disk(vertexCount, Complex(0.0, 0.0));
    std::vector<int> copies(vertexCount, 0);
    std::vector<Complex> firstCopy(vertexCount);
    out.seamMismatch = 0.0;
    for (std::size_t t = 0; t < triangleCount; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int v = originalIndex[flowMesh.triangles[t][k]];
            const Complex w = std::exp(sign * scale * corner[t][k] - outerRe);
            if (copies[v] == 0) firstCopy[v] = w;
            out.seamMismatch = std::max(out.seamMismatch, std::abs(w - firstCopy[v]));
            disk[v] += w;
            ++copies[v];
        }
    }
    out.outerRadiusError = 0.0;
    double innerRadiusSum = 0.0;
    double boundaryAngle = std::numbers::pi;  // from the centre to the nearest outer-boundary vertex
    for (int v = 0; v < vertexCount; ++v) {
        if (copies[v] > 0) disk[v] /= static_cast<double>(copies[v]);
        if (isHole[v]) continue;
        const int f = flowIndex[v];
        if (isBoundary[f] && !isInner[f]) {
            boundaryAngle = std::min(boundaryAngle, angleBetween(centre, mesh.positions[v]));
            out.outerRadiusError = std::max(out.outerRadiusError, std::abs(std::abs(disk[v]) - 1.0));
        } else if (isInner[f]) {
            innerRadiusSum += std::abs(disk[v]);
        }
    }
    int ringCount = 0;
    for (int v = 0; v < flowCount; ++v) ringCount += isInner[v];
    out.innerRadius = innerRadiusSum / std::max(ringCount, 1);
    disk[centreVertex] = Complex(0.0, 0.0);
    // The fill's zones stay clear of the outer boundary: measured in mesh spacings at the centre
    // they reached it on strongly graded meshes (coarse cells at the face centres) and for large
    // holes, and the polynomial then moved boundary values up to 2 % off the unit circle. Capped
    // at fractions of the centre's distance to the boundary; a hole too large to leave room for
    // the fill is refused.
    const double filled = std::min(std::max(kFilledSpacings * spacing, 1.5 * holeRadians), 0.5 * boundaryAngle);
    const double blended = std::min(std::max(kBlendedSpacings * spacing, 2.5 * holeRadians), 0.75 * boundaryAngle);
    const double fitted = std::min(std::max(kFittedSpacings * spacing, 3.0 * holeRadians), 0.9 * boundaryAngle);
    if (!(filled > holeRadians)) {
        throw std::runtime_error("Riemann map: a hole of " + std::to_string(holeRadians) +
                                 " rad leaves no room to fill it before the boundary, " +
                                 std::to_string(boundaryAngle) + " rad from the centre");
    }
    fillHole(mesh, centre, filled, blended, fitted, isHole, disk);
    return disk;
}

}  // namespace conformal
