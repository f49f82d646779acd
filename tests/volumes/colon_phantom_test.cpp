/// The colon phantom against its own ground truth: polyps are tissue where the JSON says, the
/// lumen is air along the centreline, noise has the requested strength and seed.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"
#include "tests/volumes/test_support.h"
#include "volumes/colon_phantom.h"
#include "volumes/load_volume.h"

namespace volumes {
namespace {

/// The default phantom, built once for the suite (about a second).
class ColonPhantomTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        spec = new ColonPhantomSpec();
        phantom = new ColonPhantom(makeColonPhantom(*spec));
    }
    static void TearDownTestSuite() {
        delete phantom;
        delete spec;
    }
    static int16_t huAtMm(const glm::dvec3& p) {
        const Volume& v = phantom->volume;
        const glm::ivec3 i(glm::round(p / v.spacingMm));
        return v.at(i.x, i.y, i.z);
    }
    static ColonPhantomSpec* spec;
    static ColonPhantom* phantom;
};
ColonPhantomSpec* ColonPhantomTest::spec = nullptr;
ColonPhantom* ColonPhantomTest::phantom = nullptr;

TEST_F(ColonPhantomTest, PolypsAreTissueInsideTheirRadius) {
    const Volume& v = phantom->volume;
    ASSERT_EQ(phantom->polyps.size(), spec->polyps.size());
    for (const PolypTruth& polyp : phantom->polyps) {
        // Every voxel centre at least half a voxel inside the sphere: tissue, not air.
        const double inner = polyp.radiusMm - 0.5 * spec->edgeWidthMm;
        const glm::ivec3 lo(glm::floor((polyp.centreMm - polyp.radiusMm) / v.spacingMm));
        const glm::ivec3 hi(glm::ceil((polyp.centreMm + polyp.radiusMm) / v.spacingMm));
        int checked = 0;
        for (int k = lo.z; k <= hi.z; ++k)
            for (int j = lo.y; j <= hi.y; ++j)
                for (int i = lo.x; i <= hi.x; ++i) {
                    if (glm::length(glm::dvec3(i, j, k) * v.spacingMm - polyp.centreMm) > inner) continue;
                    ++checked;
                    ASSERT_GT(v.at(i, j, k), -500)
                        << "voxel " << i << ',' << j << ',' << k << " in polyp of radius " << polyp.radiusMm;
                }
        EXPECT_GT(checked, 0);
        // And the polyp stands in air: just beyond its top, along the base normal, is lumen.
        const glm::dvec3 above = polyp.centreMm + (polyp.radiusMm + 1.5) * polyp.baseNormal;
        EXPECT_LT(huAtMm(above), -500) << "nothing but air should be above a polyp's top";
        // The base normal is a unit vector pointing into the lumen, the base on the wall.
        EXPECT_NEAR(glm::length(polyp.baseNormal), 1.0, 1e-9);
        EXPECT_GT(huAtMm(polyp.baseMm - 1.5 * polyp.baseNormal), -500) << "the wall behind the base is tissue";
    }
}

TEST_F(ColonPhantomTest, PolypKindsHaveTheirShape) {
    for (const PolypTruth& polyp : phantom->polyps) {
        if (polyp.kind == PolypKind::Sessile) {
            EXPECT_EQ(polyp.centreMm, polyp.baseMm);  // hemisphere on the wall
        } else {
            EXPECT_NEAR(glm::length(polyp.centreMm - polyp.baseMm), polyp.stalkLengthMm + polyp.radiusMm, 1e-9);
            // Beside the stalk, half-way up, is air: the head stands on a narrow stalk.
            const glm::dvec3 side = glm::normalize(glm::cross(polyp.baseNormal, glm::dvec3(0.3, 0.5, 0.8)));
            const glm::dvec3 beside = polyp.baseMm + 0.5 * polyp.stalkLengthMm * polyp.baseNormal +
                                      (std::max(1.0, 0.3 * polyp.radiusMm) + 2.0) * side;
            EXPECT_LT(huAtMm(beside), -500);
        }
    }
}

TEST_F(ColonPhantomTest, CentrelineRunsThroughAir) {
    // Every point, polyps and folds included: a fly-through along the centreline never
    // passes through tissue.
    std::size_t inAir = 0;
    for (const glm::dvec3& p : phantom->centrelineMm) inAir += huAtMm(p) < -900 ? 1 : 0;
    EXPECT_EQ(inAir, phantom->centrelineMm.size());
    EXPECT_GT(phantom->centrelineMm.size(), 200u);
}

