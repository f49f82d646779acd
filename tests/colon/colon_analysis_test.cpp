// The colon analysis end to end: centrelines against the phantoms' ground truth (default and
// other shapes, with polyps, folds, a collapse and a fluid pool), the anatomy told apart
// (air outside the body, lungs), cleansing that removes the fluid level from the iso surface,
// synthetic tubes with known axes, orientation from the scan's matrix, the shared abdominal CT,
// and bad input.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>

#include <gtest/gtest.h>

#include "colon/colon_analysis.h"
#include "colon/colon_error.h"
#include "volumes/analytic_phantom.h"
#include "volumes/colon_phantom.h"
#include "volumes/load_volume.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Distance from p to a polyline, and the arc length of the nearest point on it.
struct Nearest {
    double distanceMm = 1e300;
    double arcMm = 0.0;
};

Nearest nearestOnPolyline(const std::vector<glm::dvec3>& line, const glm::dvec3& p) {
    Nearest best;
    double arc = 0.0;
    for (std::size_t i = 1; i < line.size(); ++i) {
        const glm::dvec3 a = line[i - 1], b = line[i];
        const double length = glm::length(b - a);
        const double f = length > 0.0 ? std::clamp(glm::dot(p - a, b - a) / (length * length), 0.0, 1.0) : 0.0;
        const double d = glm::length(p - (a + f * (b - a)));
        if (d < best.distanceMm) best = {d, arc + f * length};
        arc += length;
    }
    return best;
}

std::vector<glm::dvec3> allPoints(const colon::ColonAnalysis& analysis) {
    std::vector<glm::dvec3> points;
    for (const auto& segment : analysis.segments) {
        points.insert(points.end(), segment.centreline.pointsMm.begin(), segment.centreline.pointsMm.end());
    }
    return points;
}

/// How a computed centreline agrees with the truth: distances of its points to the truth
/// (mean, 95th percentile) and the share of the truth (outside `excludedArcs`) it passes
/// within 3 mm of.
struct Agreement {
    double meanMm = 0.0, p95Mm = 0.0, coverage = 0.0;
};

Agreement agreementWith(const std::vector<glm::dvec3>& truth, const colon::ColonAnalysis& analysis,
                        const std::vector<std::array<double, 2>>& excludedArcs = {}) {
    const std::vector<glm::dvec3> computed = allPoints(analysis);
    std::vector<double> distances;
    for (const glm::dvec3& p : computed) distances.push_back(nearestOnPolyline(truth, p).distanceMm);
    std::sort(distances.begin(), distances.end());
    Agreement agreement;
    for (double d : distances) agreement.meanMm += d / static_cast<double>(distances.size());
    agreement.p95Mm = distances[distances.size() * 95 / 100];
    std::size_t counted = 0, covered = 0;
    double arc = 0.0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
        if (i > 0) arc += glm::length(truth[i] - truth[i - 1]);
        const bool isExcluded = std::any_of(excludedArcs.begin(), excludedArcs.end(),
                                            [&](const auto& range) { return arc >= range[0] && arc <= range[1]; });
        if (isExcluded) continue;
        ++counted;
        if (nearestOnPolyline(computed, truth[i]).distanceMm < 3.0) ++covered;
    }
    agreement.coverage = static_cast<double>(covered) / static_cast<double>(counted);
    return agreement;
}

int16_t huAt(const volumes::Volume& volume, const glm::dvec3& pointMm) {
    const glm::dvec3 v = pointMm / volume.spacingMm;
    const int i = std::clamp(static_cast<int>(std::lround(v.x)), 0, volume.dims[0] - 1);
    const int j = std::clamp(static_cast<int>(std::lround(v.y)), 0, volume.dims[1] - 1);
    const int k = std::clamp(static_cast<int>(std::lround(v.z)), 0, volume.dims[2] - 1);
    return volume.at(i, j, k);
}

/// Every centreline point lies in air: the nearest voxel of `volume` is below -800 HU.
void expectInAir(const volumes::Volume& volume, const colon::ColonAnalysis& analysis) {
    int outside = 0;
    for (const glm::dvec3& p : allPoints(analysis)) outside += huAt(volume, p) < -800 ? 0 : 1;
    EXPECT_EQ(outside, 0) << "centreline points outside the air";
}

