// The polyp shape measures against closed forms: a sphere seen by a pinhole is a disc (aspect 1,
// circularity 1, the grid square); the same view through a stretch of the tangent plane (a
// non-conformal map) has the stretch as its aspect and 2ab / (a^2 + b^2) as its circularity and
// skews the grid by the known angle; through a rotation and scale (conformal) nothing changes.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "colon/colon_error.h"
#include "colon/polyp_shape.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A pinhole at the origin looking along +z at a pedunculated polyp's head (a sphere of radius
/// r at distance d), n x n pixels over a field of `fovDeg`; each sample's direction is then
/// passed through `warp` (a map of the tangent plane at +z), its hit kept, as a display would.
template <typename Warp>
std::vector<colon::ViewSample> sphereView(double r, double d, int n, double fovDeg, Warp warp) {
    std::vector<colon::ViewSample> samples;
    const double half = std::tan(0.5 * fovDeg * kPi / 180.0);
    const double pixel = 2.0 * half / n;
    const glm::dvec3 centre(0.0, 0.0, d);
    for (int row = 0; row < n; ++row)
        for (int column = 0; column < n; ++column) {
            const glm::dvec2 p(-half + (column + 0.5) * pixel, half - (row + 0.5) * pixel);
            const glm::dvec3 ray = glm::normalize(glm::dvec3(p, 1.0));
            colon::ViewSample sample;
            // The display direction: the scene's tangent-plane point moved by the map.
            const glm::dvec2 shown = warp(p);
            sample.direction = glm::normalize(glm::dvec3(shown, 1.0));
            // Solid angle of the displayed pixel: its tangent-plane area (the map's Jacobian
            // determinant times the pixel's) times cos^3.
            const double eps = 1e-6;
            const glm::dvec2 dx = (warp(p + glm::dvec2(eps, 0.0)) - shown) / eps;
            const glm::dvec2 dy = (warp(p + glm::dvec2(0.0, eps)) - shown) / eps;
            const double c = sample.direction.z;
            sample.solidAngleSr = std::abs(dx.x * dy.y - dx.y * dy.x) * pixel * pixel * c * c * c;
            // Ray-sphere intersection, the scene's own geometry.
            const double b = glm::dot(ray, centre);
            const double disc = b * b - (glm::dot(centre, centre) - r * r);
            if (disc >= 0.0) {
                sample.isHit = true;
                sample.hitMm = (b - std::sqrt(disc)) * ray;
            }
            samples.push_back(sample);
        }
    return samples;
}

colon::PolypSurface head(double r, double d) {
    colon::PolypSurface polyp;
    polyp.isSessile = false;
    polyp.diameterMm = 2.0 * r;
    polyp.centreMm = glm::dvec3(0.0, 0.0, d);
    polyp.baseMm = polyp.centreMm + glm::dvec3(r, 0.0, 0.0);
    polyp.baseNormal = glm::dvec3(-1.0, 0.0, 0.0);
    return polyp;
}

constexpr double kR = 4.0, kD = 40.0;
const glm::dvec3 kGridNormal(0.0, 0.0, 1.0);

TEST(PolypShape, ASphereThroughAPinholeIsADiscWithASquareGrid) {
    const auto samples = sphereView(kR, kD, 240, 16.0, [](glm::dvec2 p) { return p; });
    const colon::ShapeMeasures m = colon::measurePolypShape(samples, head(kR, kD), 0.01, kGridNormal);
    EXPECT_GT(m.pixels, 10000);
    EXPECT_NEAR(m.aspect, 1.0, 0.005);
    EXPECT_NEAR(m.circularity, 1.0, 0.01);
    EXPECT_NEAR(m.gridAngleDeg, 90.0, 0.2);
    // Its area: the disc of the silhouette's half-angle asin(r / d), in the tangent plane.
    const double t = std::tan(std::asin(kR / kD));
    EXPECT_NEAR(m.areaSr, kPi * t * t, 0.01 * kPi * t * t);
}

