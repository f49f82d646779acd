// Shading normals against closed forms: a coarse ball seen from outside and a coarse tube seen
// from inside, whose surface normals are radial, and a tilted slab, whose normal is one vector
// everywhere, seen at a grazing angle across many voxel layers. The B-spline gradient must be
// accurate and turn smoothly from pixel to pixel; the trilinear central differences, whose
// kinks at voxel planes band coarse CT, are measured beside it and must show what the test
// catches. The gradient volume's normals must equal those of the volume's own taps.
#include <algorithm>
#include <array>
#include <string>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "engine/render/pinhole_camera.h"
#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "tests/support/gpu_scene.h"
#include "tests/support/gpu_test_fixture.h"
#include "volumes/analytic_phantom.h"
#include "volumes/brick_minmax.h"

namespace {

constexpr double kDegPerRad = 57.29577951308232;

using Scene = testing_support::GpuScene;

/// Per hit pixel: the first-hit position and the shading normal (two renders of one view).
struct NormalImage {
    int width = 0;
    int height = 0;
    std::vector<glm::dvec3> position;
    std::vector<glm::dvec3> normal;
    std::vector<bool> isHit;
};

NormalImage renderNormals(Scene& scene, const engine::PinholeCamera& camera, engine::GradientFilter gradient,
                          engine::RenderMode mode = engine::RenderMode::IsoSurface, bool isUsingGradientVolume = true) {
    engine::RenderSettings settings;
    settings.isUsingGradientVolume = isUsingGradientVolume;
    settings.mode = mode;  // composite: the colon-wall transfer function; the hit is where opacity reaches 0.5
    // The product's iso value. At the profile's inflection point (HU 0 here) both kinds of normal
    // carry a ~0.7 degree bias: a one-voxel central difference's truncation error (h^2 / 6 times
    // the profile's third derivative) is largest there relative to the gradient, and differs per
    // axis with the normal's direction.
    settings.isoHu = -500.0;
    settings.stepVoxels = 0.25;
    settings.gradient = gradient;
    const engine::ViewRays rays = engine::viewRaysFrom(camera);
    const engine::RenderedImage positions = scene.raycaster.render(rays, settings);
    settings.isWritingNormals = true;
    const engine::RenderedImage normals = scene.raycaster.render(rays, settings);
    NormalImage image;
    image.width = positions.width;
    image.height = positions.height;
    for (std::size_t p = 0; p < positions.hitMm.size() / 4; ++p) {
        image.isHit.push_back(positions.hitMm[4 * p + 3] > 0.5f && normals.hitMm[4 * p + 3] > 0.5f);
        image.position.emplace_back(positions.hitMm[4 * p], positions.hitMm[4 * p + 1], positions.hitMm[4 * p + 2]);
        image.normal.emplace_back(normals.hitMm[4 * p], normals.hitMm[4 * p + 1], normals.hitMm[4 * p + 2]);
    }
    return image;
}

/// A volume whose HU is 1000 tanh(-d / w) of a signed distance d (negative inside), w two of its
/// largest voxel sides: a smooth air-tissue boundary at HU 0 that the grid resolves, unlike a
/// clipped linear ramp, whose kinks alias at coarse spacing and would swamp what the normals
/// themselves do.
template <typename SignedDistance>
volumes::Volume smoothVolume(std::array<int, 3> dims, glm::dvec3 spacingMm, SignedDistance distanceMm,
                             double widthVoxels = 2.0) {
    const double widthMm = widthVoxels * std::max({spacingMm.x, spacingMm.y, spacingMm.z});
    volumes::Volume volume;
    volume.dims = dims;
    volume.spacingMm = spacingMm;
    volume.hu.resize(volume.voxelCount());
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) {
                const double d = distanceMm(glm::dvec3(i, j, k) * spacingMm);
                volume.hu[volume.linearIndex(i, j, k)] = static_cast<int16_t>(std::lround(-1000.0 * std::tanh(d / widthMm)));
            }
        }
    }
    return volume;
}