TEST_F(ColonPhantomTest, TissueClassesAndNoise) {
    // Far from the tube (a corner), soft tissue with the requested noise.
    const Volume& v = phantom->volume;
    double sum = 0.0, sumSquares = 0.0;
    int n = 0;
    for (int k = 0; k < 20; ++k)
        for (int j = 0; j < 20; ++j)
            for (int i = 0; i < 20; ++i) {
                const double hu = v.at(i, j, k);
                sum += hu;
                sumSquares += hu * hu;
                ++n;
            }
    const double mean = sum / n, sigma = std::sqrt(sumSquares / n - mean * mean);
    EXPECT_NEAR(mean, spec->tissueHu, 2.0);
    EXPECT_NEAR(sigma, spec->noiseSigmaHu, 2.0);
    // The fat band: just outside the wall, away from folds and polyps, HU near -100.
    const glm::dvec3 p = phantom->centrelineMm[phantom->centrelineMm.size() / 2 + 7];
    const glm::dvec3 q = phantom->centrelineMm[phantom->centrelineMm.size() / 2 + 8];
    const glm::dvec3 side = glm::normalize(glm::cross(q - p, glm::dvec3(0.0, 0.0, 1.0)));
    const double fatMm = spec->lumenRadiusMm + spec->wallThicknessMm + 0.5 * spec->fatThicknessMm;
    EXPECT_NEAR(huAtMm(p + fatMm * side), spec->fatHu, 60.0);
}

TEST_F(ColonPhantomTest, SameSeedSameVolume) {
    ColonPhantomSpec small;
    small.grid = {{96, 96, 96}, glm::dvec3(1.6)};
    const ColonPhantom a = makeColonPhantom(small), b = makeColonPhantom(small);
    EXPECT_EQ(a.volume.hu, b.volume.hu);
    small.seed = 2;
    EXPECT_NE(makeColonPhantom(small).volume.hu, a.volume.hu);
}

TEST(ColonPhantom, RefusesImpossibleSpecs) {
    ColonPhantomSpec spec;
    spec.grid = {{64, 64, 64}, glm::dvec3(0.5)};  // 32 mm: too small for the tube
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec = ColonPhantomSpec();
    spec.grid = {{96, 96, 96}, glm::dvec3(1.6)};
    spec.polyps = {{PolypKind::Pedunculated, 15.0, 0.5, 0.0, 8.0}};  // 23 mm tall in a 22 mm lumen
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.polyps = {{PolypKind::Pedunculated, 8.0, 0.5, 0.0, 2.0}};  // 10 mm: would reach within 1 mm of the centreline
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.polyps = {{PolypKind::Sessile, 20.0, 0.5, 0.0, 0.0}};
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    for (const char* bad : {"", "flat:6:0.5:0", "sessile:6:0.5", "sessile:2:0.5:0", "sessile:6:1.5:0",
                            "sessile:x:0.5:0", "pedunculated:8:0.5:0:4:9"}) {
        EXPECT_THROW(parsePolypSpec(bad), VolumeError) << bad;
    }
    const PolypSpec p = parsePolypSpec("pedunculated:8:0.25:120:5");
    EXPECT_EQ(p.kind, PolypKind::Pedunculated);
    EXPECT_DOUBLE_EQ(p.diameterMm, 8.0);
    EXPECT_DOUBLE_EQ(p.arcFraction, 0.25);
    EXPECT_DOUBLE_EQ(p.angleDeg, 120.0);
    EXPECT_DOUBLE_EQ(p.stalkLengthMm, 5.0);
}

TEST(CvcPhantom, WritesColonVolumeAndGroundTruth) {
    const std::string folder = testing::scratchFolder("cvc_phantom");
    const auto run = testing_support::runCvc(
        "phantom --size 112 --spacing 1.4 --seed 3 --polyp sessile:7:0.3:0 "
        "--polyp pedunculated:6:0.7:180:3 -o '" +
        folder + "/colon.vdb'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const LoadedVolume loaded = loadVolumeWithBricks(folder + "/colon.vdb");
    EXPECT_EQ(loaded.volume.dims, (std::array<int, 3>{112, 112, 112}));
    std::ifstream in(folder + "/colon.json");
    const nlohmann::json truth = nlohmann::json::parse(in);
    ASSERT_EQ(truth["polyps"].size(), 2u);
    EXPECT_EQ(truth["polyps"][1]["kind"], "pedunculated");
    EXPECT_DOUBLE_EQ(truth["polyps"][0]["diameter_mm"].get<double>(), 7.0);
    EXPECT_GT(truth["centreline_mm"].size(), 100u);
    // The JSON's polyp centre is tissue in the volume read back from disk.
    const auto c = truth["polyps"][0]["centre_mm"];
    const glm::ivec3 i(glm::round(glm::dvec3(c[0].get<double>(), c[1].get<double>(), c[2].get<double>()) / 1.4));
    EXPECT_GT(loaded.volume.at(i.x, i.y, i.z), -500);
    // Existing outputs are kept without --force.
    const auto again = testing_support::runCvc("phantom --size 112 --spacing 1.4 -o '" + folder + "/colon.vdb'");
    EXPECT_NE(again.exitCode, 0);
    EXPECT_NE(again.err.find("exists already"), std::string::npos) << again.err;
}

}  // namespace
}  // namespace volumes
