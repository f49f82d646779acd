#include "volumes/phantom_polyps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "volumes/polyline.h"
#include "volumes/random_polyps.h"

namespace volumes {
namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void fail(const std::string& problem) {
    throw VolumeError("colon phantom: " + problem);
}

double segmentDistance2d(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 ab = b - a;
    const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(p - (a + t * ab));
}

/// Exact signed distance to a cap on its support: the solid turns about the base normal, so
/// this is a distance in the half-plane (distance from the axis, height above the base plane)
/// to its profile: the cap's arc, the support's flank and the support's bottom.
double capOnSupportDistance(const PolypSolid& solid, const glm::dvec3& p) {
    const PolypTruth& truth = solid.truth;
    const glm::dvec3 v = p - truth.baseMm;
    const double height = glm::dot(v, truth.baseNormal);
    const glm::dvec2 q(glm::length(v - height * truth.baseNormal), height);
    const double sphereRadius = truth.sphereRadiusMm();
    const double centreHeight = glm::dot(truth.centreMm - truth.baseMm, truth.baseNormal);
    const glm::dvec2 rim(truth.radiusMm, 0.0);
    const glm::dvec2 foot(truth.radiusMm + kFoldSupportSlope * solid.supportDepthMm, -solid.supportDepthMm);
    const glm::dvec2 axisFoot(0.0, -solid.supportDepthMm);
    const glm::dvec2 fromCentre = q - glm::dvec2(0.0, centreHeight);
    const double r = glm::length(fromCentre);
    // The circle's nearest point is on the cap's arc when it lies above the base plane; else
    // the arc's nearest point is the rim. From the centre, every point of the arc is R away.
    double arc = sphereRadius;
    if (r > 0.0) {
        arc = centreHeight + sphereRadius * fromCentre.y / r >= 0.0 ? std::abs(r - sphereRadius) : glm::length(q - rim);
    }
    const double distance = std::min({arc, segmentDistance2d(q, rim, foot), segmentDistance2d(q, foot, axisFoot)});
    const bool isInside = height >= 0.0 ? r <= sphereRadius
                                        : height >= -solid.supportDepthMm &&
                                              q.x <= truth.radiusMm - kFoldSupportSlope * height;
    return isInside ? -distance : distance;
}

/// Signed distance to one polyp's solid; `centrelineDistanceMm` is p's distance from the
/// centreline (for the clip at the wall's middle).
double solidDistance(const PolypSolid& solid, const glm::dvec3& p, double centrelineDistanceMm) {
    const PolypTruth& truth = solid.truth;
    double d = 0.0;
    if (solid.supportDepthMm > 0.0) {
        d = capOnSupportDistance(solid, p);
    } else {
        d = glm::length(p - truth.centreMm) - truth.sphereRadiusMm();
        if (solid.cutDepthMm > 0.0)
            d = std::max(d, -(glm::dot(p - truth.baseMm, truth.baseNormal) + solid.cutDepthMm));
    }
    if (truth.kind == PolypKind::Pedunculated) {
        double t = 0.0;
        d = std::min(d, distanceToSegmentMm(p, solid.stalkStart, solid.stalkEnd, &t) - solid.stalkRadiusMm);
    }
    if (solid.wallClipRadiusMm > 0.0) d = std::max(d, centrelineDistanceMm - solid.wallClipRadiusMm);
    return d;
}

/// Shortest distance between segments p1-q1 and p2-q2 (Ericson, Real-Time Collision Detection, 5.1.9).
double segmentsDistanceMm(const glm::dvec3& p1, const glm::dvec3& q1, const glm::dvec3& p2, const glm::dvec3& q2) {
    const glm::dvec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    constexpr double kTiny = 1e-12;
    double s = 0.0, t = 0.0;
    if (a <= kTiny && e <= kTiny) return glm::length(r);
    if (a <= kTiny) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = glm::dot(d1, r);
        if (e <= kTiny) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = glm::dot(d1, d2), denominator = a * e - b * b;
            s = denominator > kTiny ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0) {
                t = 0.0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1.0) {
                t = 1.0;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return glm::length((p1 + s * d1) - (p2 + t * d2));
}

/// A capsule holding what a polyp puts in the lumen (with the support under one on a fold):
/// random polyps keep kPolypGapMm between these.
struct Capsule {
    glm::dvec3 startMm{0.0}, endMm{0.0};
    double radiusMm = 0.0;
};

Capsule lumenCapsule(const PolypSolid& solid) {
    const PolypTruth& truth = solid.truth;
    return {truth.baseMm - solid.supportDepthMm * truth.baseNormal, truth.baseMm + truth.heightMm() * truth.baseNormal,
            truth.radiusMm + kFoldSupportSlope * solid.supportDepthMm};
}

}  // namespace

