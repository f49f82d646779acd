/// The polyp ground truth as the shape checks read it (colon/polyp_truth.h): flat polyps' caps,
/// truth written before the sphere radius existed, and the phantom's random layouts read back.
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "colon/colon_error.h"
#include "colon/polyp_truth.h"
#include "volumes/colon_phantom.h"

namespace {

std::string writeTruth(const std::string& name, const std::string& text) {
    const std::string path = std::string(CVC_TEST_TMP_DIR) + "/" + name;
    std::ofstream(path, std::ios::trunc) << text;
    return path;
}

/// An 8 mm flat polyp on the plane z = 0: h = 2, R = (16 + 4) / 4 = 5, centre 3 mm below.
colon::PolypSurface flatCap() {
    colon::PolypSurface flat;
    flat.isFlat = true;
    flat.diameterMm = 8.0;
    flat.sphereRadiusMm = 5.0;
    flat.centreMm = glm::dvec3(0.0, 0.0, -3.0);
    flat.baseMm = glm::dvec3(0.0);
    flat.baseNormal = glm::dvec3(0.0, 0.0, 1.0);
    return flat;
}

TEST(PolypTruth, FlatCapIsThePolypAndTheWallIsNot) {
    const colon::PolypSurface flat = flatCap();
    EXPECT_TRUE(colon::isOnPolyp(flat, glm::dvec3(0.0, 0.0, 2.0), 0.1));                                // its top
    EXPECT_TRUE(colon::isOnPolyp(flat, glm::dvec3(2.0, 0.0, std::sqrt(21.0) - 3.0), 0.1));              // its slope
    EXPECT_TRUE(colon::isOnPolyp(flat, glm::dvec3(0.0, 4.0, 0.0), 0.1));                                // its rim
    EXPECT_FALSE(colon::isOnPolyp(flat, glm::dvec3(5.0, 0.0, 0.0), 0.1));                               // the wall beside it
    EXPECT_FALSE(colon::isOnPolyp(flat, glm::dvec3(0.0, 0.0, -1.0), 0.1));                              // under the wall
    EXPECT_FALSE(colon::isOnPolyp(flat, glm::dvec3(0.0, 0.0, 2.5), 0.1));                               // above its top
    // Its own sphere radius matters: as a 4 mm sphere its top would not be on it.
    colon::PolypSurface asHalfDiameter = flat;
    asHalfDiameter.sphereRadiusMm = 0.0;
    EXPECT_DOUBLE_EQ(asHalfDiameter.sphereRadius(), 4.0);
    EXPECT_FALSE(colon::isOnPolyp(asHalfDiameter, glm::dvec3(0.0, 0.0, 2.0), 0.1));
}

TEST(PolypTruth, AHitWellBeforeThePolypsOwnSurfaceHidesItTheRimDoesNot) {
    // A 6 mm hemisphere on the plane z = 0, seen straight down from 20 mm above its centre.
    colon::PolypSurface sessile;
    sessile.diameterMm = 6.0;
    sessile.baseNormal = glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec3 eye(0.0, 0.0, 20.0);
    const glm::dvec3 down(0.0, 0.0, -1.0);
    const double tolerance = 0.25;
    ASSERT_DOUBLE_EQ(colon::hiddenInFrontMarginMm(tolerance), 1.0);
    ASSERT_DOUBLE_EQ(colon::hiddenInFrontMarginMm(0.85), 1.7);  // a 3 mm scan's tolerance
    // Its own top (z = 3) and a hit just above it, within the margin: not hidden.
    EXPECT_FALSE(colon::isHiddenInFront(sessile, eye, down, glm::dvec3(0.0, 0.0, 3.0), tolerance));
    EXPECT_FALSE(colon::isHiddenInFront(sessile, eye, down, glm::dvec3(0.0, 0.0, 3.9), tolerance));
    // A fold 4 mm above its top: hidden.
    EXPECT_TRUE(colon::isHiddenInFront(sessile, eye, down, glm::dvec3(0.0, 0.0, 7.0), tolerance));
    // Beside the polyp the ray never meets it: nothing there to hide, whatever it hits.
    const glm::dvec3 besideEye(5.0, 0.0, 20.0);
    EXPECT_FALSE(colon::isHiddenInFront(sessile, besideEye, down, glm::dvec3(5.0, 0.0, 7.0), tolerance));
    // Seen at a grazing angle, the lowest quarter of the cap (here below z = 0.75) is its rim,
    // which a wall curving up around the base hides on every polyp: never counted. Higher up
    // the same side, within the margin is the polyp's own rounding, farther in front a fold.
    const glm::dvec3 grazing = glm::normalize(glm::dvec3(1.0, 0.0, -0.2));
    for (const double height : {0.3, 2.0}) {
        const glm::dvec3 onSurface(-std::sqrt(9.0 - height * height), 0.0, height);
        const glm::dvec3 grazingEye = onSurface - 20.0 * grazing;
        glm::dvec3 ownHit;
        ASSERT_TRUE(colon::firstPolypHit(sessile, grazingEye, grazing, ownHit));
        ASSERT_NEAR(glm::length(ownHit - onSurface), 0.0, 1e-9);
        EXPECT_FALSE(colon::isHiddenInFront(sessile, grazingEye, grazing, ownHit - 0.6 * grazing, tolerance));
        EXPECT_EQ(colon::isHiddenInFront(sessile, grazingEye, grazing, ownHit - 5.0 * grazing, tolerance), height > 0.75)
            << "at height " << height;
    }
}

TEST(PolypTruth, ReadsFlatPolypsAndTruthWithoutTheNewFields) {
    const std::string path = writeTruth(
        "polyp_truth_kinds.json",
        R"({"polyps": [{"kind": "sessile", "diameter_mm": 6.0, "centre_mm": [10, 10, 10], "base_mm": [10, 10, 10],
                        "base_normal": [0, 0, 1]},
                       {"kind": "pedunculated", "diameter_mm": 8.0, "centre_mm": [20, 10, 10], "base_mm": [20, 10, 4],
                        "base_normal": [0, 0, 2]},
                       {"kind": "flat", "diameter_mm": 8.0, "radius_mm": 4.0, "sphere_radius_mm": 5.0, "height_mm": 2.0,
                        "on_fold": true, "centre_mm": [0, 0, -3], "base_mm": [0, 0, 0], "base_normal": [0, 0, 1]}]})");
    const std::vector<colon::PolypSurface> polyps = colon::readPolypTruth(path);
    ASSERT_EQ(polyps.size(), 3u);
    EXPECT_TRUE(polyps[0].isSessile);
    EXPECT_FALSE(polyps[0].isFlat);
    EXPECT_DOUBLE_EQ(polyps[0].sphereRadius(), 3.0);  // no "sphere_radius_mm": half the diameter
    EXPECT_FALSE(polyps[1].isSessile);
    EXPECT_DOUBLE_EQ(polyps[1].sphereRadius(), 4.0);
    EXPECT_TRUE(polyps[2].isSessile);  // a flat polyp is cut by the wall plane like a sessile one
    EXPECT_TRUE(polyps[2].isFlat);
    EXPECT_DOUBLE_EQ(polyps[2].sphereRadius(), 5.0);
    EXPECT_TRUE(colon::isOnPolyp(polyps[2], glm::dvec3(0.0, 0.0, 2.0), 0.1));
}

