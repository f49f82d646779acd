// Numerical stress of the ray caster: rays exactly along the axes (zero direction components),
// cameras outside, inside, on a face, on a brick boundary and on a voxel centre, volumes of
// 1x1x1 and Nx1x1 voxels, spacing ratios of 50:1, iso values outside the data range, fully
// transparent and fully opaque classification, the smallest and largest step, extreme jitter
// seeds. Every image must be free of NaN in its hit output, finish within a watchdog's time,
// leave the validation layer silent (the GpuTest fixture), and put its hits where a closed form
// says (the analytic ball, the box's own faces, a linear ramp) or agree with a second render.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/render/pinhole_camera.h"
#include "engine/render/raycaster.h"
#include "engine/render/view_rays.h"
#include "tests/support/gpu_scene.h"
#include "tests/support/gpu_test_fixture.h"
#include "tests/support/pinhole_toward.h"
#include "volumes/analytic_phantom.h"

namespace {

using testing_support::GpuScene;
using testing_support::GpuTest;

/// Tiny images: the smallest step costs 50 times the default per ray.
constexpr int kImageSide = 15;  // odd: the centre pixel's ray is exactly the view axis

/// Renders on a worker thread and ends the whole test process if the render does not finish in
/// time: a hung dispatch cannot be cancelled, and waiting for ctest's TIMEOUT would hide which
/// case hung. Generous for ASan builds on two shared cores; a render here takes milliseconds.
engine::RenderedImage renderWithWatchdog(engine::Raycaster& raycaster, const engine::ViewRays& rays,
                                         const engine::RenderSettings& settings, const std::string& what) {
    constexpr auto kLimit = std::chrono::seconds(60);
    auto job = std::async(std::launch::async, [&] { return raycaster.render(rays, settings); });
    if (job.wait_for(kLimit) != std::future_status::ready) {
        std::fprintf(stderr, "watchdog: render '%s' did not finish within 60 s\n", what.c_str());
        std::fflush(stderr);
        std::_Exit(3);
    }
    return job.get();
}

struct Hit {
    bool isHit = false;
    glm::dvec3 p{0.0};
};

Hit hitAt(const engine::RenderedImage& image, int x, int y) {
    const std::size_t i = 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x));
    return {image.hitMm[i + 3] > 0.5f, glm::dvec3(image.hitMm[i], image.hitMm[i + 1], image.hitMm[i + 2])};
}

/// No NaN or infinity anywhere in the hit output, w exactly 0 or 1, and a hit image at all.
void expectCleanHits(const engine::RenderedImage& image, const std::string& what) {
    ASSERT_EQ(image.hitMm.size(), 4u * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) << what;
    for (std::size_t i = 0; i < image.hitMm.size(); ++i) {
        ASSERT_TRUE(std::isfinite(image.hitMm[i])) << what << ": hit value " << i << " is " << image.hitMm[i];
    }
    for (std::size_t i = 3; i < image.hitMm.size(); i += 4) {
        ASSERT_TRUE(image.hitMm[i] == 0.0f || image.hitMm[i] == 1.0f) << what << ": hit flag " << image.hitMm[i];
    }
}

int hitCount(const engine::RenderedImage& image) {
    int hits = 0;
    for (std::size_t i = 3; i < image.hitMm.size(); i += 4) hits += image.hitMm[i] > 0.5f ? 1 : 0;
    return hits;
}

/// A 15x15 image looking from `eye` along the unit `forward` through a square of side `sideMm`
/// at 10 mm: the centre pixel's ray is `forward` exactly (all terms are exact in float).
engine::ViewRays raysAlong(const glm::dvec3& eye, const glm::dvec3& forward, double sideMm) {
    const glm::dvec3 other = std::abs(forward.y) > 0.5 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    const glm::dvec3 right = glm::cross(forward, other);
    const glm::dvec3 down = glm::cross(forward, right);
    engine::ViewRays rays;
    rays.eyeMm = eye;
    rays.wallUMm = sideMm * right;
    rays.wallVMm = sideMm * down;
    rays.wallOriginMm = eye + 10.0 * forward - 0.5 * rays.wallUMm - 0.5 * rays.wallVMm;
    rays.width = rays.height = kImageSide;
    return rays;
}

engine::ViewRays raysToward(const glm::dvec3& eye, const glm::dvec3& target, double fovDeg) {
    return engine::viewRaysFrom(testing_support::cameraToward(eye, target, fovDeg, kImageSide));
}

