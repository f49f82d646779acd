// Polyp candidates against closed forms: the shape index and curvedness of a ball, a tube and a
// fold's crest; a CPU view of a ball against ray-sphere intersection; a place on a path of
// straight pieces; and the whole rule on a tube with ring folds and a hemisphere on its wall,
// where the hemisphere is found with its diameter and the folds are not.
#include <cmath>

#include <gtest/gtest.h>

#include "colon/colon_error.h"
#include "colon/path_place.h"
#include "colon/polyp_candidates.h"
#include "colon/surface_curvature.h"
#include "colon/surface_view.h"
#include "colon/wall_surface.h"
#include "tests/support/tube_volume.h"

namespace {

using testing_support::TubeSpec;

/// A ball of tissue of `radiusMm` in air at the centre of a cube, with the tube's 1 mm ramp.
volumes::Volume ballVolume(double radiusMm, double spacingMm, double extentMm) {
    volumes::Volume v;
    const int n = static_cast<int>(std::lround(extentMm / spacingMm));
    v.dims = {n, n, n};
    v.spacingMm = glm::dvec3(spacingMm);
    v.hu.resize(v.voxelCount());
    const glm::dvec3 centre(0.5 * (n - 1) * spacingMm);
    for (int k = 0; k < n; ++k) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const double inside = radiusMm - glm::length(glm::dvec3(i, j, k) * spacingMm - centre);
                const double t = std::clamp(0.5 + inside, 0.0, 1.0);
                v.hu[v.linearIndex(i, j, k)] = static_cast<int16_t>(std::lround(-1000.0 + 1040.0 * t));
            }
        }
    }
    return v;
}

glm::dvec3 cubeCentre(const volumes::Volume& v) { return 0.5 * glm::dvec3(v.dims[0] - 1) * v.spacingMm.x; }

TEST(SurfaceCurvature, ShapeIndexOfTheFiveShapesIsTheirClosedForm) {
    EXPECT_NEAR(colon::shapeIndexOf(1.0, 1.0), 1.0, 1e-12);     // cap
    EXPECT_NEAR(colon::shapeIndexOf(1.0, 0.0), 0.75, 1e-12);    // ridge
    EXPECT_NEAR(colon::shapeIndexOf(1.0, -1.0), 0.5, 1e-12);    // saddle
    EXPECT_NEAR(colon::shapeIndexOf(0.0, -1.0), 0.25, 1e-12);   // rut
    EXPECT_NEAR(colon::shapeIndexOf(-1.0, -1.0), 0.0, 1e-12);   // cup
    EXPECT_NEAR(colon::curvednessOf(0.2, 0.2), 0.2, 1e-12);
    EXPECT_NEAR(colon::curvednessOf(0.2, 0.0), 0.2 / std::sqrt(2.0), 1e-12);
}

TEST(SurfaceCurvature, ABallIsACapOfCurvednessOneOverItsRadius) {
    const double radius = 5.0;
    const volumes::Volume ball = ballVolume(radius, 0.5, 24.0);
    const glm::dvec3 centre = cubeCentre(ball);
    for (const glm::dvec3 direction : {glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::normalize(glm::dvec3(1, 2, -2)),
                                       glm::normalize(glm::dvec3(-0.3, 0.4, 0.8))}) {
        const auto shape = colon::surfaceShapeAt(ball, centre + radius * direction, 1.0, -500.0);
        ASSERT_TRUE(shape.has_value());
        EXPECT_GT(shape->shapeIndex, 0.98);
        // The smoothed ball's iso surface lies a little inside the ball: within 5 % of 1/r.
        EXPECT_NEAR(shape->curvedness, 1.0 / radius, 0.05 / radius);
        EXPECT_GT(glm::dot(shape->normal, direction), 0.999);  // outward: into the air
    }
}

