/// The colon phantom against its own ground truth: polyps are tissue where the JSON says, the
/// lumen is air along the centreline, noise has the requested strength and seed.
#include <algorithm>
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
    for (const char* bad : {"", "cone:6:0.5:0", "sessile:6:0.5", "sessile:2:0.5:0", "sessile:6:1.5:0",
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


// ---- Anatomy around the colon: shape seeds, body, lungs, collapses, fluid pools ----

/// Voxels connected (6-neighbours) to `start` whose HU is below `belowHu`.
std::vector<uint8_t> floodBelow(const Volume& v, const glm::ivec3& start, int belowHu) {
    std::vector<uint8_t> reached(v.voxelCount(), 0);
    if (v.at(start.x, start.y, start.z) >= belowHu) return reached;
    std::vector<glm::ivec3> stack{start};
    reached[v.linearIndex(start.x, start.y, start.z)] = 1;
    const glm::ivec3 steps[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    while (!stack.empty()) {
        const glm::ivec3 at = stack.back();
        stack.pop_back();
        for (const glm::ivec3& step : steps) {
            const glm::ivec3 n = at + step;
            if (n.x < 0 || n.y < 0 || n.z < 0 || n.x >= v.dims[0] || n.y >= v.dims[1] || n.z >= v.dims[2]) continue;
            const std::size_t index = v.linearIndex(n.x, n.y, n.z);
            if (reached[index] || v.hu[index] >= belowHu) continue;
            reached[index] = 1;
            stack.push_back(n);
        }
    }
    return reached;
}

glm::ivec3 nearestVoxel(const Volume& v, const glm::dvec3& p) { return glm::ivec3(glm::round(p / v.spacingMm)); }

/// Arc lengths of the centreline's vertices.
std::vector<double> arcLengths(const std::vector<glm::dvec3>& line) {
    std::vector<double> arc{0.0};
    for (std::size_t i = 1; i < line.size(); ++i) arc.push_back(arc.back() + glm::length(line[i] - line[i - 1]));
    return arc;
}

ColonPhantomSpec smallSpec() {
    ColonPhantomSpec spec;
    spec.grid = {{128, 128, 128}, glm::dvec3(1.2)};
    return spec;
}

/// withAnatomy at 128^3 x 1.2 mm, built once for the suite.
class ColonAnatomyPhantomTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        spec = new ColonPhantomSpec(ColonPhantomSpec::withAnatomy(smallSpec()));
        phantom = new ColonPhantom(makeColonPhantom(*spec));
    }
    static void TearDownTestSuite() {
        delete phantom;
        delete spec;
    }
    static ColonPhantomSpec* spec;
    static ColonPhantom* phantom;
};
ColonPhantomSpec* ColonAnatomyPhantomTest::spec = nullptr;
ColonPhantom* ColonAnatomyPhantomTest::phantom = nullptr;

TEST(ColonPhantomShape, SeedsGiveDifferentCurvesAndTheSameSeedTheSameVolume) {
    ColonPhantomSpec spec = smallSpec();
    const ColonPhantom standard = makeColonPhantom(spec);
    spec.shapeSeed = 7;
    const ColonPhantom a = makeColonPhantom(spec), b = makeColonPhantom(spec);
    EXPECT_EQ(a.volume.hu, b.volume.hu);
    EXPECT_EQ(a.centrelineMm, b.centrelineMm);
    spec.shapeSeed = 8;
    const ColonPhantom c = makeColonPhantom(spec);
    // Compare the curves at the same fractions of their length: a visible change (> 4 mm).
    auto farthestApart = [](const std::vector<glm::dvec3>& p, const std::vector<glm::dvec3>& q) {
        double worst = 0.0;
        for (int f = 0; f <= 20; ++f) {
            const glm::dvec3 x = p[(p.size() - 1) * static_cast<std::size_t>(f) / 20];
            const glm::dvec3 y = q[(q.size() - 1) * static_cast<std::size_t>(f) / 20];
            worst = std::max(worst, glm::length(x - y));
        }
        return worst;
    };
    EXPECT_GT(farthestApart(standard.centrelineMm, a.centrelineMm), 4.0);
    EXPECT_GT(farthestApart(a.centrelineMm, c.centrelineMm), 4.0);
    EXPECT_NE(a.volume.hu, c.volume.hu);
    // The caecum stays on the patient's right (small x) of the rectal end, both at the bottom.
    for (const ColonPhantom* p : {&standard, &a, &c}) {
        EXPECT_LT(p->centrelineMm.front().x + 30.0, p->centrelineMm.back().x);
        EXPECT_LT(p->centrelineMm.front().z, 0.3 * 127 * 1.2);
        EXPECT_LT(p->centrelineMm.back().z, 0.3 * 127 * 1.2);
    }
}

TEST_F(ColonAnatomyPhantomTest, OutsideTheBodyIsAirThatReachesTheFacesAndNotTheColon) {
    const Volume& v = phantom->volume;
    const BodyTruth& body = phantom->body;
    ASSERT_GT(body.semiAxesMm.x, 0.0);
    EXPECT_NEAR(body.semiAxesMm.x, 0.48 * 127 * 1.2, 1e-9);
    EXPECT_NEAR(body.semiAxesMm.y, 0.46 * 127 * 1.2, 1e-9);
    // From a corner, the air outside reaches every voxel well outside the ellipse (and so the
    // middle of each x and y face), but none inside it.
    const std::vector<uint8_t> outside = floodBelow(v, {0, 0, v.dims[2] / 2}, -800);
    std::size_t outsideVoxels = 0;
    for (int k = 0; k < v.dims[2]; k += 3)
        for (int j = 0; j < v.dims[1]; ++j)
            for (int i = 0; i < v.dims[0]; ++i) {
                const glm::dvec3 p = glm::dvec3(i, j, k) * v.spacingMm;
                const double q = std::hypot((p.x - body.centreMm.x) / body.semiAxesMm.x,
                                            (p.y - body.centreMm.y) / body.semiAxesMm.y);
                const bool isOut = outside[v.linearIndex(i, j, k)] != 0;
                if (q > 1.03) {
                    ASSERT_TRUE(isOut) << "voxel " << i << ',' << j << ',' << k << " outside the body is "
                                       << v.at(i, j, k) << " HU";
                    ++outsideVoxels;
                }
                if (q < 0.97) {
                    ASSERT_FALSE(isOut) << "voxel " << i << ',' << j << ',' << k << " inside the body";
                }
            }
    EXPECT_GT(outsideVoxels, 1000u);
    EXPECT_TRUE(outside[v.linearIndex(0, v.dims[1] / 2, 5)]);           // an x face
    EXPECT_TRUE(outside[v.linearIndex(v.dims[0] / 2, v.dims[1] - 1, 5)]);  // a y face
    // The colon's air is inside: the centreline is air the outside does not reach.
    for (const glm::dvec3& p : phantom->centrelineMm) {
        const glm::ivec3 i = nearestVoxel(v, p);
        ASSERT_FALSE(outside[v.linearIndex(i.x, i.y, i.z)]);
    }
}

TEST_F(ColonAnatomyPhantomTest, LungsAreParenchymaAtTheTopClearOfTheColon) {
    const Volume& v = phantom->volume;
    ASSERT_EQ(phantom->lungs.size(), 2u);
    EXPECT_GE(phantom->lungClearanceMm, 3.0);
    const double tubeMm = spec->lumenRadiusMm + spec->wallThicknessMm + spec->fatThicknessMm;
    for (const LungTruth& lung : phantom->lungs) {
        std::vector<int> values;
        bool reachesTop = false;
        for (int k = 0; k < v.dims[2]; ++k)
            for (int j = 0; j < v.dims[1]; ++j)
                for (int i = 0; i < v.dims[0]; ++i) {
                    const glm::dvec3 p = glm::dvec3(i, j, k) * v.spacingMm;
                    const glm::dvec3 u = (p - lung.centreMm) / lung.semiAxesMm;
                    if (glm::dot(u, u) > 0.85) continue;  // well inside, past the ramp
                    values.push_back(v.at(i, j, k));
                    reachesTop = reachesTop || k == v.dims[2] - 1;
                    if (values.size() % 7 == 0) {  // a sample of them: far from the colon's fat
                        double nearest = 1e9;
                        for (const glm::dvec3& c : phantom->centrelineMm) nearest = std::min(nearest, glm::length(p - c));
                        ASSERT_GT(nearest, tubeMm + 3.0);
                    }
                }
        ASSERT_GT(values.size(), 500u) << lung.side;
        std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
        EXPECT_NEAR(values[values.size() / 2], spec->lungHu, 30) << lung.side;
        EXPECT_TRUE(reachesTop) << lung.side << " lung should be cut by the top face";
    }
    EXPECT_LT(phantom->lungs[0].centreMm.x, phantom->lungs[1].centreMm.x);  // right, then left
}

TEST_F(ColonAnatomyPhantomTest, CollapseClosesTheLumenAndSplitsItsAir) {
    const Volume& v = phantom->volume;
    ASSERT_EQ(phantom->collapsedArcMm.size(), 1u);
    const auto [s0, s1] = phantom->collapsedArcMm[0];
    const std::vector<double> arc = arcLengths(phantom->centrelineMm);
    const double centre = spec->collapses[0].arcFraction * arc.back();
    EXPECT_LT(s0, centre - 0.5 * spec->collapses[0].lengthMm);
    EXPECT_GT(s1, centre + 0.5 * spec->collapses[0].lengthMm);
    std::size_t closed = 0, before = 0, after = 0;
    for (std::size_t i = 0; i < arc.size(); ++i) {
        const glm::ivec3 p = nearestVoxel(v, phantom->centrelineMm[i]);
        if (arc[i] >= s0 && arc[i] <= s1) {
            ++closed;
            EXPECT_GT(v.at(p.x, p.y, p.z), -500) << "centreline at " << arc[i] << " mm in the collapse";
        }
        if (arc[i] < s0 - 15.0) before = i;
        if (after == 0 && arc[i] > s1 + 15.0) after = i;
    }
    EXPECT_GT(closed, 10u);
    const std::vector<uint8_t> air = floodBelow(v, nearestVoxel(v, phantom->centrelineMm[before]), -800);
    const glm::ivec3 start = nearestVoxel(v, phantom->centrelineMm[10]);
    const glm::ivec3 end = nearestVoxel(v, phantom->centrelineMm[after]);
    EXPECT_TRUE(air[v.linearIndex(start.x, start.y, start.z)]) << "the caecum side is one component";
    EXPECT_FALSE(air[v.linearIndex(end.x, end.y, end.z)]) << "the air on both sides of the collapse must not connect";
    const glm::ivec3 rectal = nearestVoxel(v, phantom->centrelineMm[phantom->centrelineMm.size() - 10]);
    EXPECT_TRUE(floodBelow(v, end, -800)[v.linearIndex(rectal.x, rectal.y, rectal.z)])
        << "the rectal side is the other component";
}

TEST_F(ColonAnatomyPhantomTest, FluidLiesBelowItsLevelInItsArcRangeOnly) {
    const Volume& v = phantom->volume;
    ASSERT_EQ(phantom->fluidPools.size(), 1u);
    const FluidPoolTruth pool = phantom->fluidPools[0];
    const std::vector<glm::dvec3>& line = phantom->centrelineMm;
    const std::vector<double> arc = arcLengths(line);
    EXPECT_NEAR(pool.endArcMm - pool.startArcMm, spec->fluidPools[0].lengthMm, 1e-9);
    double lowest = -1e9;
    for (std::size_t i = 0; i < line.size(); ++i)
        if (arc[i] >= pool.startArcMm && arc[i] <= pool.endArcMm) lowest = std::max(lowest, line[i].y + spec->lumenRadiusMm);
    EXPECT_NEAR(pool.levelYMm, lowest - spec->fluidPools[0].depthMm, 1e-9);
    // Voxels around the pool and 30 mm either side, by their nearest centreline vertex.
    glm::dvec3 lo(1e9), hi(-1e9);
    for (std::size_t i = 0; i < line.size(); ++i)
        if (arc[i] >= pool.startArcMm - 30.0 && arc[i] <= pool.endArcMm + 30.0) {
            lo = glm::min(lo, line[i] - spec->lumenRadiusMm);
            hi = glm::max(hi, line[i] + spec->lumenRadiusMm);
        }
    const double e = spec->edgeWidthMm;
    std::size_t fluid = 0, air = 0;
    const glm::ivec3 ilo(glm::ceil(lo / v.spacingMm)), ihi(glm::floor(hi / v.spacingMm));
    for (int k = ilo.z; k <= ihi.z; ++k)
        for (int j = ilo.y; j <= ihi.y; ++j)
            for (int i = ilo.x; i <= ihi.x; ++i) {
                const glm::dvec3 p = glm::dvec3(i, j, k) * v.spacingMm;
                double d = 1e9, s = 0.0;
                for (std::size_t c = 0; c < line.size(); ++c) {
                    const double dc = glm::length(p - line[c]);
                    if (dc < d) d = dc, s = arc[c];
                }
                if (d > spec->lumenRadiusMm - e) continue;  // not inside the lumen
                const int16_t hu = v.at(i, j, k);
                if (s < pool.startArcMm - e || s > pool.endArcMm + e) {
                    ASSERT_LE(hu, 200) << "fluid outside the pool's arc range at " << s << " mm";
                    continue;
                }
                const bool nearFold = std::any_of(phantom->foldArcLengthsMm.begin(), phantom->foldArcLengthsMm.end(),
                                                  [&](double f) { return std::abs(f - s) < spec->foldHalfWidthMm + e; });
                if (nearFold || s < pool.startArcMm + e || s > pool.endArcMm - e) continue;
                if (p.y > pool.levelYMm + e) {
                    ++fluid;
                    ASSERT_GT(hu, 200) << "below the level at y " << p.y << " (level " << pool.levelYMm << ")";
                } else if (p.y < pool.levelYMm - e) {
                    ++air;
                    ASSERT_LT(hu, -800) << "above the level at y " << p.y;
                }
            }
    EXPECT_GT(fluid, 100u);
    EXPECT_GT(air, 1000u);
}

TEST_F(ColonAnatomyPhantomTest, TruthJsonDescribesTheAnatomy) {
    const nlohmann::json truth = nlohmann::json::parse(colonTruthJson(*spec, *phantom));
    EXPECT_EQ(truth["centreline_start"], "caecum");
    EXPECT_EQ(truth["centreline_end"], "rectum");
    EXPECT_EQ(truth["centreline_order"], "caecum_to_rectum");
    EXPECT_EQ(truth["shape_seed"].get<std::uint64_t>(), 0u);
    EXPECT_DOUBLE_EQ(truth["body"]["semi_axes_mm"][0].get<double>(), phantom->body.semiAxesMm.x);
    EXPECT_DOUBLE_EQ(truth["body"]["centre_mm"][1].get<double>(), phantom->body.centreMm.y);
    ASSERT_EQ(truth["lungs"].size(), 2u);
    EXPECT_EQ(truth["lungs"][0]["hu"].get<int>(), -860);
    EXPECT_DOUBLE_EQ(truth["lungs"][1]["semi_axes_mm"][2].get<double>(), phantom->lungs[1].semiAxesMm.z);
    ASSERT_EQ(truth["collapsed_arc_mm"].size(), 1u);
    EXPECT_DOUBLE_EQ(truth["collapsed_arc_mm"][0][1].get<double>(), phantom->collapsedArcMm[0][1]);
    ASSERT_EQ(truth["fluid_pools"].size(), 1u);
    EXPECT_DOUBLE_EQ(truth["fluid_pools"][0]["level_y_mm"].get<double>(), phantom->fluidPools[0].levelYMm);
    EXPECT_DOUBLE_EQ(truth["fluid_pools"][0]["arc_mm"][0].get<double>(), phantom->fluidPools[0].startArcMm);
    EXPECT_EQ(truth["fluid_pools"][0]["hu"].get<int>(), 600);
    EXPECT_EQ(truth["fluid_hu"].get<int>(), 600);
    // Without anatomy: the order keys, and none of the anatomy's.
    const ColonPhantomSpec plain = smallSpec();
    const nlohmann::json plainTruth = nlohmann::json::parse(colonTruthJson(plain, makeColonPhantom(plain)));
    EXPECT_EQ(plainTruth["centreline_order"], "caecum_to_rectum");
    for (const char* key : {"body", "lungs", "collapsed_arc_mm", "fluid_pools", "fluid_hu"})
        EXPECT_FALSE(plainTruth.contains(key)) << key;
}

TEST(ColonPhantomAnatomy, RefusesAnatomyThatCannotBe) {
    ColonPhantomSpec spec = smallSpec();
    spec.collapses = {{0.33, 12.0}};  // on the pedunculated polyp
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.collapses = {{0.01, 12.0}};  // no lumen before it
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.collapses = {{0.42, 12.0}, {0.44, 12.0}};  // overlapping
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.collapses = {{0.42, -1.0}};
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.collapses.clear();
    spec.fluidPools = {{0.68, 40.0, 6.0}};  // would submerge the 12 mm polyp
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.fluidPools = {{0.40, 40.0, 6.0}};
    spec.collapses = {{0.42, 12.0}};  // fluid in a collapse
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    spec.collapses.clear();
    spec.fluidPools = {{0.238, 40.0, 30.0}};  // deeper than the lumen
    EXPECT_THROW(makeColonPhantom(spec), VolumeError);
    for (const char* bad : {"", "x", "1.5", "0.4:0", "0.4:12:3", "0.4:-2"}) EXPECT_THROW(parseCollapseSpec(bad), VolumeError) << bad;
    for (const char* bad : {"", "0.5:40:6:1", "-0.1", "0.5:40:0", "0.5:forty"})
        EXPECT_THROW(parseFluidPoolSpec(bad), VolumeError) << bad;
    EXPECT_DOUBLE_EQ(parseCollapseSpec("0.3").lengthMm, 12.0);
    EXPECT_DOUBLE_EQ(parseCollapseSpec("0.3:20").lengthMm, 20.0);
    const FluidPoolSpec pool = parseFluidPoolSpec("0.6:30:4");
    EXPECT_DOUBLE_EQ(pool.arcFraction, 0.6);
    EXPECT_DOUBLE_EQ(pool.lengthMm, 30.0);
    EXPECT_DOUBLE_EQ(pool.depthMm, 4.0);
}

TEST(CvcPhantom, WritesAnatomyAndItsGroundTruth) {
    const std::string folder = testing::scratchFolder("cvc_phantom_anatomy");
    const auto run = testing_support::runCvc("phantom --anatomy --size 128 --spacing 1.2 -o '" + folder + "/colon.nrrd'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    std::ifstream in(folder + "/colon.json");
    const nlohmann::json truth = nlohmann::json::parse(in);
    EXPECT_EQ(truth["centreline_order"], "caecum_to_rectum");
    EXPECT_TRUE(truth.contains("body"));
    EXPECT_EQ(truth["lungs"].size(), 2u);
    EXPECT_EQ(truth["collapsed_arc_mm"].size(), 1u);
    EXPECT_EQ(truth["fluid_pools"].size(), 1u);
    const LoadedVolume loaded = loadVolumeWithBricks(folder + "/colon.nrrd");
    EXPECT_LT(loaded.volume.at(0, 0, 64), -900);  // outside the body
    // Single options, and one clear error for a bad value.
    const auto single = testing_support::runCvc("phantom --size 128 --spacing 1.2 --shape-seed 3 --body "
                                                "--collapse 0.42 --fluid 0.238:30:5 -o '" + folder + "/one.nrrd'");
    ASSERT_EQ(single.exitCode, 0) << single.err;
    std::ifstream oneIn(folder + "/one.json");
    const nlohmann::json one = nlohmann::json::parse(oneIn);
    EXPECT_EQ(one["shape_seed"].get<int>(), 3);
    EXPECT_FALSE(one.contains("lungs"));
    EXPECT_NEAR(one["fluid_pools"][0]["arc_mm"][1].get<double>() - one["fluid_pools"][0]["arc_mm"][0].get<double>(), 30.0, 1e-9);
    const auto bad = testing_support::runCvc("phantom --size 128 --spacing 1.2 --collapse 0.4:x -o '" + folder + "/bad.nrrd'");
    EXPECT_NE(bad.exitCode, 0);
    EXPECT_NE(bad.err.find("cvc: error: collapse '0.4:x'"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace volumes
