/// @brief A colon-like phantom with known ground truth: a curved air-filled tube with a soft-
/// tissue wall, haustral folds, a fat layer, and sessile and pedunculated polyps placed along
/// its centreline, plus CT-like noise.
///
/// Geometry is analytic signed distance (not OpenVDB level sets): every voxel is classified
/// from closed-form distances to the centreline polyline, the fold ridges and the polyp
/// spheres and stalks, so the ground truth is exact by construction and the phantom is
/// reproducible bit for bit from its spec and seed, with no resampling or CSG rounding in
/// between. Positions are in volume millimetres (voxel (i, j, k) at (i, j, k) * spacingMm).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "volumes/analytic_phantom.h"
#include "volumes/volume.h"

namespace volumes {

enum class PolypKind { Sessile, Pedunculated };

/// Where a polyp goes and how big it is.
struct PolypSpec {
    PolypKind kind = PolypKind::Sessile;
    double diameterMm = 6.0;     ///< 3..15 mm (the head's diameter for a pedunculated polyp)
    double arcFraction = 0.5;    ///< position along the centreline, 0 (start) .. 1 (end)
    double angleDeg = 0.0;       ///< around the centreline, from the curve's reference normal
    double stalkLengthMm = 4.0;  ///< pedunculated only: wall to the head's surface
};

/// A stretch where the colon has collapsed (not distended): the air lumen tapers to nothing
/// and the wall tissue fills it, so the lumen's air splits into two parts, as in a CT
/// colonography scan with a poorly distended segment.
struct CollapseSpec {
    double arcFraction = 0.5;  ///< centre of the collapse along the centreline, 0..1
    double lengthMm = 12.0;    ///< fully closed over this length; a taper of kCollapseTaperMm on each side
};

/// Tagged residual fluid lying in the lowest part of the lumen (gravity along +y, supine).
struct FluidPoolSpec {
    double arcFraction = 0.5;  ///< centre of the pool along the centreline, 0..1
    double lengthMm = 40.0;    ///< the pool covers arc lengths [s - L/2, s + L/2]
    double depthMm = 6.0;      ///< from the lowest point of the lumen surface in that range up to the level
};

/// How far (mm) a collapse's lumen radius takes to close, on each side of the closed part.
inline constexpr double kCollapseTaperMm = 5.0;

struct ColonPhantomSpec {
    GridSpec grid{{256, 256, 256}, glm::dvec3(0.6)};
    double lumenRadiusMm = 11.0;  ///< distended colon, ~22 mm across
    double wallThicknessMm = 2.5;
    double fatThicknessMm = 6.0;   ///< pericolic fat band outside the wall
    double foldSpacingMm = 22.0;   ///< haustral folds along the centreline
    double foldDepthMm = 4.0;      ///< how far a fold reaches into the lumen
    double foldHalfWidthMm = 1.6;  ///< half the thickness of a fold ridge
    int16_t lumenHu = -1000;
    int16_t tissueHu = 40;  ///< wall, polyps, and the soft tissue around
    int16_t fatHu = -100;
    double edgeWidthMm = 1.0;    ///< partial-volume ramp across air/tissue surfaces
    double noiseSigmaHu = 15.0;  ///< Gaussian noise, smoothed over neighbours like CT noise
    std::uint64_t seed = 1;
    std::vector<PolypSpec> polyps = defaultPolyps();

    // Anatomy around the colon, all off by default (the default phantom is unchanged). These are
    // what colon segmentation and centreline extraction are tested against: air outside the
    // body and in the lungs that must not be taken for colon, a collapsed segment that splits
    // the lumen, and tagged fluid that hides part of it.
    std::uint64_t shapeSeed = 0;  ///< 0: the standard curve; N > 0: control points moved by a hash of N
    bool hasBody = false;         ///< elliptic body outline with air outside
    bool hasLung = false;         ///< two lung bases at the top of the grid (needs nothing else)
    int16_t lungHu = -860;        ///< lung parenchyma, not pure air
    int16_t fluidHu = 600;        ///< tagged residual fluid
    std::vector<CollapseSpec> collapses;
    std::vector<FluidPoolSpec> fluidPools;