TEST(SurfaceCurvature, TheLumenIsARutAndAFoldsCrestARidge) {
    TubeSpec spec;
    spec.radiusMm = 10.0;
    spec.extentMm = {28.0, 28.0, 60.0};
    spec.zStartMm = 4.0;
    spec.zEndMm = 56.0;
    spec.foldSpacingMm = 1.0;  // one fold, at z = 40
    spec.foldFirstMm = spec.foldLastMm = 40.0;
    spec.foldHeightMm = 4.0;
    spec.foldThicknessMm = 3.0;
    const volumes::Volume tube = testing_support::tubeVolume(spec);
    const glm::dvec3 axis(0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y, 0.0);
    // The tube's wall, far from the fold and the ends: k1 = 0, k2 = -1/R.
    const auto wall = colon::surfaceShapeAt(tube, axis + glm::dvec3(spec.radiusMm, 0.0, 20.0), 1.0, -500.0);
    ASSERT_TRUE(wall.has_value());
    EXPECT_NEAR(wall->shapeIndex, 0.25, 0.02);
    EXPECT_NEAR(wall->k2, -1.0 / spec.radiusMm, 0.1 / spec.radiusMm);
    EXPECT_NEAR(wall->k1, 0.0, 0.01);
    // The fold's crest, a ring of radius R - h bulging into the lumen: a ridge, below the
    // candidates' growing threshold.
    const glm::dvec3 crest = axis + glm::dvec3(0.0, spec.radiusMm - spec.foldHeightMm, 40.0);
    const auto ridge = colon::surfaceShapeAt(tube, crest, 1.0, -500.0);
    ASSERT_TRUE(ridge.has_value());
    EXPECT_GT(ridge->shapeIndex, 0.55);
    EXPECT_LT(ridge->shapeIndex, colon::CandidateSettings{}.growShapeIndex);
    EXPECT_THROW(colon::surfaceShapeAt(tube, crest, 0.0, -500.0), colon::ColonError);
    EXPECT_FALSE(colon::surfaceShapeAt(tube, glm::dvec3(-1.0, 5.0, 5.0), 1.0, -500.0).has_value());
}

TEST(SurfaceView, HitsOfABallLieOnItAndMissesAroundIt) {
    const double radius = 5.0;
    const volumes::Volume ball = ballVolume(radius, 0.5, 30.0);
    const glm::dvec3 centre = cubeCentre(ball);
    colon::SurfaceViewRequest view;
    view.eyeMm = centre + glm::dvec3(0.0, 0.0, -13.0);
    view.lookAtMm = centre;
    view.up = {0.0, 1.0, 0.0};
    view.fovDeg = 60.0;
    view.size = 64;
    const colon::HitImage image = colon::surfaceView(ball, view);
    // Ray-sphere intersection: a pixel hits when its ray passes within r of the centre.
    const double halfWidth = std::tan(M_PI / 6.0);
    int agreeing = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const double u = halfWidth * (2.0 * (x + 0.5) / image.width - 1.0);
            const double v = halfWidth * (1.0 - 2.0 * (y + 0.5) / image.height);
            const glm::dvec3 d = glm::normalize(glm::dvec3(-u, v, 1.0));  // right = forward x up = -x
            const glm::dvec3 toCentre = centre - view.eyeMm;
            const double along = glm::dot(toCentre, d);
            const double miss2 = glm::dot(toCentre, toCentre) - along * along;
            const bool expectHit = miss2 < radius * radius;
            if (std::abs(std::sqrt(miss2) - radius) < 0.15) continue;  // grazing: either answer
            EXPECT_EQ(image.hitAt(x, y), expectHit) << x << ", " << y;
            if (expectHit && image.hitAt(x, y)) {
                EXPECT_NEAR(glm::length(image.hitMm[image.index(x, y)] - centre), radius, 0.05);
                ++agreeing;
            }
        }
    }
    EXPECT_GT(agreeing, 200);
    const auto picture = colon::shadedSurfaceView(image, view.eyeMm);
    ASSERT_EQ(picture.size(), 64u * 64u * 4u);
    EXPECT_GT(picture[4 * image.index(32, 32)], picture[4 * image.index(32, 32 - 11)]);  // lit head-on, darker at the rim
    EXPECT_EQ(picture[4 * image.index(0, 0)], 0);                                        // a miss is black
    view.eyeMm = centre;  // inside the ball
    EXPECT_THROW(colon::surfaceView(ball, view), colon::ColonError);
}

TEST(PathPlace, ArcLengthCountsTheSegmentsButNotTheGaps) {
    const std::vector<std::vector<glm::dvec3>> segments = {{{0, 0, 0}, {10, 0, 0}, {10, 10, 0}},  // 20 mm
                                                           {{30, 10, 0}, {30, 30, 0}}};           // 20 mm
    const std::vector<glm::dvec3> frames = {{0, 0, 0}, {10, 5, 0}, {30, 10, 0}, {30, 20, 0}, {30, 30, 0}};
    const colon::PathPlace place = colon::placeOnPath(segments, {33, 16, 0}, frames);
    EXPECT_EQ(place.segment, 1);
    EXPECT_NEAR(place.arcLengthMm, 26.0, 1e-9);
    EXPECT_NEAR(place.distanceMm, 3.0, 1e-9);
    EXPECT_EQ(place.nearestFrame, 3);
    const colon::PathPlace first = colon::placeOnPath(segments, {4, -2, 0}, frames);
    EXPECT_EQ(first.segment, 0);
    EXPECT_NEAR(first.arcLengthMm, 4.0, 1e-9);
    EXPECT_EQ(first.nearestFrame, 0);
    EXPECT_EQ(colon::placeOnPath({}, {1, 1, 1}, frames).segment, -1);
}

