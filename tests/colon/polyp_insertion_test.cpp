// Polyp insertion against an analytic tube whose wall is known in closed form: the base on the
// wall, the normal to the axis, the apex where the geometry puts it for both kinds, the wall's
// tissue value never exceeded, nothing changed away from the polyp, the edge as blurred as the
// wall's; bad input refused with a message naming the problem; and the shared abdominal CT.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "colon/colon_analysis.h"
#include "colon/colon_error.h"
#include "colon/polyp_insertion.h"
#include "volumes/analytic_phantom.h"
#include "volumes/load_volume.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTubeRadiusMm = 15.0;
constexpr double kTubeEdgeMm = 1.5;

volumes::TubeSpec tubeSpec(double spacingMm) {
    volumes::TubeSpec spec;
    const int size = static_cast<int>(std::lround(64.0 / spacingMm));
    spec.grid = {{size, size, size}, glm::dvec3(spacingMm)};
    spec.axisMm = glm::dvec2(0.5 * (size - 1) * spacingMm);
    spec.radiusMm = kTubeRadiusMm;
    spec.edgeWidthMm = kTubeEdgeMm;
    return spec;
}

/// Trilinear HU at a point in volume millimetres (written here again, independent of the code under test).
double sampleHu(const volumes::Volume& v, const glm::dvec3& p) {
    const glm::dvec3 g = glm::clamp(p / v.spacingMm, glm::dvec3(0.0),
                                    glm::dvec3(v.dims[0] - 1, v.dims[1] - 1, v.dims[2] - 1) - 1e-9);
    const glm::ivec3 i0(glm::floor(g));
    const glm::dvec3 f = g - glm::dvec3(i0);
    double sum = 0.0;
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const double w = (dx ? f.x : 1 - f.x) * (dy ? f.y : 1 - f.y) * (dz ? f.z : 1 - f.z);
                sum += w * v.at(std::min(i0.x + dx, v.dims[0] - 1), std::min(i0.y + dy, v.dims[1] - 1),
                                std::min(i0.z + dz, v.dims[2] - 1));
            }
    return sum;
}

/// Distance from `from` along `direction` to where the HU first falls below `level`.
double distanceToFall(const volumes::Volume& v, const glm::dvec3& from, const glm::dvec3& direction, double level) {
    for (double t = 0.0; t < 40.0; t += 0.005) {
        if (sampleHu(v, from + t * direction) < level) return t;
    }
    return std::numeric_limits<double>::quiet_NaN();
}

/// The 10%-90% width of the HU profile between `low` and `high` along `direction` through `at`
/// (the profile falls along `direction`).
double tenToNinetyMm(const volumes::Volume& v, const glm::dvec3& at, const glm::dvec3& direction, double low,
                     double high) {
    const double start = -10.0;
    const glm::dvec3 from = at + start * direction;
    return distanceToFall(v, from, direction, low + 0.1 * (high - low)) -
           distanceToFall(v, from, direction, low + 0.9 * (high - low));
}

double radialMm(const volumes::TubeSpec& spec, const glm::dvec3& p) {
    return glm::length(glm::dvec2(p.x, p.y) - spec.axisMm);
}

glm::dvec3 nearAxis(const volumes::TubeSpec& spec) {
    // Off the axis toward +x and a little +y, so the wall nearest it is unique.
    return {spec.axisMm.x + 1.5, spec.axisMm.y + 0.7, 0.5 * (spec.grid.dims[2] - 1) * spec.grid.spacingMm.z};
}

/// What every insertion into the tube must satisfy: the base on the wall, the normal to the
/// axis, nothing lowered or raised past the tissue, nothing changed away from the polyp.
void expectWellPlaced(const volumes::TubeSpec& spec, const volumes::Volume& before, const volumes::Volume& after,
                      const colon::InsertedPolyp& polyp) {
    const volumes::PolypTruth& t = polyp.truth;
    EXPECT_NEAR(radialMm(spec, t.baseMm), kTubeRadiusMm, 0.3) << "the base lies on the analytic wall";
    const glm::dvec3 towardAxis =
        glm::normalize(glm::dvec3(spec.axisMm.x - t.baseMm.x, spec.axisMm.y - t.baseMm.y, 0.0));
    const double angleDeg = std::acos(std::clamp(glm::dot(t.baseNormal, towardAxis), -1.0, 1.0)) * 180.0 / kPi;
    EXPECT_LT(angleDeg, 2.0) << "the normal points to the axis";
    EXPECT_NEAR(glm::length(t.baseNormal), 1.0, 1e-9);
    EXPECT_NEAR(polyp.tissueHu, spec.wallHu, 1.0);
    EXPECT_NEAR(polyp.airHu, spec.lumenHu, 1.0);
    ASSERT_GT(polyp.voxelsChanged, 0u);

    std::size_t changed = 0;
    for (int k = 0; k < after.dims[2]; ++k)
        for (int j = 0; j < after.dims[1]; ++j)
            for (int i = 0; i < after.dims[0]; ++i) {
                const int16_t old = before.at(i, j, k), now = after.at(i, j, k);
                if (polyp.signedDistanceMm(glm::dvec3(i, j, k) * after.spacingMm) > 1.5 * polyp.edgeWidthMm) {
                    ASSERT_EQ(now, old) << "voxel " << i << ' ' << j << ' ' << k << " is away from the polyp";
                }
                if (now == old) continue;
                ++changed;
                ASSERT_GT(now, old) << "only raised toward tissue";
                ASSERT_LE(now, polyp.tissueHu + 1.0) << "never past the tissue value";
            }
    EXPECT_EQ(changed, polyp.voxelsChanged);
}