/// True when `p` lies at least four voxels inside the volume's box: nearer the faces, the
/// gradient's taps reach beyond the data (clamped to the edge) and measure the border instead.
bool isInterior(const volumes::Volume& volume, const glm::dvec3& p) {
    for (int a = 0; a < 3; ++a) {
        const double margin = 4.0 * volume.spacingMm[a];
        if (p[a] < margin || p[a] > (volume.dims[a] - 1) * volume.spacingMm[a] - margin) return false;
    }
    return true;
}

double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * kDegPerRad;
}

double percentile(std::vector<double> values, double q) {
    if (values.empty()) return NAN;
    std::sort(values.begin(), values.end());
    return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

/// The median and 99th percentile of the angle in degrees between each hit's normal and the
/// closed form, over hits that face the camera (at grazing silhouettes a pixel's hit and normal
/// are ill-defined).
struct AngleError {
    double median = 0.0;
    double p99 = 0.0;
};
template <typename Expected>
AngleError normalError(const volumes::Volume& volume, const NormalImage& image, const engine::PinholeCamera& camera,
                      Expected expected) {
    std::vector<double> errors;
    for (std::size_t p = 0; p < image.isHit.size(); ++p) {
        if (!image.isHit[p] || !isInterior(volume, image.position[p])) continue;
        const glm::dvec3 truth = expected(image.position[p]);
        const glm::dvec3 towardEye = glm::normalize(camera.positionMm - image.position[p]);
        if (glm::dot(truth, towardEye) < 0.3) continue;
        errors.push_back(angleDeg(image.normal[p], truth));
    }
    EXPECT_GT(errors.size(), 2000u);
    return {percentile(errors, 0.5), percentile(errors, 0.99)};
}

class Normals : public testing_support::GpuTest {};

// A ball of 2.5 mm voxels and a tube of 2 x 2 x 3 mm voxels (coarse, like thick-slice CT).
TEST_F(Normals, CoarseBallAndTubeWithinOneDegreeOfTheClosedForm) {
    const glm::dvec3 ballCentre(59.3, 58.6, 60.1);  // off the voxel lattice on purpose
    const double ballRadius = 40.0;
    Scene ball(context(), smoothVolume({48, 48, 48}, glm::dvec3(2.5), [&](const glm::dvec3& p) {
                   return glm::length(p - ballCentre) - ballRadius;
               }));
    engine::PinholeCamera outside;
    outside.positionMm = ballCentre + glm::dvec3(30.0, -20.0, -150.0);
    outside.lookAtMm = ballCentre;
    outside.verticalFovDeg = 40.0;
    outside.width = outside.height = 160;
    const auto radial = [&](const glm::dvec3& p) { return glm::normalize(p - ballCentre); };
    const AngleError ballBSpline = normalError(
        ball.volume, renderNormals(ball, outside, engine::GradientFilter::BSpline), outside, radial);
    const AngleError ballCentral = normalError(
        ball.volume, renderNormals(ball, outside, engine::GradientFilter::Central), outside, radial);
    const AngleError ballAtVoxels = normalError(
        ball.volume, renderNormals(ball, outside, engine::GradientFilter::BSplineAtVoxels), outside, radial);
    // Composite mode shades its samples with the same normals.
    const AngleError ballComposite = normalError(
        ball.volume, renderNormals(ball, outside, engine::GradientFilter::BSpline, engine::RenderMode::Composite),
        outside, radial);

    // Seen from inside: the lumen (air) within the radius, so the normal points to the axis.
    const glm::dvec2 axis(39.3, 38.6);
    const double tubeRadius = 28.0;
    Scene tube(context(), smoothVolume({40, 40, 60}, glm::dvec3(2.0, 2.0, 3.0), [&](const glm::dvec3& p) {
                   return tubeRadius - glm::length(glm::dvec2(p.x, p.y) - axis);
               }));
    engine::PinholeCamera inside;
    inside.positionMm = {axis.x, axis.y, 20.0};
    inside.lookAtMm = {axis.x + 8.0, axis.y + 5.0, 160.0};
    inside.verticalFovDeg = 70.0;
    inside.width = inside.height = 160;
    const auto inward = [&](const glm::dvec3& p) {
        return glm::normalize(glm::dvec3(axis.x - p.x, axis.y - p.y, 0.0));
    };
    const AngleError tubeBSpline = normalError(
        tube.volume, renderNormals(tube, inside, engine::GradientFilter::BSpline), inside, inward);
    const AngleError tubeCentral = normalError(
        tube.volume, renderNormals(tube, inside, engine::GradientFilter::Central), inside, inward);
    const AngleError tubeAtVoxels = normalError(
        tube.volume, renderNormals(tube, inside, engine::GradientFilter::BSplineAtVoxels), inside, inward);

    // Within 1 degree at the 99th percentile; the trilinear central differences' figures are
    // reported beside (on data this smooth they are close: the slab below is where they part).
    const auto report = [](const char* what, const AngleError& bspline, const AngleError& central) {
        return std::string(what) + ": B-spline median " + std::to_string(bspline.median) + ", p99 " +
               std::to_string(bspline.p99) + " deg; trilinear central differences median " +
               std::to_string(central.median) + ", p99 " + std::to_string(central.p99) + " deg";
    };
    RecordProperty("ball", report("ball", ballBSpline, ballCentral));
    RecordProperty("ball_composite", report("ball, composite", ballComposite, ballCentral));
    RecordProperty("tube", report("tube", tubeBSpline, tubeCentral));
    RecordProperty("ball_bspline_voxels_p99_deg", std::to_string(ballAtVoxels.p99));
    RecordProperty("tube_bspline_voxels_p99_deg", std::to_string(tubeAtVoxels.p99));
    EXPECT_LT(ballBSpline.p99, 1.0) << report("ball", ballBSpline, ballCentral);
    EXPECT_LT(ballComposite.p99, 1.0) << report("ball, composite", ballComposite, ballCentral);
    EXPECT_LT(tubeBSpline.p99, 1.0) << report("tube", tubeBSpline, tubeCentral);
    // The B-spline's values at the voxels, blended trilinearly (one fetch of the gradient volume).
    EXPECT_LT(ballAtVoxels.p99, 1.0) << "ball, bspline-voxels median " << ballAtVoxels.median;
    EXPECT_LT(tubeAtVoxels.p99, 1.0) << "tube, bspline-voxels median " << tubeAtVoxels.median;
}

TEST_F(Normals, NormalsTurnSmoothlyAcrossVoxelLayersOfATiltedSlab) {
    // A slab of 3 mm voxels whose face is tilted 8 degrees off the grid's z planes, with a
    // ramp from air to tissue one voxel wide, as the skin on thick-slice CT: its true normal is
    // one vector everywhere.
    const glm::dvec3 n = glm::normalize(glm::dvec3(std::sin(8.0 / kDegPerRad), 0.0, std::cos(8.0 / kDegPerRad)));
    const double offset = 60.0;
    // Air on the side n points away from: the air side's normal is -n.
    volumes::Volume slab = smoothVolume({48, 48, 40}, glm::dvec3(3.0),
                                        [&](const glm::dvec3& p) { return offset - glm::dot(n, p); }, 1.0);
    Scene scene(context(), std::move(slab));
    // Seen from the air side at a grazing 70 degrees, so each image row crosses many voxel layers.
    engine::PinholeCamera grazing;
    const glm::dvec3 centre(72.0, 72.0, 0.0);
    const glm::dvec3 onSurface = centre + (offset - glm::dot(n, centre)) * n;
    const glm::dvec3 along = glm::normalize(glm::cross(glm::dvec3(0.0, 1.0, 0.0), n));
    grazing.positionMm = onSurface - 40.0 * n + 110.0 * along;
    grazing.lookAtMm = onSurface;
    grazing.up = {0.0, 1.0, 0.0};
    grazing.verticalFovDeg = 30.0;
    grazing.width = grazing.height = 200;

    // Largest change of the normal between horizontally neighbouring hit pixels, and the
    // largest deviation from the slab's normal (the air side's normal is -n).
    const auto measure = [&](engine::GradientFilter gradient, double& worstStep, double& worstDeviation) {
        const NormalImage image = renderNormals(scene, grazing, gradient);
        worstStep = 0.0;
        worstDeviation = 0.0;
        int pairs = 0;
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x + 1 < image.width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * image.width + x;
                if (!image.isHit[p] || !image.isHit[p + 1] || !isInterior(scene.volume, image.position[p]) ||
                    !isInterior(scene.volume, image.position[p + 1])) {
                    continue;
                }
                ++pairs;
                worstStep = std::max(worstStep, angleDeg(image.normal[p], image.normal[p + 1]));
                worstDeviation = std::max(worstDeviation, angleDeg(image.normal[p], -n));
            }
        }
        EXPECT_GT(pairs, 10000);
    };
    double bsplineStep = 0.0, bsplineDeviation = 0.0, centralStep = 0.0, centralDeviation = 0.0;
    double atVoxelsStep = 0.0, atVoxelsDeviation = 0.0;
    measure(engine::GradientFilter::BSpline, bsplineStep, bsplineDeviation);
    measure(engine::GradientFilter::Central, centralStep, centralDeviation);
    measure(engine::GradientFilter::BSplineAtVoxels, atVoxelsStep, atVoxelsDeviation);
    RecordProperty("bspline_voxels_worst_step_deg", std::to_string(atVoxelsStep));
    RecordProperty("bspline_voxels_worst_deviation_deg", std::to_string(atVoxelsDeviation));

    RecordProperty("bspline_worst_step_deg", std::to_string(bsplineStep));
    RecordProperty("central_worst_step_deg", std::to_string(centralStep));
    RecordProperty("bspline_worst_deviation_deg", std::to_string(bsplineDeviation));
    RecordProperty("central_worst_deviation_deg", std::to_string(centralDeviation));
    // The bound: a fifth of a degree per pixel. The trilinear gradient must exceed it (that is
    // what this test is for); the B-spline must stay under it.
    EXPECT_LT(bsplineStep, 0.2) << "B-spline deviation " << bsplineDeviation << " deg";
    // The B-spline's values at the voxels blended trilinearly keep a kink in the normal's rate of
    // turn at voxel planes, but the smoothing takes the band away: under the bound too (measured
    // 0.13 degrees against the B-spline's 0.09 and the central differences' 0.25).
    EXPECT_LT(atVoxelsStep, 0.2) << "bspline-voxels deviation " << atVoxelsDeviation << " deg";
    EXPECT_GT(centralStep, 0.2) << "central deviation " << centralDeviation
                                << " deg: the slab no longer shows the trilinear gradient's kinks";
}

