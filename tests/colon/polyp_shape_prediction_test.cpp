// The map-only shape prediction against closed forms: through the identity nothing changes;
// through a Möbius transformation of the sphere (conformal, and it sends circles to circles
// however large) nothing changes either, though its scale varies across the polyp by a fifth;
// through a stretch of the gnomonic plane by 1.3 the aspect is 1.3 and the circularity
// 2 * 1.3 / (1.3^2 + 1); a polyp whose centre no displayed direction shows is not found; a
// polyp's own outline, a D seen from the side, goes through the stretch as its moments say.
#include <cmath>
#include <complex>
#include <stdexcept>

#include <gtest/gtest.h>

#include "colon/polyp_shape_prediction.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

double radians(double degrees) { return degrees * kPi / 180.0; }

/// Stereographic projection from the north pole (+z) and back.
std::complex<double> planeFromSphere(const glm::dvec3& d) { return {d.x / (1.0 - d.z), d.y / (1.0 - d.z)}; }
glm::dvec3 sphereFromPlane(std::complex<double> w) {
    const double r2 = std::norm(w);
    return glm::dvec3(2.0 * w.real(), 2.0 * w.imag(), r2 - 1.0) / (r2 + 1.0);
}

TEST(PolypShapePrediction, IdentityChangesNothing) {
    const colon::SceneFromDisplay identity = [](const glm::dvec3& d) { return d; };
    const glm::dvec3 scene = glm::normalize(glm::dvec3(0.3, 0.8, -0.5));
    const colon::PredictedShape p = colon::predictPolypShape(identity, scene, radians(5.0));
    ASSERT_TRUE(p.isFound);
    EXPECT_LT(glm::length(p.displayDirection - scene), 1e-6);
    EXPECT_LT(p.aspectError, 1e-3);
    EXPECT_LT(p.circularityError, 1e-3);
    EXPECT_LT(p.gridAngleErrorDeg, 0.05);
    EXPECT_NEAR(p.reference.aspect, 1.0, 2e-3);
    EXPECT_NEAR(p.reference.circularity, 1.0, 3e-3);
    EXPECT_NEAR(p.displayRadiusRad, radians(5.0), radians(0.1));
}

// w -> 3 w + 0.4 in the stereographic plane: a Möbius transformation. Its scale changes by a
// fifth or more across the polyp's 10-degree radius, yet the image of a circle is a circle.
TEST(PolypShapePrediction, MoebiusTransformationKeepsCirclesRound) {
    const colon::SceneFromDisplay moebius = [](const glm::dvec3& d) {
        if (d.z > 1.0 - 1e-12) return glm::dvec3(0.0, 0.0, 1.0);
        return sphereFromPlane(3.0 * planeFromSphere(d) + 0.4);
    };
    const glm::dvec3 scene = glm::normalize(glm::dvec3(0.6, 0.2, 0.2));
    const colon::PredictedShape p = colon::predictPolypShape(moebius, scene, radians(10.0));
    ASSERT_TRUE(p.isFound);
    EXPECT_LT(glm::length(moebius(p.displayDirection) - scene), 1e-6);
    EXPECT_LT(p.aspectError, 3e-3);
    EXPECT_LT(p.circularityError, 3e-3);
    // What makes the test: the map's scale (scene radians per display radian) differs across the
    // image by a fifth or more.
    const glm::dvec3 across = glm::normalize(glm::cross(p.displayDirection, glm::dvec3(0.0, 0.0, 1.0)));
    const auto scaleAt = [&](const glm::dvec3& d) {
        const double h = 1e-5;
        return glm::length(moebius(glm::normalize(d + h * across)) - moebius(d)) / h;
    };
    const glm::dvec3 toward = glm::normalize(glm::cross(across, p.displayDirection));
    const double near = scaleAt(glm::normalize(p.displayDirection + std::tan(p.displayRadiusRad) * toward));
    const double far = scaleAt(glm::normalize(p.displayDirection - std::tan(p.displayRadiusRad) * toward));
    EXPECT_GT(std::max(near, far) / std::min(near, far), 1.2) << near << " " << far;
}

// In gnomonic coordinates about +z the map (u, v) -> (1.3 u, v) is linear: the preimage of the
// polyp's circle is an ellipse of axis ratio 1.3, and the painted grid stays square.
TEST(PolypShapePrediction, StretchHasTheClosedFormAspectAndCircularity) {
    const colon::SceneFromDisplay stretch = [](const glm::dvec3& d) {
        return glm::normalize(glm::dvec3(1.3 * d.x, d.y, d.z));
    };
    const colon::PredictedShape p = colon::predictPolypShape(stretch, glm::dvec3(0.0, 0.0, 1.0), radians(6.0));
    ASSERT_TRUE(p.isFound);
    EXPECT_NEAR(p.view.aspect, 1.3, 4e-3);
    EXPECT_NEAR(p.aspectError, 0.3, 5e-3);
    EXPECT_NEAR(p.circularityError, 1.0 - 2.0 * 1.3 / (1.3 * 1.3 + 1.0), 3e-3);
    EXPECT_LT(p.gridAngleErrorDeg, 0.2);
}

