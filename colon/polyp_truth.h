/// @brief The polyps of a ground-truth JSON (the phantom's, or `cvc insert-polyp`'s): what the
/// shape checks need to tell a polyp's surface from the wall around it.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace colon {

struct PolypSurface {
    /// Sessile or flat: the part of a sphere above the wall plane (a hemisphere, or a flat
    /// polyp's low cap); otherwise a pedunculated polyp's head on a stalk.
    bool isSessile = true;
    bool isFlat = false;        ///< a flat (Paris 0-IIa-like) cap; isSessile is true for it too
    double diameterMm = 0.0;    ///< the head's, or the base's for sessile and flat polyps
    double sphereRadiusMm = 0.0; ///< the sphere's radius; 0 reads as diameterMm / 2 (see sphereRadius)
    glm::dvec3 centreMm{0.0};   ///< sphere centre (sessile: on the wall surface; flat: below it)
    glm::dvec3 baseMm{0.0};     ///< where the polyp meets the wall
    glm::dvec3 baseNormal{0.0}; ///< unit wall normal at the base, into the lumen

    /// The radius of the sphere the polyp's surface lies on: sphereRadiusMm when set, else
    /// half the diameter (sessile and pedunculated polyps, and truth written before the field).
    double sphereRadius() const { return sphereRadiusMm > 0.0 ? sphereRadiusMm : 0.5 * diameterMm; }
};

/// The "polyps" list of a ground-truth JSON file: kind sessile, pedunculated or flat; the
/// optional "sphere_radius_mm" (absent: half the diameter; a flat polyp needs it, and it may
/// not be less than half the diameter). Throws ColonError naming the file and the polyp for a
/// missing file, a missing or malformed field, or a polyp of non-positive size.
std::vector<PolypSurface> readPolypTruth(const std::string& path);

/// The candidates of `cvc candidates`' candidates.json as polyps to check, best first: each a
/// sessile cap below its apex ("centre_mm") along its normal, as wide as its measured diameter,
/// of the radius of the sphere its measurement fitted ("sphere_radius_mm"; the cap's base circle
/// lies where a sphere of that radius through the apex is that wide);
/// a candidate without a fitted sphere, or one whose sphere is narrower than its diameter (a
/// head seen from above), is the hemisphere of its diameter below its apex. Throws ColonError
/// naming the file and the candidate for a missing file, a missing or malformed field, or an
/// empty list.
std::vector<PolypSurface> readCandidatesAsPolyps(const std::string& path);

/// Whether a surface point in volume millimetres lies on the polyp: on its sphere (the head of
/// a pedunculated polyp; the stalk and the wall are not the polyp) within `toleranceMm`, and for
/// a sessile or flat polyp above the wall plane.
bool isOnPolyp(const PolypSurface& polyp, const glm::dvec3& pointMm, double toleranceMm);

/// The point a polyp is aimed at and its distance measured to: a pedunculated polyp's head
/// centre, or half way up a sessile or flat polyp's cap above its base.
glm::dvec3 polypAimPointOf(const PolypSurface& polyp);

/// Where the ray from `originMm` along the unit `direction` first meets the polyp's own surface
/// (its sphere; for a sessile or flat polyp the part above the wall plane, below which the wall
/// hides the sphere), with nothing else in the way; nothing (false) where it does not.
bool firstPolypHit(const PolypSurface& polyp, const glm::dvec3& originMm, const glm::dvec3& direction, glm::dvec3& hitMm);

/// How much nearer the eye than the polyp's own surface a first hit must lie to be something in
/// front of the polyp (a fold, a bend of the wall) rather than its rim: where a polyp meets the
/// wall the rendered surface rounds off within a voxel or so of its sphere, and the hit within
/// `toleranceMm` of it (polypToleranceMm). 1 mm, or twice the tolerance on coarser scans.
double hiddenInFrontMarginMm(double toleranceMm);

/// Whether the ray from `originMm` along the unit `direction` would meet the polyp's own surface
/// (firstPolypHit) above the lowest quarter of a sessile or flat polyp's cap (its rim, which the
/// wall curving up around the base hides from grazing rays) while its first hit `hitMm` lies more
/// than hiddenInFrontMarginMm nearer the eye: something in front of the polyp hides it there.
bool isHiddenInFront(const PolypSurface& polyp, const glm::dvec3& originMm, const glm::dvec3& direction,
                     const glm::dvec3& hitMm, double toleranceMm);

}  // namespace colon