/// Where the ray from `eye` along `dir` enters the closed box [lo, hi] (slab test in double;
/// 0 when the eye is inside), or nothing when it misses or only touches it.
std::optional<double> boxEntry(const glm::dvec3& eye, const glm::dvec3& dir, const glm::dvec3& lo, const glm::dvec3& hi) {
    double tEnter = 0.0;
    double tExit = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (dir[a] == 0.0) {
            if (eye[a] < lo[a] || eye[a] > hi[a]) return std::nullopt;
            continue;
        }
        double t0 = (lo[a] - eye[a]) / dir[a];
        double t1 = (hi[a] - eye[a]) / dir[a];
        if (t0 > t1) std::swap(t0, t1);
        tEnter = std::max(tEnter, t0);
        tExit = std::min(tExit, t1);
    }
    if (tEnter >= tExit) return std::nullopt;
    return tEnter;
}

/// Rays that pass at least `margin` inside the box, and rays that pass at least `margin` outside
/// it: the float and double slab tests agree on both; rays grazing an edge are left out.
bool clearlyEnters(const glm::dvec3& eye, const glm::dvec3& dir, const glm::dvec3& lo, const glm::dvec3& hi, double margin) {
    return boxEntry(eye, dir, lo + margin, hi - margin).has_value();
}
bool clearlyMisses(const glm::dvec3& eye, const glm::dvec3& dir, const glm::dvec3& lo, const glm::dvec3& hi, double margin) {
    return !boxEntry(eye, dir, lo - margin, hi + margin).has_value();
}

/// The volume's box: voxel centres at i * spacing, the box half a voxel beyond them.
struct Box {
    glm::dvec3 lo, hi;
};
Box boxOf(const volumes::Volume& v) {
    return {-0.5 * v.spacingMm, (glm::dvec3(v.dims[0], v.dims[1], v.dims[2]) - 0.5) * v.spacingMm};
}

volumes::Volume uniformVolume(std::array<int, 3> dims, glm::dvec3 spacing, int16_t hu) {
    volumes::Volume v;
    v.dims = dims;
    v.spacingMm = spacing;
    v.hu.assign(v.voxelCount(), hu);
    return v;
}

/// A ball of 1000 HU in -1000 HU, centred on a voxel centre so that axis rays through it are exact.
volumes::BallSpec ballSpec() {
    volumes::BallSpec spec;
    spec.grid.dims = {40, 40, 40};
    spec.centreMm = glm::dvec3(20.0);
    spec.radiusMm = 12.0;
    return spec;
}

double sphereError(const volumes::BallSpec& spec, const glm::dvec3& p) {
    return std::abs(glm::length(p - spec.centreMm) - spec.radiusMm);
}

engine::RenderSettings isoAt(double iso) {
    engine::RenderSettings settings;
    settings.isoHu = iso;
    settings.isWritingHits = true;
    return settings;
}

class RaycasterStress : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        if (!IsSkipped()) {
            ASSERT_TRUE(context().isValidationEnabled()) << "the stress matrix must run with validation";
        }
    }
};

/// For a volume that is matter everywhere at the iso value: every ray that clearly enters the box
/// hits where it enters (within `toleranceMm`), every ray that clearly misses hits nothing.
/// Returns how many rays were checked as entering.
int expectHitsWhereRaysEnterTheBox(const engine::RenderedImage& image, const engine::ViewRays& rays,
                                   const glm::dvec3& eye, const Box& box, double toleranceMm, const std::string& what) {
    int entering = 0;
    for (int y = 0; y < kImageSide; ++y) {
        for (int x = 0; x < kImageSide; ++x) {
            const glm::dvec3 dir = engine::rayDirectionOf(rays, x, y);
            const Hit h = hitAt(image, x, y);
            if (clearlyEnters(eye, dir, box.lo, box.hi, 1e-3)) {
                const double entry = *boxEntry(eye, dir, box.lo, box.hi);
                EXPECT_TRUE(h.isHit) << what << " pixel " << x << "," << y;
                if (h.isHit) {
                    EXPECT_LT(glm::length(h.p - (eye + entry * dir)), toleranceMm) << what << " pixel " << x << "," << y;
                }
                ++entering;
            } else if (clearlyMisses(eye, dir, box.lo, box.hi, 1e-3)) {
                EXPECT_FALSE(h.isHit) << what << " pixel " << x << "," << y;
            }
        }
    }
    return entering;
}