// A display lacking the directions above 30 degrees of elevation (the map returns nothing
// there): a polyp whose centre maps from none of the shown directions is not found, and one
// half in view has its cut-off image measured.
TEST(PolypShapePrediction, MissingDirectionsAreNotShown) {
    const colon::SceneFromDisplay shown = [](const glm::dvec3& d) {
        return d.y > std::sin(radians(30.0)) ? glm::dvec3(0.0) : d;
    };
    const colon::PredictedShape hidden =
        colon::predictPolypShape(shown, glm::dvec3(0.0, std::sin(radians(60.0)), -std::cos(radians(60.0))), radians(5.0));
    EXPECT_FALSE(hidden.isFound);
    EXPECT_EQ(hidden.view.pixels, 0);
    const colon::PredictedShape cut =
        colon::predictPolypShape(shown, glm::dvec3(0.0, std::sin(radians(29.0)), -std::cos(radians(29.0))), radians(5.0));
    ASSERT_TRUE(cut.isFound);
    EXPECT_GT(cut.aspectError, 0.2);  // the outline's top 4 degrees are cut away
}

// A polyp's own outline: a whole sphere (a pedunculated polyp's head) predicts as its circle
// does. A sessile hemisphere seen 70 degrees off its axis has a D-shaped outline; through a
// stretch of the gnomonic plane (linear there) its second moments M become S M S, S the
// stretch's inverse: the predicted aspect is the closed form from the outline's own measures.
TEST(PolypShapePrediction, APolypsOwnOutlineGoesThroughTheMap) {
    const colon::SceneFromDisplay stretch = [](const glm::dvec3& d) {
        return glm::normalize(glm::dvec3(1.3 * d.x, d.y, d.z));
    };
    const glm::dvec3 ahead(0.0, 0.0, 1.0);
    const double distance = 40.0, radius = 3.5;
    colon::PolypSurface head;
    head.isSessile = false;
    head.diameterMm = 2.0 * radius;
    head.centreMm = distance * ahead;
    head.baseMm = head.centreMm;
    head.baseNormal = -ahead;
    const colon::PredictedShape circle = colon::predictPolypShape(stretch, ahead, std::asin(radius / distance));
    const colon::PredictedShape sphere = colon::predictPolypShape(stretch, head);
    ASSERT_TRUE(circle.isFound && sphere.isFound);
    EXPECT_NEAR(sphere.aspectError, circle.aspectError, 2e-3);

    colon::PolypSurface cap;  // its axis 70 degrees off the line of sight, tilted about x + y
    const glm::dvec3 side = glm::normalize(glm::dvec3(1.0, 1.0, 0.0));
    cap.baseNormal = std::cos(glm::radians(70.0)) * -ahead + std::sin(glm::radians(70.0)) * side;
    cap.diameterMm = 2.0 * radius;
    cap.baseMm = distance * ahead;
    cap.centreMm = cap.baseMm;
    const colon::PredictedShape oblique = colon::predictPolypShape(stretch, cap);
    ASSERT_TRUE(oblique.isFound);
    EXPECT_GT(oblique.reference.aspect, 1.4);
    // The reference's ellipse of second moments, then its image.
    const double a = oblique.reference.aspect, theta = glm::radians(oblique.reference.orientationDeg);
    const glm::dmat2 rotation(std::cos(theta), std::sin(theta), -std::sin(theta), std::cos(theta));
    const glm::dmat2 moments = rotation * glm::dmat2(a * a, 0.0, 0.0, 1.0) * glm::transpose(rotation);
    const glm::dmat2 inverseStretch(1.0 / 1.3, 0.0, 0.0, 1.0);
    const glm::dmat2 image = inverseStretch * moments * inverseStretch;
    const double half = 0.5 * (image[0][0] + image[1][1]);
    const double root = std::sqrt(0.25 * (image[0][0] - image[1][1]) * (image[0][0] - image[1][1]) + image[0][1] * image[0][1]);
    EXPECT_NEAR(oblique.view.aspect, std::sqrt((half + root) / (half - root)), 0.01);
    const colon::SceneFromDisplay identity = [](const glm::dvec3& d) { return d; };
    EXPECT_LT(colon::predictPolypShape(identity, cap).aspectError, 1e-3);
}

TEST(PolypShapePrediction, RefusesBadInput) {
    const colon::SceneFromDisplay identity = [](const glm::dvec3& d) { return d; };
    EXPECT_THROW(colon::predictPolypShape(identity, glm::dvec3(0.0), radians(5.0)), std::invalid_argument);
    EXPECT_THROW(colon::predictPolypShape(identity, glm::dvec3(0.0, 0.0, 1.0), 0.0), std::invalid_argument);
    EXPECT_THROW(colon::predictPolypShape(identity, glm::dvec3(0.0, 0.0, 1.0), radians(45.0)), std::invalid_argument);
    EXPECT_THROW(colon::predictPolypShape(identity, glm::dvec3(0.0, 0.0, 1.0), radians(5.0), 8), std::invalid_argument);
}

}  // namespace