TEST(PolypInsertion, SessileSitsOnTheTubeWallWithItsApexRFromTheBase) {
    const volumes::TubeSpec spec = tubeSpec(1.0);
    const volumes::Volume before = volumes::makeTubePhantom(spec);
    volumes::Volume after = before;
    const colon::InsertedPolyp polyp = colon::insertPolyp(after, {nearAxis(spec), 8.0, 0.0, -500.0});
    ASSERT_EQ(polyp.truth.kind, volumes::PolypKind::Sessile);
    EXPECT_NEAR(polyp.truth.radiusMm, 4.0, 1e-12);
    EXPECT_EQ(polyp.truth.centreMm, polyp.truth.baseMm);
    expectWellPlaced(spec, before, after, polyp);
    EXPECT_NEAR(distanceToFall(after, polyp.truth.centreMm, polyp.truth.baseNormal, -500.0), 4.0, 0.5)
        << "the apex";
    EXPECT_GT(sampleHu(after, polyp.truth.centreMm), 0.0) << "the polyp is tissue where the wall was air";
}

TEST(PolypInsertion, PedunculatedHeadTopIsStalkPlusDiameterFromTheBase) {
    const volumes::TubeSpec spec = tubeSpec(1.0);
    const volumes::Volume before = volumes::makeTubePhantom(spec);
    volumes::Volume after = before;
    const colon::InsertedPolyp polyp = colon::insertPolyp(after, {nearAxis(spec), 8.0, 5.0, -500.0});
    ASSERT_EQ(polyp.truth.kind, volumes::PolypKind::Pedunculated);
    EXPECT_NEAR(polyp.truth.stalkLengthMm, 5.0, 1e-12);
    EXPECT_NEAR(glm::length(polyp.truth.centreMm - polyp.truth.baseMm), 5.0 + 4.0, 1e-9);
    expectWellPlaced(spec, before, after, polyp);
    const glm::dvec3 n = polyp.truth.baseNormal;
    EXPECT_NEAR(distanceToFall(after, polyp.truth.baseMm + 0.5 * n, n, -500.0) + 0.5, 5.0 + 8.0, 0.5)
        << "the head's top at base + stalk + 2r, and tissue all the way along the stalk";
    // The stalk is thinner than the head: beside it, half-way up, is lumen.
    const glm::dvec3 side = glm::normalize(glm::cross(n, glm::dvec3(0.0, 0.0, 1.0)));
    const glm::dvec3 midStalk = polyp.truth.baseMm + 2.5 * n;
    EXPECT_GT(sampleHu(after, midStalk), -300.0);
    EXPECT_LT(sampleHu(after, midStalk + 3.0 * side), -900.0);
}

TEST(PolypInsertion, EdgeIsAsBlurredAsTheWallAtFineAndCoarseSpacing) {
    for (const double spacingMm : {1.0, 2.0}) {
        const volumes::TubeSpec spec = tubeSpec(spacingMm);
        volumes::Volume volume = volumes::makeTubePhantom(spec);
        const double diameterMm = std::max(8.0, 4.0 * spacingMm);
        const colon::InsertedPolyp polyp = colon::insertPolyp(volume, {nearAxis(spec), diameterMm, 0.0, -500.0});
        const glm::dvec3 n = polyp.truth.baseNormal;
        // The wall's blur away from the polyp (the far side of the tube), and the polyp's at its apex.
        const glm::dvec3 farWall = polyp.truth.baseMm + (2.0 * kTubeRadiusMm) * n;
        const double wallWidth = tenToNinetyMm(volume, farWall, -n, spec.lumenHu, spec.wallHu);
        const double apexWidth = tenToNinetyMm(volume, polyp.truth.centreMm + 0.5 * diameterMm * n, n, spec.lumenHu,
                                               spec.wallHu);
        std::printf("spacing %.1f mm: edge width %.2f mm; 10-90%% across the wall %.2f mm, across the polyp %.2f mm\n",
                    spacingMm, polyp.edgeWidthMm, wallWidth, apexWidth);
        EXPECT_NEAR(apexWidth, wallWidth, 0.15 * wallWidth) << "spacing " << spacingMm;
        if (spacingMm == 1.0) {
            EXPECT_NEAR(polyp.edgeWidthMm, kTubeEdgeMm, 0.2) << "the tube's own ramp, recovered";
        }
    }
}