TEST(PolypTruth, RefusesFlatPolypsWithoutASphereAndSpheresNarrowerThanTheBase) {
    const std::string base = R"("diameter_mm": 8, "centre_mm": [0, 0, 0], "base_mm": [0, 0, 0], "base_normal": [0, 0, 1])";
    const std::vector<std::string> bad = {R"({"kind": "flat", )" + base + "}",
                                          R"({"kind": "flat", "sphere_radius_mm": 3.9, )" + base + "}",
                                          R"({"kind": "sessile", "sphere_radius_mm": "4", )" + base + "}",
                                          R"({"kind": "cone", )" + base + "}"};
    for (const std::string& polyp : bad) {
        const std::string path = writeTruth("polyp_truth_bad_sphere.json", R"({"polyps": [)" + polyp + "]}");
        try {
            colon::readPolypTruth(path);
            ADD_FAILURE() << "accepted " << polyp;
        } catch (const colon::ColonError& e) {
            EXPECT_NE(std::string(e.what()).find("polyp 0"), std::string::npos) << e.what();
        }
    }
}

TEST(PolypTruth, RandomPhantomTruthReadsBack) {
    volumes::ColonPhantomSpec spec;
    spec.grid = {{96, 96, 96}, glm::dvec3(1.6)};
    spec.noiseSigmaHu = 0.0;
    spec.randomPolypCount = 16;
    spec.seed = 11;
    const volumes::ColonPhantom phantom = volumes::makeColonPhantom(spec);
    const std::string path = writeTruth("polyp_truth_random.json", volumes::colonTruthJson(spec, phantom));
    const std::vector<colon::PolypSurface> polyps = colon::readPolypTruth(path);
    ASSERT_EQ(polyps.size(), phantom.polyps.size());
    for (std::size_t i = 0; i < polyps.size(); ++i) {
        const volumes::PolypTruth& truth = phantom.polyps[i];
        const colon::PolypSurface& polyp = polyps[i];
        EXPECT_EQ(polyp.isFlat, truth.kind == volumes::PolypKind::Flat);
        EXPECT_EQ(polyp.isSessile, truth.kind != volumes::PolypKind::Pedunculated);
        EXPECT_DOUBLE_EQ(polyp.sphereRadius(), truth.sphereRadiusMm());
        // The top is on the polyp; the wall plane beside its base is not (for a sessile or flat one).
        EXPECT_TRUE(colon::isOnPolyp(polyp, truth.baseMm + truth.heightMm() * truth.baseNormal, 0.05));
        const glm::dvec3 across = glm::normalize(glm::cross(truth.baseNormal, glm::dvec3(0.36, 0.48, 0.8)));
        if (polyp.isSessile) {
            EXPECT_FALSE(colon::isOnPolyp(polyp, truth.baseMm + (truth.radiusMm + 1.0) * across, 0.05));
        }
    }
}

}  // namespace