TEST_F(RaycasterStress, RaysAlongTheAxesHitTheBallOnAxis) {
    const volumes::BallSpec spec = ballSpec();
    GpuScene scene(context(), volumes::makeBallPhantom(spec));
    for (int axis = 0; axis < 3; ++axis) {
        for (const double sign : {1.0, -1.0}) {
            glm::dvec3 forward(0.0);
            forward[axis] = sign;
            const glm::dvec3 eye = spec.centreMm - 40.0 * forward;  // outside the box, on the axis
            const engine::ViewRays rays = raysAlong(eye, forward, 4.0);
            for (const bool isSkipping : {true, false}) {
                engine::RenderSettings settings = isoAt(0.0);
                settings.isSkipping = isSkipping;
                const std::string what = "axis " + std::to_string(axis) + (sign > 0 ? "+" : "-") + (isSkipping ? " skipping" : "");
                const auto image = renderWithWatchdog(scene.raycaster, rays, settings, what);
                expectCleanHits(image, what);
                EXPECT_EQ(hitCount(image), kImageSide * kImageSide) << what;
                // The centre pixel's ray has two zero components: it meets the ball at centre - R forward.
                const Hit centre = hitAt(image, kImageSide / 2, kImageSide / 2);
                ASSERT_TRUE(centre.isHit) << what;
                EXPECT_LT(glm::length(centre.p - (spec.centreMm - spec.radiusMm * forward)), 0.1) << what;
                for (int y = 0; y < kImageSide; ++y) {
                    for (int x = 0; x < kImageSide; ++x) {
                        const Hit h = hitAt(image, x, y);
                        if (h.isHit) {
                            EXPECT_LT(sphereError(spec, h.p), 0.25) << what << " pixel " << x << "," << y;
                        }
                    }
                }
            }
        }
    }
}

TEST_F(RaycasterStress, CamerasOnFacesBrickBoundariesAndVoxelCentres) {
    const volumes::BallSpec spec = ballSpec();
    GpuScene scene(context(), volumes::makeBallPhantom(spec));
    const Box box = boxOf(scene.volume);
    struct View {
        const char* name;
        glm::dvec3 eye;
    };
    const View views[] = {
        {"outside", glm::dvec3(-30.0, 20.0, 20.0)},
        {"on the -x face", glm::dvec3(box.lo.x, 20.0, 20.0)},
        {"on the +z face", glm::dvec3(20.0, 20.0, box.hi.z)},
        {"on a box corner", box.lo},
        {"on the 8^3 bricks' boundary planes", glm::dvec3(7.5, 7.5, 7.5)},  // voxel faces 7 | 8
        {"on a 2-voxel skip cell's corner", glm::dvec3(31.5, 5.5, 33.5)},
        {"on a voxel centre", glm::dvec3(5.0, 5.0, 5.0)},
        {"on a voxel centre of the last layer", glm::dvec3(39.0, 39.0, 39.0)},
    };
    for (const View& view : views) {
        const engine::ViewRays rays = raysToward(view.eye, spec.centreMm, 50.0);
        std::optional<engine::RenderedImage> reference;
        for (const int cell : {0, 2, 8}) {  // 0: no skipping, the reference
            engine::RenderSettings settings = isoAt(0.0);
            settings.isSkipping = cell > 0;
            settings.skipCellVoxels = std::max(cell, 2);
            const std::string what = std::string(view.name) + ", skip cell " + std::to_string(cell);
            const auto image = renderWithWatchdog(scene.raycaster, rays, settings, what);
            expectCleanHits(image, what);
            for (int y = 0; y < kImageSide; ++y) {
                for (int x = 0; x < kImageSide; ++x) {
                    const Hit h = hitAt(image, x, y);
                    if (h.isHit) {
                        EXPECT_LT(sphereError(spec, h.p), 0.25) << what << " pixel " << x << "," << y;
                    }
                }
            }
            // Every view looks at the ball's centre from outside the ball: the centre pixel hits.
            EXPECT_TRUE(hitAt(image, kImageSide / 2, kImageSide / 2).isHit) << what;
            if (!reference) {
                reference = image;
                continue;
            }
            // Skipping may not change what is seen.
            for (int y = 0; y < kImageSide; ++y) {
                for (int x = 0; x < kImageSide; ++x) {
                    const Hit a = hitAt(*reference, x, y);
                    const Hit b = hitAt(image, x, y);
                    EXPECT_EQ(a.isHit, b.isHit) << what << " pixel " << x << "," << y;
                    if (a.isHit && b.isHit) {
                        EXPECT_LT(glm::length(a.p - b.p), 0.05) << what << " pixel " << x << "," << y;
                    }
                }
            }
        }
    }
}