/// A tube with two ring folds and, between them, balls centred on the wall (hemispheres).
TubeSpec polypTube(const std::vector<std::pair<double, double>>& polypsAtZWithRadius) {
    TubeSpec spec;
    spec.spacingMm = 0.5;
    spec.radiusMm = 10.0;
    spec.extentMm = {28.0, 28.0, 90.0};
    spec.zStartMm = 5.0;
    spec.zEndMm = 85.0;
    spec.foldSpacingMm = 50.0;
    spec.foldFirstMm = 20.0;
    spec.foldLastMm = 70.0;
    spec.foldHeightMm = 4.0;
    spec.foldThicknessMm = 2.5;
    double angle = 0.0;
    for (const auto& [z, r] : polypsAtZWithRadius) {
        const glm::dvec3 onWall(0.5 * spec.extentMm.x + spec.radiusMm * std::cos(angle),
                                0.5 * spec.extentMm.y + spec.radiusMm * std::sin(angle), z);
        spec.balls.emplace_back(onWall, r);
        angle += 2.0;
    }
    return spec;
}

TEST(PolypCandidates, AHemisphereOnTheWallIsFoundWithItsDiameterAndTheFoldsAreNot) {
    const TubeSpec spec = polypTube({{45.0, 4.0}});
    const volumes::Volume tube = testing_support::tubeVolume(spec);
    const colon::WallSurface wall = colon::colonWallSurface(tube, testing_support::airMask(tube));
    const colon::CandidateSearch search = colon::findPolypCandidates(tube, wall);
    ASSERT_EQ(search.candidates.size(), 1u) << "the hemisphere alone; the folds are ridges";
    const colon::PolypCandidate& found = search.candidates.front();
    // Its apex: the ball's centre moved r toward the axis.
    const glm::dvec3 ballCentre = spec.balls.front().first;
    const glm::dvec3 inward = glm::normalize(glm::dvec3(0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y, 45.0) - ballCentre);
    EXPECT_LT(glm::length(found.centreMm - (ballCentre + 4.0 * inward)), 1.5);
    EXPECT_NEAR(found.diameterMm, 8.0, 1.2);
    EXPECT_GT(glm::dot(found.normal, inward), 0.9);
    EXPECT_GT(found.shapeIndex, 0.9);
    EXPECT_GT(found.score, 0.5);
}

TEST(PolypCandidates, FoldsAloneGiveNoCandidateAndBadSettingsAreRefused) {
    const volumes::Volume tube = testing_support::tubeVolume(polypTube({}));
    const colon::WallSurface wall = colon::colonWallSurface(tube, testing_support::airMask(tube));
    const colon::CandidateSearch search = colon::findPolypCandidates(tube, wall);
    EXPECT_TRUE(search.candidates.empty()) << search.candidates.front().diameterMm << " mm at z "
                                           << search.candidates.front().centreMm.z;
    colon::CandidateSettings bad;
    bad.growShapeIndex = 0.95;  // above the seeds' threshold
    EXPECT_THROW(colon::findPolypCandidates(tube, wall, bad), colon::ColonError);
    EXPECT_THROW(colon::findPolypCandidates(tube, colon::WallSurface{}), colon::ColonError);
}

TEST(PolypCandidates, TwoPolypsAreRankedAndASpeckIsNotOne) {
    // A 10 mm and a 6 mm hemisphere, and a 2 mm one under the smallest diameter reported.
    const TubeSpec spec = polypTube({{35.0, 5.0}, {55.0, 3.0}, {45.0, 1.0}});
    const volumes::Volume tube = testing_support::tubeVolume(spec);
    const colon::WallSurface wall = colon::colonWallSurface(tube, testing_support::airMask(tube));
    const colon::CandidateSearch search = colon::findPolypCandidates(tube, wall);
    ASSERT_EQ(search.candidates.size(), 2u);
    for (const auto& candidate : search.candidates) {
        const bool isLarge = std::abs(candidate.centreMm.z - 35.0) < 3.0;
        EXPECT_TRUE(isLarge || std::abs(candidate.centreMm.z - 55.0) < 3.0) << candidate.centreMm.z;
        EXPECT_NEAR(candidate.diameterMm, isLarge ? 10.0 : 6.0, isLarge ? 1.5 : 1.0);
    }
    EXPECT_GE(search.candidates[0].score, search.candidates[1].score);
}

}  // namespace
