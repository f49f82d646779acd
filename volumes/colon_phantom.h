/// @brief A colon-like phantom with known ground truth: a curved air-filled tube with a soft-
/// tissue wall, haustral folds, a fat layer, and sessile, pedunculated and flat polyps placed
/// along its centreline (listed, or laid out at random from a seed), plus CT-like noise.
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

/// Sessile: a hemisphere on the wall. Pedunculated: a sphere (the head) on a stalk. Flat (Paris
/// 0-IIa-like): a spherical cap of base diameter D rising h = min(2.5 mm, D / 4) above the wall.
enum class PolypKind { Sessile, Pedunculated, Flat };

/// "sessile", "pedunculated" or "flat", as the ground truth and --polyp spell it.
const char* polypKindName(PolypKind kind);

/// A flat polyp of base diameter `diameterMm`: its height above the wall, min(2.5 mm, D / 4).
double flatPolypHeightMm(double diameterMm);

/// A flat polyp's sphere radius R = (D^2 / 4 + h^2) / (2 h): the cap of height h cut from it
/// has a base of diameter D.
double flatPolypSphereRadiusMm(double diameterMm);

/// Where a polyp goes and how big it is.
struct PolypSpec {
    PolypKind kind = PolypKind::Sessile;
    /// 3..15 mm (the head's diameter for a pedunculated polyp, the base's for a flat one)
    double diameterMm = 6.0;
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
    std::uint64_t seed = 1;  ///< the noise, and the layout of random polyps
    std::vector<PolypSpec> polyps = defaultPolyps();
    /// 1..kMaxRandomPolyps: that many polyps laid out at random from `seed` replace `polyps`
    /// (volumes/random_polyps.h gives the rules); the folds then stay where they are without
    /// polyps and about a quarter of the polyps stand on a fold's ridge. 0: `polyps` as listed.
    int randomPolypCount = 0;

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

/// At most this many random polyps (ColonPhantomSpec::randomPolypCount). The default colon
/// (~290 mm) holds 35 for every seed tried; with --anatomy's collapse and pool, 30 fit for most
/// seeds, and a layout that does not fit fails naming how many did.
inline constexpr int kMaxRandomPolyps = 30;

/// Ground truth of one polyp, in volume millimetres.
struct PolypTruth {
    PolypKind kind = PolypKind::Sessile;
    /// Sphere centre: sessile, on the wall surface; pedunculated, the head's centre; flat, R - h
    /// below the wall surface along the base normal.
    glm::dvec3 centreMm{0.0};
    double radiusMm = 0.0;       ///< half the diameter (the head's, or the flat polyp's base)
    glm::dvec3 baseMm{0.0};      ///< where the polyp meets the wall (or the fold's ridge it stands on)
    glm::dvec3 baseNormal{0.0};  ///< unit wall (or ridge) normal at the base, pointing into the lumen
    double arcLengthMm = 0.0;    ///< along the centreline from its start
    double stalkLengthMm = 0.0;
    bool isOnFold = false;  ///< on a haustral fold's ridge rather than the plain wall

    /// The radius of the sphere the polyp's surface lies on: radiusMm, or a flat polyp's R.
    double sphereRadiusMm() const;
    /// How far the polyp rises above its base along the normal: r, h, or stalk + diameter.
    double heightMm() const;
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
/// 3..15 mm, a pedunculated polyp that would not fit the lumen, a grid the tube does not fit,
/// more random polyps than fit).
ColonPhantom makeColonPhantom(const ColonPhantomSpec& spec);

/// The ground truth as JSON text: grid, tissue values, centreline polyline, folds and polyps
/// (volume millimetres; see volume.h).
std::string colonTruthJson(const ColonPhantomSpec& spec, const ColonPhantom& phantom);

/// Parses "sessile:6:0.3:45", "flat:8:0.4:120" or "pedunculated:10:0.6:200[:stalkMm]" (kind:
/// diameterMm:arcFraction:angleDeg) into a PolypSpec; throws VolumeError naming the part that is wrong.
PolypSpec parsePolypSpec(const std::string& text);

/// Parses "POSITION[:LENGTH_MM]" (e.g. "0.42:12") into a CollapseSpec; throws VolumeError.
CollapseSpec parseCollapseSpec(const std::string& text);

/// Parses "POSITION[:LENGTH_MM[:DEPTH_MM]]" (e.g. "0.238:40:6") into a FluidPoolSpec; throws VolumeError.
FluidPoolSpec parseFluidPoolSpec(const std::string& text);

}  // namespace volumes