double polypDistance(const std::vector<PolypSolid>& polyps, const glm::dvec3& p, double centrelineDistanceMm) {
    double d = std::numeric_limits<double>::max();
    for (const PolypSolid& polyp : polyps) {
        if (glm::length(p - polyp.boundCentreMm) - polyp.boundRadiusMm >= d) continue;
        d = std::min(d, solidDistance(polyp, p, centrelineDistanceMm));
    }
    return d;
}

PolypSolid makePolypSolid(const ColonPhantomSpec& spec, const Centreline& line, const std::vector<Fold>& folds,
                          const PolypPlacement& p) {
    PolypSolid solid;
    PolypTruth& truth = solid.truth;
    truth.kind = p.kind;
    truth.radiusMm = 0.5 * p.diameterMm;
    truth.arcLengthMm = p.arcMm;
    truth.isOnFold = p.isOnFold;
    glm::dvec3 point, tangent, normal;
    line.frameAt(truth.arcLengthMm, point, tangent, normal);
    const glm::dvec3 binormal = glm::cross(tangent, normal);
    const double theta = p.angleDeg * kPi / 180.0;
    const glm::dvec3 outward = std::cos(theta) * normal + std::sin(theta) * binormal;
    // On a fold the base is on the ridge's crest: there the ridge is level along the colon
    // (its profile's apex) and around it (full depth), so the lumen's normal is radial there too.
    const double ridgeHeightMm = p.isOnFold ? foldIntrusion(spec, folds, p.arcMm, theta) : 0.0;
    truth.baseMm = p.isOnFold ? point + (spec.lumenRadiusMm - ridgeHeightMm) * outward
                              : point + spec.lumenRadiusMm * outward;
    truth.baseNormal = -outward;
    if (p.kind == PolypKind::Sessile) {
        truth.centreMm = truth.baseMm;  // half the sphere stands in the lumen: a hemisphere
    } else if (p.kind == PolypKind::Flat) {
        const double height = flatPolypHeightMm(p.diameterMm);
        truth.centreMm = truth.baseMm - (truth.sphereRadiusMm() - height) * truth.baseNormal;
    } else {
        // The head must stop short of the centreline, so a fly-through along it stays in air.
        if (!(p.stalkLengthMm >= 0.5) || p.stalkLengthMm + p.diameterMm > spec.lumenRadiusMm - kCentrelineClearanceMm) {
            fail("a pedunculated polyp of " + std::to_string(p.diameterMm) + " mm on a " +
                 std::to_string(p.stalkLengthMm) + " mm stalk would reach the centreline of a lumen " +
                 std::to_string(2.0 * spec.lumenRadiusMm) + " mm across (stalk + diameter must be at most " +
                 std::to_string(spec.lumenRadiusMm - kCentrelineClearanceMm) + " mm)");
        }
        truth.stalkLengthMm = p.stalkLengthMm;
        truth.centreMm = truth.baseMm + (p.stalkLengthMm + truth.radiusMm) * truth.baseNormal;
        solid.stalkStart = truth.baseMm - spec.wallThicknessMm * 0.5 * truth.baseNormal;
        solid.stalkEnd = truth.centreMm;
        solid.stalkRadiusMm = std::max(1.0, 0.3 * truth.radiusMm);
    }
    if (p.isOnFold) {
        solid.supportDepthMm = ridgeHeightMm + 0.5 * spec.wallThicknessMm;
    } else if (p.kind == PolypKind::Flat) {
        solid.cutDepthMm = 0.5 * spec.wallThicknessMm;
    }
    if (p.isOnFold || p.kind == PolypKind::Flat)
        solid.wallClipRadiusMm = spec.lumenRadiusMm + 0.5 * spec.wallThicknessMm;

    // Bounding spheres: the sphere itself (it holds a cut one too); the support's cylinder; the
    // stalk from the wall's middle to the head's top.
    solid.boundCentreMm = truth.centreMm;
    solid.boundRadiusMm = truth.sphereRadiusMm();
    if (p.isOnFold) {
        const double top = truth.heightMm(), bottom = -solid.supportDepthMm;
        solid.boundCentreMm = truth.baseMm + 0.5 * (top + bottom) * truth.baseNormal;
        solid.boundRadiusMm =
            std::hypot(0.5 * (top - bottom), truth.radiusMm + kFoldSupportSlope * solid.supportDepthMm);
    } else if (p.kind == PolypKind::Pedunculated) {
        const double top = truth.heightMm(), bottom = -0.5 * spec.wallThicknessMm;
        solid.boundCentreMm = truth.baseMm + 0.5 * (top + bottom) * truth.baseNormal;
        solid.boundRadiusMm = std::hypot(0.5 * (top - bottom), truth.radiusMm);
    }
    return solid;
}