TEST_F(RaycasterStress, OneVoxelVolumeIsASolidBox) {
    // One voxel of 1000 HU: clamp-to-edge sampling makes its whole box 1000 HU, so every ray that
    // enters the box starts inside matter and hits exactly where it enters.
    GpuScene scene(context(), uniformVolume({1, 1, 1}, glm::dvec3(1.0), 1000));
    const Box box = boxOf(scene.volume);
    const glm::dvec3 eyes[] = {{0.0, 0.0, -3.0}, {2.0, 1.5, -2.5}, {0.0, 0.0, 0.0}, {0.5, 0.0, 0.0}};
    for (const glm::dvec3& eye : eyes) {
        for (const double iso : {0.0, -30000.0}) {
            const engine::ViewRays rays = glm::length(eye) > 0.6 ? raysToward(eye, glm::dvec3(0.0), 40.0)
                                                                 : raysAlong(eye, glm::dvec3(0, 0, 1), 4.0);
            const std::string what = "eye (" + std::to_string(eye.x) + ", " + std::to_string(eye.y) + ", " +
                                     std::to_string(eye.z) + ") iso " + std::to_string(iso);
            const auto image = renderWithWatchdog(scene.raycaster, rays, isoAt(iso), what);
            expectCleanHits(image, what);
            EXPECT_GT(expectHitsWhereRaysEnterTheBox(image, rays, eye, box, 2e-3, what), 0) << what;
        }
        // Above the data: nothing to see.
        const auto empty = renderWithWatchdog(scene.raycaster, raysToward(eye + glm::dvec3(0, 0, -1), glm::dvec3(0.0), 40.0),
                                              isoAt(1001.0), "one voxel, iso above max");
        expectCleanHits(empty, "one voxel, iso above max");
        EXPECT_EQ(hitCount(empty), 0);
    }
}

TEST_F(RaycasterStress, LineVolumesFindTheRampsCrossing) {
    // 64 voxels along one axis, one across: values ramp from -1000 to +1000, so the iso-0 surface
    // is the plane at voxel 31.5 (trilinear interpolation is exact on a linear ramp).
    for (int axis = 0; axis < 3; ++axis) {
        std::array<int, 3> dims{1, 1, 1};
        dims[static_cast<std::size_t>(axis)] = 64;
        volumes::Volume v = uniformVolume(dims, glm::dvec3(1.0), 0);
        for (int i = 0; i < 64; ++i) v.hu[static_cast<std::size_t>(i)] = static_cast<int16_t>(std::lround(-1000.0 + 2000.0 * i / 63.0));
        GpuScene scene(context(), std::move(v));
        glm::dvec3 forward(0.0);
        forward[axis] = 1.0;
        // From the low end the ray meets the crossing; from the high end it starts in matter and
        // hits where it enters, at the box's face 63.5.
        const std::string name = "64 voxels along axis " + std::to_string(axis);
        const auto up = renderWithWatchdog(scene.raycaster, raysAlong(-10.0 * forward, forward, 0.1), isoAt(0.0), name + ", +");
        const auto down = renderWithWatchdog(scene.raycaster, raysAlong(80.0 * forward, -forward, 0.1), isoAt(0.0), name + ", -");
        expectCleanHits(up, name);
        expectCleanHits(down, name);
        // The narrow view (0.6 degrees) keeps every ray inside the 1 mm thick box up to the crossing.
        EXPECT_EQ(hitCount(up), kImageSide * kImageSide) << name;
        EXPECT_EQ(hitCount(down), kImageSide * kImageSide) << name;
        for (int y = 0; y < kImageSide; ++y) {
            for (int x = 0; x < kImageSide; ++x) {
                EXPECT_NEAR(hitAt(up, x, y).p[axis], 31.5, 0.02) << name << " pixel " << x << "," << y;
                EXPECT_NEAR(hitAt(down, x, y).p[axis], 63.5, 2e-3) << name << " pixel " << x << "," << y;
            }
        }
    }
}

