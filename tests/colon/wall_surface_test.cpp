// The colon wall surface and its coverage bookkeeping, without a GPU: the mesh's area against
// the closed form of a capped tube, its normals, what it leaves out, and coverage fed with hit
// images made here by exact ray-cylinder intersection (an oracle independent of the renderer).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "colon/colon_error.h"
#include "colon/surface_coverage.h"
#include "colon/wall_surface.h"
#include "tests/support/tube_volume.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

using testing_support::TubeSpec;

TEST(WallSurface, CappedTubeAreaMatchesItsClosedForm) {
    const TubeSpec spec;
    const volumes::Volume volume = testing_support::tubeVolume(spec);
    const colon::WallSurface wall = colon::colonWallSurface(volume, testing_support::airMask(volume));
    const double R = spec.radiusMm, L = spec.zEndMm - spec.zStartMm;
    const double expected = 2.0 * kPi * R * L + 2.0 * kPi * R * R;
    EXPECT_NEAR(wall.totalAreaMm2, expected, 0.02 * expected);
    // Every normal points into the lumen: toward the axis on the side wall, inward at the caps.
    const glm::dvec2 axis(0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y);
    int outward = 0;
    for (std::size_t e = 0; e < wall.size(); ++e) {
        const glm::dvec3 c = wall.centreMm[e];
        const glm::dvec3 inward = c.z < spec.zStartMm + 1.0   ? glm::dvec3(0, 0, 1)
                                  : c.z > spec.zEndMm - 1.0 ? glm::dvec3(0, 0, -1)
                                                            : glm::dvec3(axis - glm::dvec2(c), 0.0);
        if (glm::dot(wall.normal[e], inward) <= 0.0) ++outward;
    }
    EXPECT_EQ(outward, 0);
}

TEST(WallSurface, LeavesOutAirThatIsNotTheLumen) {
    const TubeSpec spec;
    volumes::Volume volume = testing_support::tubeVolume(spec);
    std::vector<uint8_t> lumen = testing_support::airMask(volume);
    const double tubeArea = colon::colonWallSurface(volume, lumen).totalAreaMm2;
    // A bubble of air 3 mm outside the tube wall, not in the mask: not colon wall.
    const glm::dvec3 bubble(0.5 * spec.extentMm.x + spec.radiusMm + 5.0, 0.5 * spec.extentMm.y, 40.0);
    for (int k = 0; k < volume.dims[2]; ++k) {
        for (int j = 0; j < volume.dims[1]; ++j) {
            for (int i = 0; i < volume.dims[0]; ++i) {
                if (glm::length(glm::dvec3(i, j, k) * spec.spacingMm - bubble) < 2.0) volume.hu[volume.linearIndex(i, j, k)] = -1000;
            }
        }
    }
    const colon::WallSurface wall = colon::colonWallSurface(volume, lumen);
    EXPECT_NEAR(wall.totalAreaMm2, tubeArea, 1e-6 * tubeArea);
    for (const auto& c : wall.centreMm) EXPECT_GT(glm::length(c - bubble), 2.5);
}

TEST(WallSurface, RefusesAMaskOfAnotherSizeOrAnEmptyOne) {
    const volumes::Volume volume = testing_support::tubeVolume(TubeSpec{});
    EXPECT_THROW(colon::colonWallSurface(volume, std::vector<uint8_t>(10, 1)), colon::ColonError);
    EXPECT_THROW(colon::colonWallSurface(volume, std::vector<uint8_t>(volume.voxelCount(), 0)), colon::ColonError);
    colon::WallSurfaceSettings noCrossing;
    noCrossing.isoHu = 500.0;  // above every voxel: the lumen's boundary never crosses it
    EXPECT_THROW(colon::colonWallSurface(volume, testing_support::airMask(volume), noCrossing), colon::ColonError);
}