TEST(PolypShape, AStretchShowsAsItsAspectCircularityAndSkew) {
    const double a = 1.3;
    const auto stretched = sphereView(kR, kD, 240, 16.0, [a](glm::dvec2 p) { return glm::dvec2(a * p.x, p.y); });
    const colon::ShapeMeasures s = colon::measurePolypShape(stretched, head(kR, kD), 0.01, kGridNormal);
    EXPECT_NEAR(s.aspect, a, 0.01);
    EXPECT_NEAR(s.circularity, 2.0 * a / (a * a + 1.0), 0.01);
    EXPECT_LT(std::min(s.orientationDeg, 180.0 - s.orientationDeg), 1.0) << "the major axis along x (an axis: 0 = 180)";
    // A stretch along x keeps x- and y-lines perpendicular; a shear skews them by atan(k).
    EXPECT_NEAR(s.gridAngleDeg, 90.0, 0.3);
    const double k = 0.2;
    const auto sheared = sphereView(kR, kD, 240, 16.0, [k](glm::dvec2 p) { return glm::dvec2(p.x + k * p.y, p.y); });
    const colon::ShapeMeasures h = colon::measurePolypShape(sheared, head(kR, kD), 0.01, kGridNormal);
    EXPECT_NEAR(std::abs(90.0 - h.gridAngleDeg), std::atan(k) * 180.0 / kPi, 0.5);
}

TEST(PolypShape, ARotationAndScaleChangeNothing) {
    const double angle = 0.7, scale = 0.6;
    const auto turned = sphereView(kR, kD, 240, 16.0, [&](glm::dvec2 p) {
        return scale * glm::dvec2(std::cos(angle) * p.x - std::sin(angle) * p.y, std::sin(angle) * p.x + std::cos(angle) * p.y);
    });
    const colon::ShapeMeasures m = colon::measurePolypShape(turned, head(kR, kD), 0.01, kGridNormal);
    EXPECT_NEAR(m.aspect, 1.0, 0.005);
    EXPECT_NEAR(m.circularity, 1.0, 0.01);
    EXPECT_NEAR(m.gridAngleDeg, 90.0, 0.3);
}

TEST(PolypShape, OnlyThePolypsOwnSurfaceCounts) {
    colon::PolypSurface sessile;
    sessile.diameterMm = 10.0;
    sessile.centreMm = glm::dvec3(0.0);
    sessile.baseMm = glm::dvec3(0.0);
    sessile.baseNormal = glm::dvec3(0.0, 0.0, 1.0);
    EXPECT_TRUE(colon::isOnPolyp(sessile, glm::dvec3(0.0, 0.0, 5.0), 0.1));          // its top
    EXPECT_TRUE(colon::isOnPolyp(sessile, glm::dvec3(5.05, 0.0, 0.5), 0.1));         // its side
    EXPECT_FALSE(colon::isOnPolyp(sessile, glm::dvec3(0.0, 0.0, -5.0), 0.1));        // the wall's side, below
    EXPECT_FALSE(colon::isOnPolyp(sessile, glm::dvec3(6.0, 0.0, 0.0), 0.1));         // the wall beside it
    const auto none = colon::measurePolypShape({}, sessile, 0.1, kGridNormal);
    EXPECT_EQ(none.pixels, 0);
}

TEST(PolypTruth, MalformedPolypsAreRefusedWithColonErrors) {
    // Found by fuzzing: a "kind" that is not a string threw the JSON library's own type_error.
    const std::string path = std::string(CVC_TEST_TMP_DIR) + "/polyp_truth_kind.json";
    for (const char* text : {R"({"polyps": [{"kind": ["sessile"], "base_normal": [0, 0, 1]}]})",
                             R"({"polyps": [{"kind": "sessile", "diameter_mm": "6"}]})",
                             R"({"polyps": [{"kind": "sessile", "diameter_mm": 6, "centre_mm": [1, 2]}]})",
                             R"({"polyps": 3})", "not json"}) {
        std::ofstream(path, std::ios::trunc) << text;
        EXPECT_THROW(colon::readPolypTruth(path), colon::ColonError) << text;
    }
}

}  // namespace