TEST_F(RaycasterStress, SpacingRatioOfFiftyToOne) {
    // Voxels 50 times longer along one axis than along the others (and the reverse): the step is
    // in units of the smallest side, so a ray takes thousands of steps; hits stay on the ball to
    // within the coarse axis's interpolation error and match a render at a quarter of the step.
    for (const bool isCoarseX : {true, false}) {
        volumes::BallSpec spec;
        spec.grid.dims = isCoarseX ? std::array<int, 3>{12, 300, 300} : std::array<int, 3>{300, 300, 6};
        spec.grid.spacingMm = isCoarseX ? glm::dvec3(5.0, 0.1, 0.1) : glm::dvec3(0.1, 0.1, 5.0);
        const glm::dvec3 extent = glm::dvec3(spec.grid.dims[0], spec.grid.dims[1], spec.grid.dims[2]) * spec.grid.spacingMm;
        spec.centreMm = 0.5 * extent - 0.5 * spec.grid.spacingMm;
        spec.radiusMm = 10.0;
        spec.edgeWidthMm = 2.0;
        GpuScene scene(context(), volumes::makeBallPhantom(spec));
        const double coarse = 5.0;
        const std::string name = isCoarseX ? "5 x 0.1 x 0.1 mm" : "0.1 x 0.1 x 5 mm";
        for (const glm::dvec3& eye : {spec.centreMm - glm::dvec3(40.0, 0.0, 0.0), spec.centreMm + glm::dvec3(0.0, 0.0, 40.0),
                                      spec.centreMm + glm::dvec3(25.0, 20.0, -30.0)}) {
            const engine::ViewRays rays = raysToward(eye, spec.centreMm, 40.0);
            engine::RenderSettings settings = isoAt(0.0);
            const auto image = renderWithWatchdog(scene.raycaster, rays, settings, name);
            settings.stepVoxels = 0.125;
            const auto fine = renderWithWatchdog(scene.raycaster, rays, settings, name + ", fine step");
            expectCleanHits(image, name);
            expectCleanHits(fine, name);
            EXPECT_GT(hitCount(image), kImageSide * kImageSide / 4) << name;
            for (int y = 0; y < kImageSide; ++y) {
                for (int x = 0; x < kImageSide; ++x) {
                    const Hit a = hitAt(image, x, y);
                    const Hit b = hitAt(fine, x, y);
                    // Trilinear interpolation across 5 mm voxels rounds the ball's ramp by up to
                    // a fraction of the coarse side.
                    if (a.isHit) {
                        EXPECT_LT(sphereError(spec, a.p), 0.5 * coarse) << name;
                    }
                    if (a.isHit && b.isHit) {
                        EXPECT_LT(glm::length(a.p - b.p), 0.05) << name << " pixel " << x << "," << y;
                    }
                }
            }
        }
    }
}

TEST_F(RaycasterStress, IsoValuesOutsideTheDataRange) {
    const volumes::BallSpec spec = ballSpec();  // data in [-1000, 1000]
    GpuScene scene(context(), volumes::makeBallPhantom(spec));
    const Box box = boxOf(scene.volume);
    const glm::dvec3 eyes[] = {glm::dvec3(-25.0, 10.0, 31.0), glm::dvec3(3.0, 4.0, 5.0)};  // outside, inside the box
    for (const glm::dvec3& eye : eyes) {
        const engine::ViewRays rays = raysToward(eye, spec.centreMm, 70.0);
        for (const double iso : {1000.5, 3072.0, 1e9, std::numeric_limits<double>::max()}) {
            const std::string what = "iso " + std::to_string(iso);
            const auto image = renderWithWatchdog(scene.raycaster, rays, isoAt(iso), what);
            expectCleanHits(image, what);
            EXPECT_EQ(hitCount(image), 0) << what;
        }
        for (const double iso : {-1000.5, -40000.0, -1e9, -std::numeric_limits<double>::max()}) {
            // Below every value: each ray starts in matter and hits where it enters the box (or,
            // from inside the box, at the eye).
            const std::string what = "iso " + std::to_string(iso);
            const auto image = renderWithWatchdog(scene.raycaster, rays, isoAt(iso), what);
            expectCleanHits(image, what);
            EXPECT_GT(expectHitsWhereRaysEnterTheBox(image, rays, eye, box, 1e-2, what), 0) << what;
        }
    }
    // Not a number is refused, not rendered.
    EXPECT_THROW(scene.raycaster.render(raysToward(eyes[0], spec.centreMm, 70.0), isoAt(std::nan(""))), std::invalid_argument);
}