std::vector<PolypSolid> layOutRandomSolids(const ColonPhantomSpec& spec, const Centreline& line,
                                           const std::vector<Fold>& folds,
                                           const std::vector<std::array<double, 2>>& blockedArcMm) {
    RandomPolypRoom room;
    room.lengthMm = line.length();
    room.lumenRadiusMm = spec.lumenRadiusMm;
    room.foldDepthMm = spec.foldDepthMm;
    room.foldHalfWidthMm = spec.foldHalfWidthMm;
    room.foldFullDepthHalfAngleRad = kFoldFullDepthHalfAngleRad;
    room.foldHalfAngleRad = kFoldHalfAngleRad;
    room.centrelineClearanceMm = kCentrelineClearanceMm;
    room.supportSlope = kFoldSupportSlope;
    for (const Fold& fold : folds) room.folds.push_back({fold.arcMm, fold.angleRad});
    room.blockedArcMm = blockedArcMm;

    const auto solidOf = [&](const RandomPolyp& p) {
        return makePolypSolid(spec, line, folds,
                              {p.kind, p.diameterMm, p.arcMm, p.angleDeg, p.stalkLengthMm, p.isOnFold});
    };
    std::vector<Capsule> placedCapsules;  // of the layout's `placed`, which only grows
    const PolypFitCheck fits = [&](const RandomPolyp& candidate, const std::vector<RandomPolyp>& placed) {
        while (placedCapsules.size() < placed.size())
            placedCapsules.push_back(lumenCapsule(solidOf(placed[placedCapsules.size()])));
        const PolypSolid solid = solidOf(candidate);
        for (const glm::dvec3& c : line.points) {
            if (solidDistance(solid, c, 0.0) < kCentrelineClearanceMm) return false;
        }
        const Capsule capsule = lumenCapsule(solid);
        return std::all_of(placedCapsules.begin(), placedCapsules.end(), [&](const Capsule& other) {
            return segmentsDistanceMm(capsule.startMm, capsule.endMm, other.startMm, other.endMm) - capsule.radiusMm -
                       other.radiusMm >= kPolypGapMm;
        });
    };
    std::vector<PolypSolid> solids;
    for (const RandomPolyp& p : layOutRandomPolyps(spec.randomPolypCount, spec.seed, room, fits))
        solids.push_back(solidOf(p));
    return solids;
}

const char* polypKindName(PolypKind kind) {
    switch (kind) {
        case PolypKind::Sessile: return "sessile";
        case PolypKind::Pedunculated: return "pedunculated";
        case PolypKind::Flat: return "flat";
    }
    return "sessile";
}

double flatPolypHeightMm(double diameterMm) { return std::min(2.5, 0.25 * diameterMm); }

double flatPolypSphereRadiusMm(double diameterMm) {
    const double h = flatPolypHeightMm(diameterMm);
    return (0.25 * diameterMm * diameterMm + h * h) / (2.0 * h);
}

double PolypTruth::sphereRadiusMm() const {
    return kind == PolypKind::Flat ? flatPolypSphereRadiusMm(2.0 * radiusMm) : radiusMm;
}

double PolypTruth::heightMm() const {
    switch (kind) {
        case PolypKind::Sessile: return radiusMm;
        case PolypKind::Pedunculated: return stalkLengthMm + 2.0 * radiusMm;
        case PolypKind::Flat: return flatPolypHeightMm(2.0 * radiusMm);
    }
    return radiusMm;
}

}  // namespace volumes