/// The hits of a pinhole camera on the axis of the analytic tube (side wall only, caps beyond
/// reach), looking along `forward`: exact ray-cylinder intersections, 4 floats per pixel.
std::vector<float> analyticTubeHits(const TubeSpec& spec, const glm::dvec3& eye, const glm::dvec3& forward,
                                    const glm::dvec3& up, double fovDeg, int pixels) {
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up));
    const glm::dvec3 trueUp = glm::cross(right, forward);
    const double half = std::tan(0.5 * fovDeg * kPi / 180.0);
    const glm::dvec2 axis(0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y);
    std::vector<float> hits(4 * static_cast<std::size_t>(pixels) * static_cast<std::size_t>(pixels), 0.0f);
    for (int y = 0; y < pixels; ++y) {
        for (int x = 0; x < pixels; ++x) {
            const double u = (2.0 * (x + 0.5) / pixels - 1.0) * half, v = (1.0 - 2.0 * (y + 0.5) / pixels) * half;
            const glm::dvec3 d = glm::normalize(forward + u * right + v * trueUp);
            const glm::dvec2 o = glm::dvec2(eye) - axis, dd(d.x, d.y);
            const double a = glm::dot(dd, dd), b = 2.0 * glm::dot(o, dd), c = glm::dot(o, o) - spec.radiusMm * spec.radiusMm;
            if (a < 1e-12) continue;  // along the axis: no side-wall hit
            const double t = (-b + std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
            const glm::dvec3 p = eye + t * d;
            if (p.z < spec.zStartMm || p.z > spec.zEndMm) continue;
            float* out = &hits[4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(pixels) + static_cast<std::size_t>(x))];
            out[0] = static_cast<float>(p.x);
            out[1] = static_cast<float>(p.y);
            out[2] = static_cast<float>(p.z);
            out[3] = 1.0f;
        }
    }
    return hits;
}

TEST(SurfaceCoverage, SixAxisViewsOfATubeSeeItsSideWallAndNeverMoreThanAll) {
    const TubeSpec spec;
    const volumes::Volume volume = testing_support::tubeVolume(spec);
    const colon::WallSurface wall = colon::colonWallSurface(volume, testing_support::airMask(volume));
    colon::SurfaceCoverage coverage(wall, colon::CoverageSettings{});
    const glm::dvec2 axis(0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y);
    // Four sideways views from each of several points along the axis: the side wall within
    // 45 degrees of each view's centre, so every side-wall element is seen head on.
    double added = 0.0;
    for (double z = 14.0; z <= 66.0; z += 4.0) {
        const glm::dvec3 eye(axis, z);
        for (const glm::dvec3 look : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0)}) {
            const std::vector<float> hits = analyticTubeHits(spec, eye, look, {0, 0, 1}, 90.0, 120);
            added += coverage.addView({120, 120, hits, eye});
            EXPECT_LE(coverage.percent(), 100.0);
        }
    }
    EXPECT_NEAR(added, coverage.seenAreaMm2(), 1e-6 * coverage.seenAreaMm2());
    // Seen: the side wall from 2 mm before the first eye's reach to after the last one's
    // (the views reach 8 mm along the axis each way); unseen: the caps and the ends near them.
    double sideArea = 0.0, sideSeen = 0.0, capSeen = 0.0;
    for (std::size_t e = 0; e < wall.size(); ++e) {
        const double z = wall.centreMm[e].z;
        if (z > 12.0 && z < 68.0) {
            sideArea += wall.areaMm2[e];
            sideSeen += coverage.seen()[e] ? wall.areaMm2[e] : 0.0;
        } else if (z < spec.zStartMm + 0.5 || z > spec.zEndMm - 0.5) {
            // The cap away from its rim, which the side views never reach.
            const double r = glm::length(glm::dvec2(wall.centreMm[e]) - axis);
            if (r < spec.radiusMm - 1.5) capSeen += coverage.seen()[e] ? wall.areaMm2[e] : 0.0;
        }
    }
    EXPECT_GT(sideSeen, 0.995 * sideArea);
    EXPECT_LT(capSeen, 1.0);
    // What is unseen comes out as two patches (one per end), largest first.
    const auto patches = coverage.unseenPatches(10.0);
    ASSERT_EQ(patches.size(), 2u);
    EXPECT_GE(patches[0].areaMm2, patches[1].areaMm2);
    EXPECT_NEAR(patches[0].areaMm2 + patches[1].areaMm2, wall.totalAreaMm2 - coverage.seenAreaMm2(), 1e-6 * wall.totalAreaMm2);
}