TEST_F(RaycasterStress, TransparentAndOpaqueClassification) {
    // The engine's transfer functions are presets; their extremes are reached by the data: air
    // (and the lowest int16) is clear in every preset, bone-dense values (and the highest int16,
    // beyond the tables' end) are opaque. Clear volumes show nothing and leave the background;
    // opaque ones reach 50 % opacity within the first millimetre of the box.
    const glm::dvec3 eye(-12.0, 5.0, 9.0);
    struct Case {
        int16_t hu;
        bool isOpaque;
    };
    for (const Case c : {Case{-1024, false}, Case{std::numeric_limits<int16_t>::min(), false}, Case{3071, true},
                         Case{std::numeric_limits<int16_t>::max(), true}}) {
        GpuScene scene(context(), uniformVolume({16, 16, 16}, glm::dvec3(1.0), c.hu));
        const Box box = boxOf(scene.volume);
        const engine::ViewRays rays = raysToward(eye, glm::dvec3(7.5), 60.0);
        for (const char* preset : {"colon-wall", "soft-tissue", "bone"}) {
            for (const double step : {0.01, 1.0, 8.0}) {
                engine::RenderSettings settings;
                settings.mode = engine::RenderMode::Composite;
                settings.transferFunction = preset;
                settings.stepVoxels = step;
                const std::string what = std::to_string(c.hu) + " HU, " + preset + ", step " + std::to_string(step);
                const auto image = renderWithWatchdog(scene.raycaster, rays, settings, what);
                expectCleanHits(image, what);
                if (!c.isOpaque) {
                    EXPECT_EQ(hitCount(image), 0) << what;
                    for (std::size_t i = 4; i < image.rgba.size(); ++i) ASSERT_EQ(image.rgba[i], image.rgba[i % 4]) << what;
                    continue;
                }
                for (int y = 0; y < kImageSide; ++y) {
                    for (int x = 0; x < kImageSide; ++x) {
                        const glm::dvec3 dir = engine::rayDirectionOf(rays, x, y);
                        const Hit h = hitAt(image, x, y);
                        if (clearlyEnters(eye, dir, box.lo, box.hi, 1e-2)) {
                        const double entry = *boxEntry(eye, dir, box.lo, box.hi);
                            ASSERT_TRUE(h.isHit) << what << " pixel " << x << "," << y;
                            // The first sample is at the entry: opacity 1 per millimetre (0.9 for
                            // soft tissue) passes 0.5 there or on the next sample.
                            EXPECT_LT(glm::length(h.p - (eye + entry * dir)), std::max(1.0, step) + 1e-3) << what;
                        } else if (clearlyMisses(eye, dir, box.lo, box.hi, 1e-2)) {
                            EXPECT_FALSE(h.isHit) << what;
                        }
                    }
                }
            }
        }
    }
}