// The gradient volume holds each voxel's central differences: one trilinear fetch of it must give
// the six taps' gradient, and eight B-spline fetches the 48 taps', but for half-float rounding.
// Checked on the coarse ball and tube and on a tilted slab that crosses the volume's faces, where
// the taps are clamped to the edge, in iso and composite mode: same hits, normals within 0.05
// degrees (the rounding's relative 2^-11 turns a normal by at most about 0.03 degrees) wherever
// the hit lies within the voxel centres' range (a voxel further in for the B-spline).
TEST_F(Normals, GradientVolumeGivesTheNormalsOfTheVolumesTaps) {
    const glm::dvec3 ballCentre(59.3, 58.6, 60.1);
    Scene ball(context(), smoothVolume({48, 48, 48}, glm::dvec3(2.5), [&](const glm::dvec3& p) {
                   return glm::length(p - ballCentre) - 40.0;
               }));
    engine::PinholeCamera outside;
    outside.positionMm = ballCentre + glm::dvec3(30.0, -20.0, -150.0);
    outside.lookAtMm = ballCentre;
    outside.verticalFovDeg = 40.0;
    outside.width = outside.height = 120;

    const glm::dvec2 axis(39.3, 38.6);
    Scene tube(context(), smoothVolume({40, 40, 60}, glm::dvec3(2.0, 2.0, 3.0), [&](const glm::dvec3& p) {
                   return 28.0 - glm::length(glm::dvec2(p.x, p.y) - axis);
               }));
    engine::PinholeCamera inside;
    inside.positionMm = {axis.x, axis.y, 20.0};
    inside.lookAtMm = {axis.x + 8.0, axis.y + 5.0, 160.0};
    inside.verticalFovDeg = 70.0;
    inside.width = inside.height = 120;

    // A slab tilted about two axes, its face crossing all four side faces of the box.
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.15, -0.1, 1.0));
    Scene slab(context(), smoothVolume({30, 30, 24}, glm::dvec3(3.0), [&](const glm::dvec3& p) {
                   return 35.0 - glm::dot(n, p);
               }, 1.0));
    engine::PinholeCamera above;
    above.positionMm = {43.5, 43.5, -60.0};
    above.lookAtMm = {43.5, 43.5, 30.0};
    above.verticalFovDeg = 80.0;
    above.width = above.height = 120;

    struct Case {
        const char* name;
        Scene* scene;
        const engine::PinholeCamera* camera;
    };
    const Case cases[] = {{"ball", &ball, &outside}, {"tube", &tube, &inside}, {"slab", &slab, &above}};
    for (const Case& c : cases) {
        for (const auto gradient : {engine::GradientFilter::Central, engine::GradientFilter::BSpline}) {
            for (const auto mode : {engine::RenderMode::IsoSurface, engine::RenderMode::Composite}) {
                const bool isBSpline = gradient == engine::GradientFilter::BSpline;
                const NormalImage fromVolume = renderNormals(*c.scene, *c.camera, gradient, mode, true);
                const NormalImage fromTaps = renderNormals(*c.scene, *c.camera, gradient, mode, false);
                int compared = 0;
                int atTheFaces = 0;  // hits within a voxel of a side face, where the taps are clamped
                double worstAngle = 0.0;
                double worstHitMm = 0.0;
                for (std::size_t p = 0; p < fromVolume.isHit.size(); ++p) {
                    ASSERT_EQ(fromVolume.isHit[p], fromTaps.isHit[p]) << c.name << " pixel " << p;
                    if (!fromVolume.isHit[p]) continue;
                    const glm::dvec3 hit = fromVolume.position[p];
                    const glm::dvec3 spacing = c.scene->volume.spacingMm;
                    const glm::dvec3 lastCentre =
                        (glm::dvec3(c.scene->volume.dims[0], c.scene->volume.dims[1], c.scene->volume.dims[2]) - 1.0) *
                        spacing;
                    // Beyond the outermost voxel centres the clamped interpolant is flat: the taps
                    // there see the edge difference scaled toward zero, the gradient volume the
                    // edge voxels' own. The two differ by design in that half-voxel shell, and the
                    // B-spline's, whose fetches reach a voxel further, within a voxel more of it.
                    const glm::dvec3 margin = isBSpline ? spacing : glm::dvec3(0.0);
                    if (glm::any(glm::lessThan(hit, margin)) || glm::any(glm::greaterThan(hit, lastCentre - margin))) {
                        continue;
                    }
                    ++compared;
                    const glm::dvec3 nearFace = margin + spacing;  // the taps reach past the centres
                    if (hit.x < nearFace.x || hit.y < nearFace.y || hit.x > lastCentre.x - nearFace.x ||
                        hit.y > lastCentre.y - nearFace.y) {
                        ++atTheFaces;
                    }
                    worstHitMm = std::max(worstHitMm, glm::length(hit - fromTaps.position[p]));
                    worstAngle = std::max(worstAngle, angleDeg(fromVolume.normal[p], fromTaps.normal[p]));
                }
                const std::string what = std::string(c.name) +
                                         (isBSpline ? ", B-spline" : ", central") +
                                         (mode == engine::RenderMode::Composite ? ", composite" : ", iso");
                RecordProperty(what, "worst angle " + std::to_string(worstAngle) + " deg over " +
                                         std::to_string(compared) + " hits, " + std::to_string(atTheFaces) +
                                         " at the faces");
                EXPECT_GT(compared, 3000) << what;
                if (std::string(c.name) == "slab") {
                    EXPECT_GT(atTheFaces, 100) << what;
                }
                EXPECT_LT(worstHitMm, 1e-4) << what;  // shading does not move hits
                EXPECT_LT(worstAngle, 0.05) << what;
            }
        }
    }
}

}  // namespace