    /// Five polyps, 3 to 12 mm, both kinds, spread along the colon and around it.
    static std::vector<PolypSpec> defaultPolyps();

    /// `base` with body, lungs, one 12 mm collapse at 0.42 and one 40 mm pool 6 mm deep at 0.238:
    /// positions clear of the default polyps (see docs/volumes.md for their arc lengths).
    static ColonPhantomSpec withAnatomy(ColonPhantomSpec base);
};

/// Ground truth of one polyp, in volume millimetres.
struct PolypTruth {
    PolypKind kind = PolypKind::Sessile;
    glm::dvec3 centreMm{0.0};  ///< sphere centre (sessile: on the wall surface; the head's centre otherwise)
    double radiusMm = 0.0;
    glm::dvec3 baseMm{0.0};      ///< where the polyp meets the wall
    glm::dvec3 baseNormal{0.0};  ///< unit wall normal at the base, pointing into the lumen
    double arcLengthMm = 0.0;    ///< along the centreline from its start
    double stalkLengthMm = 0.0;
};

/// The body outline: an elliptic cylinder along z (x, y in volume millimetres).
struct BodyTruth {
    glm::dvec2 centreMm{0.0};
    glm::dvec2 semiAxesMm{0.0};
};

/// A lung base: an ellipsoid, cut by the grid's top face.
struct LungTruth {
    std::string side;  ///< "right" (small x) or "left" (large x), the patient's side
    glm::dvec3 centreMm{0.0};
    glm::dvec3 semiAxesMm{0.0};
};

struct FluidPoolTruth {
    double startArcMm = 0.0, endArcMm = 0.0;  ///< the arc range the fluid lies in
    double levelYMm = 0.0;                    ///< fluid where y > level (y grows posteriorly, downwards)
};

struct ColonPhantom {
    Volume volume;
    std::vector<glm::dvec3> centrelineMm;  ///< polyline through the lumen centre, ~1 mm steps, caecum to rectum
    std::vector<PolypTruth> polyps;
    std::vector<double> foldArcLengthsMm;  ///< where the haustral folds are along the centreline
    BodyTruth body;                        ///< set when spec.hasBody
    std::vector<LungTruth> lungs;          ///< two when spec.hasLung
    double lungClearanceMm = 0.0;          ///< hasLung: least gap between the lungs and the colon's fat
    std::vector<std::array<double, 2>> collapsedArcMm;  ///< arc ranges with no air on the centreline
    std::vector<FluidPoolTruth> fluidPools;
};

/// Builds the phantom. Throws VolumeError for a spec that cannot make sense (polyp sizes outside
/// 3..15 mm, a pedunculated polyp that would not fit the lumen, a grid the tube does not fit).
ColonPhantom makeColonPhantom(const ColonPhantomSpec& spec);

/// The ground truth as JSON text: grid, tissue values, centreline polyline, folds and polyps
/// (volume millimetres; see volume.h).
std::string colonTruthJson(const ColonPhantomSpec& spec, const ColonPhantom& phantom);

/// Parses "sessile:6:0.3:45" or "pedunculated:10:0.6:200[:stalkMm]" (kind:diameterMm:
/// arcFraction:angleDeg) into a PolypSpec; throws VolumeError naming the part that is wrong.
PolypSpec parsePolypSpec(const std::string& text);

/// Parses "POSITION[:LENGTH_MM]" (e.g. "0.42:12") into a CollapseSpec; throws VolumeError.
CollapseSpec parseCollapseSpec(const std::string& text);

/// Parses "POSITION[:LENGTH_MM[:DEPTH_MM]]" (e.g. "0.238:40:6") into a FluidPoolSpec; throws VolumeError.
FluidPoolSpec parseFluidPoolSpec(const std::string& text);

}  // namespace volumes
