/// @brief Polyp candidates on the colon wall (computer-aided detection), from the wall's shape
/// alone, after Yoshida & Naeppi (IEEE TMI 20(12), 2001): a polyp is a cap of tissue bulging
/// into the lumen, a haustral fold a ridge, the lumen's own wall a rut (colon/surface_curvature.h).
///
/// The rule, step by step (each threshold's reason is in docs/candidates.md):
///  1. The shape index and curvedness at the centre of every element of the colon wall's mesh
///     (colon/wall_surface.h), on the volume smoothed by max(smoothingMm, 0.75 voxel).
///  2. Cap regions by hysteresis on the mesh: seeds where SI >= seedShapeIndex and the
///     curvedness lies in [minCurvedness, maxCurvedness], grown over neighbouring elements with
///     SI >= growShapeIndex and curvedness >= minCurvedness.
///  3. Regions whose centres lie closer than the sum of their equivalent radii (a hemisphere of
///     the region's area) are merged: noise can split one polyp's cap into pieces.
///  4. A region is dropped when its area is under minCapAreaMm2 (a speck of noise or a fold's
///     knot) or it is elongated (the ratio of its two largest extents over maxElongation: a
///     fold's crest, a ridge that the smoothing rounded into caps along its length).
///  5. Its diameter is measured as `cvc measure` measures a polyp (colon/surface_measure.h) on
///     a CPU view (colon/surface_view.h) from the lumen along the region's normal; under
///     minDiameterMm, or where no view can be had, the region is dropped.
///  6. Score = capness x fill x roundness, each in [0, 1]: capness the mean SI mapped from
///     [growShapeIndex, 1] onto [0, 1]; fill the cap's area over the area of the measured
///     diameter's disc (capped at 1: a polyp's cap covers its footprint, a fold's knot a small
///     part of what the patch rule then measures); roundness 1 / elongation.
/// Candidates are ranked by score, highest first, and at most maxCandidates are kept.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "colon/wall_surface.h"
#include "volumes/volume.h"

namespace colon {

struct CandidateSettings {
    double isoHu = -500.0;          ///< the wall, as rendered and meshed
    double smoothingMm = 1.0;       ///< Gaussian sigma (at least 0.75 of the largest voxel spacing)
    double seedShapeIndex = 0.9;
    double growShapeIndex = 0.8;
    double minCurvedness = 0.05;    ///< 1/mm: a sphere of 20 mm radius
    double maxCurvedness = 0.7;     ///< 1/mm: a sphere of 1.4 mm radius, under the smallest polyp's
    double minCapAreaMm2 = 5.0;
    double maxElongation = 3.0;
    double minDiameterMm = 4.0;
    int maxCandidates = 50;
};

struct PolypCandidate {
    glm::dvec3 centreMm{0.0};   ///< the cap's centre on the surface (volume millimetres)
    glm::dvec3 normal{0.0};     ///< into the lumen
    double diameterMm = 0.0;    ///< measured as colon/surface_measure.h's polypDiameter
    double score = 0.0;
    double shapeIndex = 0.0;    ///< the cap's mean (area-weighted)
    double curvedness = 0.0;    ///< the cap's mean (area-weighted), 1/mm
    double capAreaMm2 = 0.0;
    double elongation = 1.0;
    int elements = 0;           ///< wall elements in the cap
    glm::dvec3 viewEyeMm{0.0};  ///< where the measuring view looked from
    glm::dvec3 sphereCentreMm{0.0};  ///< the sphere the measurement fitted to the patch
    double sphereRadiusMm = 0.0;     ///< 0: no sphere fitted (a flat patch)
};

struct CandidateSearch {
    std::vector<PolypCandidate> candidates;  ///< ranked, highest score first
    int capRegions = 0;                      ///< after merging
    int droppedSmall = 0;                    ///< step 4: area
    int droppedElongated = 0;                ///< step 4: a ridge
    int droppedUnmeasured = 0;               ///< step 5: no view, or under minDiameterMm
    int droppedBeyondLimit = 0;              ///< past maxCandidates
    double wallAreaMm2 = 0.0;
    std::size_t wallElements = 0;
};

/// The Gaussian sigma step 1 smooths `volume` with: settings.smoothingMm, at least 0.75 of its
/// largest voxel spacing.
double candidateSmoothingMm(const CandidateSettings& settings, const volumes::Volume& volume);

using CandidateProgress = std::function<void(const std::string& step)>;

/// The candidates on `wall` (the colon wall of `volume` at settings.isoHu). Throws ColonError
/// for settings out of range or an empty wall.
CandidateSearch findPolypCandidates(const volumes::Volume& volume, const WallSurface& wall,
                                    const CandidateSettings& settings = {}, const CandidateProgress& progress = {});

}  // namespace colon