TEST(SurfaceCoverage, ThresholdsDecide) {
    const TubeSpec spec;
    const volumes::Volume volume = testing_support::tubeVolume(spec);
    const colon::WallSurface wall = colon::colonWallSurface(volume, testing_support::airMask(volume));
    const glm::dvec2 axis(0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y);
    const glm::dvec3 eye(axis, 40.0);
    const std::vector<float> hits = analyticTubeHits(spec, eye, {1, 0, 0}, {0, 0, 1}, 90.0, 60);
    // The view down the side at 45 degrees shows the wall at up to 45 degrees from its normal
    // (x = R, the wall point straight ahead, is head on).
    colon::CoverageSettings strict;
    strict.maxViewAngleDeg = 20.0;
    colon::SurfaceCoverage narrow(wall, strict), wide(wall, colon::CoverageSettings{});
    narrow.addView({60, 60, hits, eye});
    wide.addView({60, 60, hits, eye});
    EXPECT_LT(narrow.seenAreaMm2(), 0.6 * wide.seenAreaMm2());
    colon::CoverageSettings coarse;
    coarse.maxFootprintMm2 = 1e-4;  // smaller than any pixel's footprint here
    colon::SurfaceCoverage none(wall, coarse);
    EXPECT_EQ(none.addView({60, 60, hits, eye}), 0.0);
    EXPECT_THROW(colon::SurfaceCoverage(wall, colon::CoverageSettings{0.0, 80.0}), colon::ColonError);
    EXPECT_THROW(colon::SurfaceCoverage(wall, colon::CoverageSettings{4.0, 95.0}), colon::ColonError);
    EXPECT_THROW(wide.addView({61, 60, hits, eye}), colon::ColonError);
}

TEST(SurfaceCoverage, DoesNotDependOnTheOrderOfViews) {
    const TubeSpec spec;
    const volumes::Volume volume = testing_support::tubeVolume(spec);
    const colon::WallSurface wall = colon::colonWallSurface(volume, testing_support::airMask(volume));
    const glm::dvec2 axis(0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y);
    struct View {
        glm::dvec3 eye, look;
        std::vector<float> hits;
    };
    std::vector<View> views;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> along(12.0, 68.0), angle(0.0, 2.0 * kPi);
    for (int i = 0; i < 12; ++i) {
        const double a = angle(random);
        const glm::dvec3 eye(axis.x + 2.0 * std::cos(a), axis.y + 2.0 * std::sin(a), along(random));
        const glm::dvec3 look(std::cos(a + 1.0), std::sin(a + 1.0), 0.3);
        // The analytic hits assume an eye on the axis; off the axis they are still exact points
        // of the wall, which is all the bookkeeping needs.
        views.push_back({eye, look, analyticTubeHits(spec, eye, glm::normalize(look), {0, 0, 1}, 70.0, 48)});
    }
    colon::SurfaceCoverage forward(wall, {}), backward(wall, {});
    for (const auto& v : views) forward.addView({48, 48, v.hits, v.eye});
    for (auto v = views.rbegin(); v != views.rend(); ++v) backward.addView({48, 48, v->hits, v->eye});
    EXPECT_GT(forward.percent(), 5.0);
    EXPECT_EQ(forward.seen(), backward.seen());
    EXPECT_EQ(forward.seenAreaMm2(), backward.seenAreaMm2());
}

}  // namespace