TEST_F(RaycasterStress, StepsFromTheSmallestToTheLargest) {
    const volumes::BallSpec spec = ballSpec();
    GpuScene scene(context(), volumes::makeBallPhantom(spec));
    const engine::ViewRays rays = raysToward(spec.centreMm + glm::dvec3(-21.0, 30.0, 17.0), spec.centreMm, 50.0);
    std::optional<engine::RenderedImage> finestOf[2];  // per filter: tricubic smooths the ramp
    for (const double step : {0.01, 0.1, 1.0, 4.0, 8.0}) {
        for (const bool isTricubic : {false, true}) {
            engine::RenderSettings settings = isoAt(0.0);
            settings.stepVoxels = step;
            settings.filter = isTricubic ? engine::VolumeFilter::Tricubic : engine::VolumeFilter::Trilinear;
            settings.refinementSteps = 32;  // the most allowed: bisection beats even an 8-voxel step
            const std::string what = "step " + std::to_string(step) + (isTricubic ? " tricubic" : " trilinear");
            const auto image = renderWithWatchdog(scene.raycaster, rays, settings, what);
            expectCleanHits(image, what);
            std::optional<engine::RenderedImage>& finest = finestOf[isTricubic ? 1 : 0];
            if (!finest) finest = image;
            for (int y = 0; y < kImageSide; ++y) {
                for (int x = 0; x < kImageSide; ++x) {
                    const Hit h = hitAt(image, x, y);
                    if (h.isHit) {
                        EXPECT_LT(sphereError(spec, h.p), 0.25) << what << " pixel " << x << "," << y;
                    }
                    // A long step may jump over the ball's rim, never invent a hit.
                    if (h.isHit) {
                        EXPECT_TRUE(hitAt(*finest, x, y).isHit) << what << " pixel " << x << "," << y;
                    }
                }
            }
            // A miss where the finest step hits is allowed only where the ray's chord through the
            // matter is shorter than the step: a closed form per ray, with the ball shrunk by the
            // 0.25 mm the interpolated surface may deviate (checked above for every hit).
            for (int y = 0; y < kImageSide; ++y) {
                for (int x = 0; x < kImageSide; ++x) {
                    if (hitAt(image, x, y).isHit || !hitAt(*finest, x, y).isHit) continue;
                    const glm::dvec3 dir = engine::rayDirectionOf(rays, x, y);
                    const double offAxis = glm::length(glm::cross(spec.centreMm - rays.eyeMm, dir));
                    const double outer = spec.radiusMm - 0.25;
                    const double chord = 2.0 * std::sqrt(std::max(0.0, outer * outer - offAxis * offAxis));
                    EXPECT_LT(chord, step + 1e-3) << what << ": missed pixel " << x << "," << y << " with a chord of " << chord << " mm";
                }
            }
        }
    }
    // The documented range ends there.
    for (const double step : {0.0099, 8.01, 0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
        engine::RenderSettings settings = isoAt(0.0);
        settings.stepVoxels = step;
        EXPECT_THROW(scene.raycaster.render(rays, settings), std::invalid_argument) << "step " << step;
    }
}

TEST_F(RaycasterStress, ExtremeJitterSeeds) {
    const volumes::BallSpec spec = ballSpec();
    GpuScene scene(context(), volumes::makeBallPhantom(spec));
    const engine::ViewRays rays = raysToward(spec.centreMm + glm::dvec3(31.0, -9.0, 22.0), spec.centreMm, 50.0);
    engine::RenderSettings unjittered = isoAt(0.0);
    unjittered.stepVoxels = 0.25;
    const auto plain = renderWithWatchdog(scene.raycaster, rays, unjittered, "no jitter");
    for (const uint32_t seed : {0u, 1u, 0x7fffffffu, 0x80000000u, std::numeric_limits<uint32_t>::max()}) {
        for (const auto mode : {engine::RenderMode::IsoSurface, engine::RenderMode::Composite}) {
            engine::RenderSettings settings = isoAt(0.0);
            settings.mode = mode;
            settings.transferFunction = "bone";
            settings.stepVoxels = 0.25;  // as in Raycasting.CompositeOpacityFrontFindsTheBall
            settings.isJittered = true;
            settings.jitterSeed = seed;
            const std::string what = "seed " + std::to_string(seed) + (mode == engine::RenderMode::Composite ? " composite" : " iso");
            const auto image = renderWithWatchdog(scene.raycaster, rays, settings, what);
            expectCleanHits(image, what);
            const auto again = renderWithWatchdog(scene.raycaster, rays, settings, what);
            EXPECT_EQ(image.rgba, again.rgba) << what << ": a seed must reproduce its frame";
            if (mode == engine::RenderMode::Composite) {
                // The opacity front of the bone preset lies within a voxel of the ball's surface.
                for (int y = 0; y < kImageSide; ++y) {
                    for (int x = 0; x < kImageSide; ++x) {
                        const Hit h = hitAt(image, x, y);
                        if (h.isHit) {
                            EXPECT_LT(sphereError(spec, h.p), 1.0) << what;
                        }
                    }
                }
                continue;
            }
            // A jittered start moves samples less than a step: the surface found is the same.
            for (int y = 0; y < kImageSide; ++y) {
                for (int x = 0; x < kImageSide; ++x) {
                    const Hit a = hitAt(plain, x, y);
                    const Hit b = hitAt(image, x, y);
                    EXPECT_EQ(a.isHit, b.isHit) << what << " pixel " << x << "," << y;
                    if (b.isHit) {
                        EXPECT_LT(sphereError(spec, b.p), 0.25) << what;
                    }
                }
            }
        }
    }
}

}  // namespace