/// A volume of soft tissue with air where sdf(p) < 0 (p in volume millimetres), with a 1 mm
/// partial-volume ramp.
volumes::Volume volumeWithAir(std::array<int, 3> dims, glm::dvec3 spacing,
                              const std::function<double(const glm::dvec3&)>& sdf) {
    volumes::Volume volume;
    volume.dims = dims;
    volume.spacingMm = spacing;
    volume.hu.resize(volume.voxelCount());
    for (int k = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
            for (int i = 0; i < dims[0]; ++i) {
                const double d = sdf(glm::dvec3(i, j, k) * spacing);
                const double air = std::clamp(0.5 - d, 0.0, 1.0);
                volume.hu[volume.linearIndex(i, j, k)] = static_cast<int16_t>(std::lround(40.0 + air * (-1040.0)));
            }
    return volume;
}

class ColonPhantomAnalysis : public ::testing::Test {
protected:
    /// The anatomy phantom (body, lungs, a collapse, a fluid pool) and its analysis, shared.
    static void SetUpTestSuite() {
        spec = new volumes::ColonPhantomSpec(volumes::ColonPhantomSpec::withAnatomy({}));
        phantom = new volumes::ColonPhantom(volumes::makeColonPhantom(*spec));
        cleansed = new volumes::Volume(phantom->volume);
        analysis = new colon::ColonAnalysis(colon::analyseColon(*cleansed, colon::ColonSettings{}));
    }
    static void TearDownTestSuite() {
        delete analysis;
        delete cleansed;
        delete phantom;
        delete spec;
    }
    static volumes::ColonPhantomSpec* spec;
    static volumes::ColonPhantom* phantom;
    static volumes::Volume* cleansed;
    static colon::ColonAnalysis* analysis;
};
volumes::ColonPhantomSpec* ColonPhantomAnalysis::spec = nullptr;
volumes::ColonPhantom* ColonPhantomAnalysis::phantom = nullptr;
volumes::Volume* ColonPhantomAnalysis::cleansed = nullptr;
colon::ColonAnalysis* ColonPhantomAnalysis::analysis = nullptr;

TEST(ColonCentreline, FollowsThePhantomsTruthForSeveralShapes) {
    // Targets: within 1 mm mean and 2 mm p95 of the truth, covering 95 % of it, in air, with
    // the default shape and two other shape seeds carrying the full anatomy.
    for (const std::uint64_t shapeSeed : {0u, 2u, 3u}) {
        volumes::ColonPhantomSpec spec = shapeSeed == 0 ? volumes::ColonPhantomSpec{}
                                                        : volumes::ColonPhantomSpec::withAnatomy({});
        spec.shapeSeed = shapeSeed;
        const volumes::ColonPhantom phantom = volumes::makeColonPhantom(spec);
        volumes::Volume volume = phantom.volume;
        const colon::ColonAnalysis analysis = colon::analyseColon(volume, colon::ColonSettings{});
        const Agreement agreement = agreementWith(phantom.centrelineMm, analysis, phantom.collapsedArcMm);
        std::printf("shape seed %llu: %zu segment(s), mean %.2f mm, p95 %.2f mm, coverage %.3f\n",
                    static_cast<unsigned long long>(shapeSeed), analysis.segments.size(), agreement.meanMm,
                    agreement.p95Mm, agreement.coverage);
        EXPECT_LT(agreement.meanMm, 1.0) << "shape seed " << shapeSeed;
        EXPECT_LT(agreement.p95Mm, 2.0) << "shape seed " << shapeSeed;
        EXPECT_GE(agreement.coverage, 0.95) << "shape seed " << shapeSeed;
        expectInAir(volume, analysis);
    }
}

TEST_F(ColonPhantomAnalysis, RunsRectumToCaecum) {
    // The phantom's truth runs caecum -> rectum; the analysis must run the other way.
    const glm::dvec3 caecum = phantom->centrelineMm.front(), rectum = phantom->centrelineMm.back();
    const glm::dvec3 start = analysis->segments.front().centreline.pointsMm.front();
    const glm::dvec3 end = analysis->segments.back().centreline.pointsMm.back();
    EXPECT_LT(glm::length(start - rectum), 15.0);
    EXPECT_LT(glm::length(end - caecum), 15.0);
    EXPECT_NEAR(glm::dot(analysis->anteriorMm, glm::dvec3(0, -1, 0)), 1.0, 1e-12);
}

TEST_F(ColonPhantomAnalysis, ACollapseGivesTwoSegmentsAndAGapNotAPathThroughTissue) {
    ASSERT_EQ(phantom->collapsedArcMm.size(), 1u);
    ASSERT_EQ(analysis->segments.size(), 2u);
    ASSERT_EQ(analysis->gapsMm.size(), 1u);
    const auto collapsed = phantom->collapsedArcMm[0];
    EXPECT_GE(analysis->gapsMm[0], collapsed[1] - collapsed[0]);
    for (const glm::dvec3& p : allPoints(*analysis)) {
        const double arc = nearestOnPolyline(phantom->centrelineMm, p).arcMm;
        EXPECT_FALSE(arc > collapsed[0] && arc < collapsed[1]) << "a point in the collapse at arc " << arc;
    }
    expectInAir(*cleansed, *analysis);
}

TEST_F(ColonPhantomAnalysis, AirOutsideTheBodyAndTheLungsAreNotColon) {
    const auto& labels = analysis->labels;
    EXPECT_EQ(labels.at(0, 0, 0), colon::kLabelOutside);
    EXPECT_EQ(labels.at(labels.dims[0] - 1, labels.dims[1] / 2, labels.dims[2] / 2), colon::kLabelOutside);
    ASSERT_EQ(phantom->lungs.size(), 2u);
    for (const auto& lung : phantom->lungs) {
        // The lowest point of the lung base inside the grid, a little above its surface.
        const glm::dvec3 inLung = lung.centreMm - glm::dvec3(0.0, 0.0, lung.semiAxesMm.z - 3.0);
        ASSERT_LT(inLung.z, (labels.dims[2] - 1) * labels.spacingMm.z);
        EXPECT_EQ(huAt(labels, inLung), colon::kLabelLung) << lung.side;
    }
    int lungRegions = 0, outsideRegions = 0;
    for (const auto& region : analysis->airRegions) {
        lungRegions += region.kind == colon::AirClass::Lung ? 1 : 0;
        outsideRegions += region.kind == colon::AirClass::Outside ? 1 : 0;
        if (region.kind == colon::AirClass::Colon) {
            EXPECT_LT(region.medianHu, -900.0);
        }
    }
    EXPECT_EQ(lungRegions, 2);
    EXPECT_EQ(outsideRegions, 1);
    for (const glm::dvec3& p : allPoints(*analysis)) EXPECT_GE(huAt(labels, p), colon::kLabelFirstSegment);
}

TEST_F(ColonPhantomAnalysis, CleansingRemovesTheFluidLevelFromTheIsoSurface) {
    ASSERT_EQ(phantom->fluidPools.size(), 1u);
    EXPECT_TRUE(analysis->isCleansed);
    EXPECT_EQ(analysis->cleansing.pools, 1);
    EXPECT_EQ(analysis->cleansing.rejectedRegions, 0);
    const auto& pool = phantom->fluidPools[0];
    // Look down (gravity: +y) from the centreline in the pool's middle: before cleansing the
    // -500 HU surface is the fluid level; after it, the wall at the lumen radius.
    const auto firstSurfaceBelow = [&](const volumes::Volume& volume, const glm::dvec3& from) {
        for (double r = 0.0; r < 3.0 * spec->lumenRadiusMm; r += 0.1) {
            if (huAt(volume, from + glm::dvec3(0.0, r, 0.0)) > -500) return r;
        }
        return 1e300;
    };
    int checked = 0;
    double arc = 0.0;
    for (std::size_t i = 1; i < phantom->centrelineMm.size(); ++i) {
        arc += glm::length(phantom->centrelineMm[i] - phantom->centrelineMm[i - 1]);
        if (arc < pool.startArcMm + 3.0 || arc > pool.endArcMm - 3.0) continue;  // the pool's ends are ramps
        const glm::dvec3 p = phantom->centrelineMm[i];
        if (p.y + spec->lumenRadiusMm - pool.levelYMm < 2.0) continue;  // hardly any fluid under this point
        const double levelDepth = pool.levelYMm - p.y;
        const double before = firstSurfaceBelow(phantom->volume, p);
        const double after = firstSurfaceBelow(*cleansed, p);
        EXPECT_NEAR(before, levelDepth, 1.0) << "arc " << arc << ": the uncleansed surface is the fluid level";
        EXPECT_GT(after, before + 1.5) << "arc " << arc << ": the surface moved down from the level";
        EXPECT_NEAR(after, spec->lumenRadiusMm, 1.5) << "arc " << arc << ": to the wall, not beyond it";
        ++checked;
    }
    EXPECT_GT(checked, 5);
    // Fluid voxels are air-like now, and nothing above +200 HU is left in the pool's lumen.
    for (std::size_t n = 0; n < cleansed->hu.size(); ++n) {
        if (phantom->volume.hu[n] > 400 && analysis->labels.hu[n] >= colon::kLabelFirstSegment) {
            EXPECT_LT(cleansed->hu[n], -500) << "voxel " << n;
        }
    }
}

TEST(ColonCentreline, AStraightTubeGivesItsAxis) {
    volumes::TubeSpec spec;
    spec.grid = {{48, 48, 80}, glm::dvec3(1.0)};
    spec.axisMm = {23.5, 23.5};
    spec.radiusMm = 10.0;
    volumes::Volume volume = volumes::makeTubePhantom(spec);
    const colon::ColonAnalysis analysis = colon::analyseColon(volume, colon::ColonSettings{});
    ASSERT_EQ(analysis.segments.size(), 1u);
    double lowest = 1e300, highest = -1e300;
    for (const glm::dvec3& p : allPoints(analysis)) {
        EXPECT_LT(glm::length(glm::dvec2(p.x, p.y) - spec.axisMm), 0.5) << "at z " << p.z;
        lowest = std::min(lowest, p.z);
        highest = std::max(highest, p.z);
    }
    EXPECT_GT(highest - lowest, 50.0);  // the whole tube but its end caps (the faces count as wall)
}

TEST(ColonCentreline, AULoopDoesNotShortCut) {
    // Two arms 24 mm apart (12 mm of tissue between), joined over the top by a half circle.
    const double radius = 6.0, bend = 12.0, top = 70.0;
    const glm::dvec3 bendCentre(48.0, 24.0, top);
    std::vector<glm::dvec3> axis;
    for (double z = 0.0; z <= top; z += 1.0) axis.emplace_back(bendCentre.x - bend, 24.0, z);
    for (int a = 1; a < 60; ++a) {
        const double t = kPi * a / 60.0;
        axis.push_back(bendCentre + glm::dvec3(-bend * std::cos(t), 0.0, bend * std::sin(t)));
    }
    for (double z = top; z >= 0.0; z -= 1.0) axis.emplace_back(bendCentre.x + bend, 24.0, z);
    volumes::Volume volume = volumeWithAir({96, 48, 100}, glm::dvec3(1.0), [&](const glm::dvec3& p) {
        return nearestOnPolyline(axis, p).distanceMm - radius;
    });
    const colon::ColonAnalysis analysis = colon::analyseColon(volume, colon::ColonSettings{});
    ASSERT_EQ(analysis.segments.size(), 1u);
    for (const glm::dvec3& p : allPoints(analysis)) EXPECT_LT(nearestOnPolyline(axis, p).distanceMm, 1.5);
    const double truthLength = 2.0 * top + kPi * bend;
    EXPECT_GT(analysis.segments[0].centreline.lengthMm, truthLength - 4.0 * radius);  // only the end caps trimmed
    expectInAir(volume, analysis);
}

TEST(ColonOrientation, TheOrderFollowsThePatientNotTheVoxelAxes) {
    volumes::ColonPhantomSpec spec;
    spec.grid = {{128, 128, 128}, glm::dvec3(1.2)};
    const volumes::ColonPhantom phantom = volumes::makeColonPhantom(spec);
    volumes::Volume plain = phantom.volume;
    // The same patient stored with the voxel x axis running to the patient's right, as the
    // shared abdominal CT is: mirrored voxels, a mirrored direction and the origin moved.
    volumes::Volume mirrored = phantom.volume;
    for (int k = 0; k < mirrored.dims[2]; ++k)
        for (int j = 0; j < mirrored.dims[1]; ++j)
            for (int i = 0; i < mirrored.dims[0]; ++i) {
                mirrored.hu[mirrored.linearIndex(i, j, k)] = phantom.volume.at(mirrored.dims[0] - 1 - i, j, k);
            }
    mirrored.directionLps[0] = glm::dvec3(-1.0, 0.0, 0.0);
    mirrored.originLps.x = (mirrored.dims[0] - 1) * mirrored.spacingMm.x;
    const colon::ColonAnalysis a = colon::analyseColon(plain, colon::ColonSettings{});
    const colon::ColonAnalysis b = colon::analyseColon(mirrored, colon::ColonSettings{});
    const glm::dvec3 startA = volumes::patientFromVolumeMm(plain, a.segments.front().centreline.pointsMm.front());
    const glm::dvec3 startB = volumes::patientFromVolumeMm(mirrored, b.segments.front().centreline.pointsMm.front());
    EXPECT_LT(glm::length(startA - startB), 2.0) << "the rectal end is the same place in the patient";
    EXPECT_GT(startA.x, 0.5 * (plain.dims[0] - 1) * plain.spacingMm.x) << "the rectal end is on the patient's left";
}

TEST(ColonRealCt, FindsTheAirFilledColonOfTheSharedAbdomen) {
    const std::string path = std::string(CVC_SHARED_DATA_DIR) + "/ct/ts_example_abdomen_3mm.nrrd";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is missing";
    const volumes::Volume original = volumes::loadVolume(path);
    volumes::Volume volume = original;
    const colon::ColonAnalysis analysis = colon::analyseColon(volume, colon::ColonSettings{});
    double total = 0.0;
    for (const auto& segment : analysis.segments) total += segment.centreline.lengthMm;
    std::printf("shared CT: %zu segments, %.0f mm of centreline\n", analysis.segments.size(), total);
    EXPECT_GE(analysis.segments.size(), 2u);
    EXPECT_GT(total, 300.0);
    EXPECT_FALSE(analysis.isCleansed) << "the scan has no tagged fluid";
    expectInAir(original, analysis);
    int lungs = 0;
    for (const auto& region : analysis.airRegions) lungs += region.kind == colon::AirClass::Lung ? 1 : 0;
    EXPECT_GE(lungs, 1) << "the lung bases at the top of the scan";
}

TEST(ColonBadInput, NoAirAllAirOrATinyColonSayWhatWasFound) {
    const auto messageOf = [](volumes::Volume volume) {
        try {
            colon::analyseColon(volume, colon::ColonSettings{});
        } catch (const colon::ColonError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const auto tissue = volumeWithAir({32, 32, 32}, glm::dvec3(1.0), [](const glm::dvec3&) { return 10.0; });
    EXPECT_NE(messageOf(tissue).find("has no air"), std::string::npos) << messageOf(tissue);
    const auto air = volumeWithAir({32, 32, 32}, glm::dvec3(1.0), [](const glm::dvec3&) { return -10.0; });
    EXPECT_NE(messageOf(air).find("air everywhere"), std::string::npos) << messageOf(air);
    const auto speck = volumeWithAir({32, 32, 32}, glm::dvec3(1.0),
                                     [](const glm::dvec3& p) { return glm::length(p - glm::dvec3(16.0)) - 1.5; });
    EXPECT_NE(messageOf(speck).find("no air-filled colon found among 1 air regions (0 outside the body, 1 under"),
              std::string::npos)
        << messageOf(speck);
    // A ball of gas (a stomach's bubble) is round, not tubular: not colon either.
    const auto bubble = volumeWithAir({64, 64, 64}, glm::dvec3(1.0),
                                      [](const glm::dvec3& p) { return glm::length(p - glm::dvec3(32.0)) - 20.0; });
    EXPECT_NE(messageOf(bubble).find("0 lung-like, 1 round"), std::string::npos) << messageOf(bubble);
}

}  // namespace
