// The speed bound of a baked map (conformal/cube_map_speed.h) against maps whose speed is known
// in closed form: the identity and a rotation turn rays at speed 1 everywhere; a map that
// doubles the polar angle about +z turns them at speed 2 near the pole (and only there).
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "conformal/cube_map.h"
#include "conformal/cube_map_speed.h"

namespace {

std::vector<float> texelsOf(int size, const std::function<glm::dvec3(const glm::dvec3&)>& map) {
    std::vector<float> rgba;
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < size; ++j) {
            for (int i = 0; i < size; ++i) {
                const glm::dvec3 scene =
                    map(glm::normalize(conformal::directionFromCubeFace(face, (i + 0.5) / size, (j + 0.5) / size)));
                rgba.insert(rgba.end(), {float(scene.x), float(scene.y), float(scene.z), 1.0f});
            }
        }
    }
    return rgba;
}

double boundAt(const conformal::SpeedBoundMap& bounds, const glm::dvec3& direction) {
    const conformal::CubeFaceCoordinate c = conformal::cubeFaceFromDirection(direction);
    const int i = std::min(static_cast<int>(c.s * bounds.size), bounds.size - 1);
    const int j = std::min(static_cast<int>(c.t * bounds.size), bounds.size - 1);
    return bounds.rgba[((static_cast<std::size_t>(c.face) * bounds.size + j) * bounds.size + i) * 4];
}

TEST(SpeedBound, IdentityAndRotationTurnAtSpeedOne) {
    const glm::dmat3 rotation(glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1, 2, 3))));
    for (const auto& map : std::vector<std::function<glm::dvec3(const glm::dvec3&)>>{
             [](const glm::dvec3& d) { return d; }, [&](const glm::dvec3& d) { return rotation * d; }}) {
        const conformal::SpeedBoundMap bounds = conformal::speedBoundMap(128, texelsOf(128, map));
        ASSERT_EQ(bounds.size, 32);
        for (std::size_t k = 0; k < bounds.rgba.size(); k += 4) {
            // At least the true speed 1. The bound's own factor sqrt 2 (for directions oblique to
            // the grid) and, near face edges, seamless filtering's taps (the adjacent face's
            // nearest texel, up to half a texel from where the filter places it) add the rest.
            EXPECT_GE(bounds.rgba[k], 1.0f);
            EXPECT_LE(bounds.rgba[k], 2.0f);
        }
        // Far from the edges only the factor sqrt 2 and the interpolant's length remain.
        for (const glm::dvec3& centre : {glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1)}) {
            EXPECT_LE(boundAt(bounds, centre), 1.5);
        }
    }
}

TEST(SpeedBound, ADoubledPolarAngleIsBoundByTwoNearThePoleOnly) {
    // theta -> 2 theta about +z (up to 90 degrees, then the rest of the sphere squeezed): near
    // the pole the map stretches every direction by 2.
    const auto doubled = [](const glm::dvec3& d) {
        const double theta = std::acos(std::clamp(d.z, -1.0, 1.0));
        const double phi = std::atan2(d.y, d.x);
        const double pi = 3.14159265358979323846;
        const double mapped = theta < 0.25 * pi ? 2.0 * theta : 0.5 * pi + (theta - 0.25 * pi) * (0.5 * pi) / (0.75 * pi);
        return glm::dvec3(std::sin(mapped) * std::cos(phi), std::sin(mapped) * std::sin(phi), std::cos(mapped));
    };
    const conformal::SpeedBoundMap bounds = conformal::speedBoundMap(128, texelsOf(128, doubled));
    EXPECT_GE(boundAt(bounds, glm::dvec3(0.0, 0.0, 1.0)), 2.0);
    EXPECT_LE(boundAt(bounds, glm::dvec3(0.0, 0.0, 1.0)), 3.0);
    // Far from the pole the map compresses (speed 2/3 along meridians, at most 1 across them).
    EXPECT_LE(boundAt(bounds, glm::dvec3(0.0, 0.0, -1.0)), 1.5);
    EXPECT_GE(bounds.largest, 2.0);
}

TEST(SpeedBound, RefusesWrongSizes) {
    EXPECT_THROW(conformal::speedBoundMap(1, std::vector<float>(24, 0.0f)), std::invalid_argument);
    EXPECT_THROW(conformal::speedBoundMap(4, std::vector<float>(10, 0.0f)), std::invalid_argument);
}

}  // namespace
