/// @brief The colon phantom's polyps as solids: sessile, pedunculated and flat polyps placed on
/// the plain wall or on a fold's ridge (a cap on a support that thickens the fold under it),
/// their signed distances, and the random layout's polyps checked against each other in 3D.
/// Internal to the phantom (colon_phantom.cpp); the public polyp types are in colon_phantom.h.
#pragma once

#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "volumes/colon_phantom.h"
#include "volumes/phantom_tube.h"

namespace volumes {

/// Free space a pedunculated polyp's head (and any random polyp) leaves around the centreline (mm).
constexpr double kCentrelineClearanceMm = 1.5;
/// How fast (mm per mm of depth) the support under a polyp on a fold widens towards the wall.
constexpr double kFoldSupportSlope = 0.5;

/// Where a polyp goes, in tube coordinates: a listed PolypSpec or a random one.
struct PolypPlacement {
    PolypKind kind = PolypKind::Sessile;
    double diameterMm = 0.0, arcMm = 0.0, angleDeg = 0.0, stalkLengthMm = 0.0;
    bool isOnFold = false;
};

/// A polyp's solid. Sessile: the whole sphere (its lower half hides in the wall). Pedunculated:
/// the head's sphere and a capsule stalk. Flat: the sphere cut half a wall thickness below the
/// base plane (R is large: the rest would bulge out through the wall). On a fold, the cap (the
/// sphere above the base plane) stands on a support, a frustum from the base disc widening down
/// to the wall's middle: the fold thickens under the polyp rather than leave the cap's rim
/// overhanging a 3 mm ridge. The support is fold, not polyp: the truth's surface is the cap.
struct PolypSolid {
    PolypTruth truth;
    glm::dvec3 stalkStart{0.0}, stalkEnd{0.0};
    double stalkRadiusMm = 0.0;
    double cutDepthMm = 0.0;        ///< flat on the wall: cut this far below the base plane (0: not cut)
    double supportDepthMm = 0.0;    ///< on a fold: the support's depth below the base plane (0: none)
    /// > 0: no polyp beyond this distance from the centreline (the wall's middle), so the fat
    /// band stays fat.
    double wallClipRadiusMm = 0.0;
    glm::dvec3 boundCentreMm{0.0};  ///< a sphere holding the solid, to skip far polyps
    double boundRadiusMm = 0.0;
};

/// A polyp's solid at its place: on the wall (or a fold's ridge) at its arc and angle, the base
/// normal pointing into the lumen. Throws VolumeError for a pedunculated polyp that would reach
/// within kCentrelineClearanceMm of the centreline.
PolypSolid makePolypSolid(const ColonPhantomSpec& spec, const Centreline& line, const std::vector<Fold>& folds,
                          const PolypPlacement& p);

/// Signed distance to the polyps' union (negative inside a polyp). A polyp whose bounding
/// sphere is no nearer than the nearest so far cannot lower the minimum and is skipped.
double polypDistance(const std::vector<PolypSolid>& polyps, const glm::dvec3& p, double centrelineDistanceMm);

/// The random layout's polyps as solids. The layout draws them in tube coordinates; here each
/// candidate is checked in 3D: kCentrelineClearanceMm from every centreline point and
/// kPolypGapMm between the capsules holding the polyps. `blockedArcMm`: arc ranges that take no
/// polyp (collapses with their tapers, fluid pools).
std::vector<PolypSolid> layOutRandomSolids(const ColonPhantomSpec& spec, const Centreline& line,
                                           const std::vector<Fold>& folds,
                                           const std::vector<std::array<double, 2>>& blockedArcMm);

}  // namespace volumes