std::string errorOf(volumes::Volume volume, const colon::PolypInsertion& request) {
    try {
        colon::insertPolyp(volume, request);
    } catch (const colon::ColonError& e) {
        return e.what();
    }
    return "no error";
}

TEST(PolypInsertion, BadInputIsRefusedNamingTheProblem) {
    const volumes::TubeSpec spec = tubeSpec(1.0);
    const volumes::Volume tube = volumes::makeTubePhantom(spec);
    const glm::dvec3 at = nearAxis(spec);
    const auto expectError = [&](const colon::PolypInsertion& request, const std::string& words) {
        const std::string message = errorOf(tube, request);
        EXPECT_NE(message.find(words), std::string::npos) << message;
    };
    expectError({{2.0, 2.0, 32.0}, 8.0, 0.0, -500.0}, "is not in the lumen (HU 40");
    expectError({at, 3.5, 0.0, -500.0}, "3.5 voxels across at this scan's 1.00 mm spacing");
    expectError({at, 3.5, 0.0, -500.0}, "a spacing of 0.88 mm or less");
    expectError({at, 2.0, 0.0, -500.0}, "outside 3..30 mm");
    expectError({at, 31.0, 0.0, -500.0}, "outside 3..30 mm");
    expectError({{at.x, std::nan(""), at.z}, 8.0, 0.0, -500.0}, "not finite");
    expectError({at, 8.0, -1.0, -500.0}, "stalk length");
    expectError({at, 10.0, 25.0, -500.0}, "past the opposite wall");
    expectError({{-20.0, at.y, at.z}, 8.0, 0.0, -500.0}, "outside the volume");
    // An all-air volume has no wall to put a polyp on.
    volumes::TubeSpec wide = spec;
    wide.radiusMm = 200.0;
    const std::string noWall = errorOf(volumes::makeTubePhantom(wide), {at, 8.0, 0.0, -500.0});
    EXPECT_NE(noWall.find("no wall"), std::string::npos) << noWall;
    // Near the end face of the grid, a big head leaves the volume.
    expectError({{at.x, at.y, 1.0}, 20.0, 0.0, -500.0}, "outside the volume");
}

TEST(PolypInsertionRealCt, TwelveMillimetreSessilePolypInTheSharedAbdomen) {
    const std::string path = std::string(CVC_SHARED_DATA_DIR) + "/ct/ts_example_abdomen_3mm.nrrd";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is missing";
    const volumes::Volume before = volumes::loadVolume(path);
    volumes::Volume analysed = before;
    const colon::ColonAnalysis analysis = colon::analyseColon(analysed, colon::ColonSettings{});
    const auto longest = std::max_element(analysis.segments.begin(), analysis.segments.end(), [](auto& a, auto& b) {
        return a.centreline.lengthMm < b.centreline.lengthMm;
    });
    ASSERT_NE(longest, analysis.segments.end());
    const auto& points = longest->centreline.pointsMm;
    const glm::dvec3 at = points[points.size() / 2];

    volumes::Volume after = before;
    const double diameterMm = 12.0;
    const colon::InsertedPolyp polyp = colon::insertPolyp(after, {at, diameterMm, 0.0, -500.0});
    std::printf("shared CT: 12 mm sessile polyp at (%.1f, %.1f, %.1f) mm from (%.1f, %.1f, %.1f): tissue %.0f HU, "
                "air %.0f HU, edge width %.2f mm, %zu voxels changed\n",
                polyp.truth.baseMm.x, polyp.truth.baseMm.y, polyp.truth.baseMm.z, at.x, at.y, at.z, polyp.tissueHu,
                polyp.airHu, polyp.edgeWidthMm, polyp.voxelsChanged);
    EXPECT_GT(polyp.voxelsChanged, 10u);
    EXPECT_GT(polyp.tissueHu, -150.0);
    EXPECT_LT(polyp.tissueHu, 150.0);
    EXPECT_GT(glm::dot(polyp.truth.baseNormal, at - polyp.truth.baseMm), 0.0) << "the normal faces the point";
    for (int k = 0; k < after.dims[2]; ++k)
        for (int j = 0; j < after.dims[1]; ++j)
            for (int i = 0; i < after.dims[0]; ++i) {
                if (after.at(i, j, k) == before.at(i, j, k)) continue;
                const glm::dvec3 centre = glm::dvec3(i, j, k) * after.spacingMm;
                ASSERT_LT(glm::length(centre - polyp.truth.baseMm), diameterMm) << "changed far from the base";
            }
    std::printf("shared CT: trilinear HU at the polyp's centre %.0f before, %.0f after\n",
                sampleHu(before, polyp.truth.centreMm), sampleHu(after, polyp.truth.centreMm));
    EXPECT_LT(sampleHu(before, polyp.truth.centreMm), -450.0) << "the base is on the air side of the wall";
    EXPECT_GT(sampleHu(after, polyp.truth.centreMm), -300.0) << "and the polyp made it tissue";
}

}  // namespace
