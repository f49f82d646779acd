/// @brief Random polyp layouts for the colon phantom (`cvc phantom --random-polyps N`): kinds,
/// sizes and places drawn from a seed, about a quarter of them on the ridge of a haustral fold.
///
/// Draws come from a SplitMix64 stream turned into doubles here (not std::uniform_*_distribution,
/// whose output the standard leaves to each library), so a seed gives the same layout on every
/// platform. The layout works in tube coordinates (arc length along the centreline, angle around
/// it); whether a candidate clears the centreline and the polyps already placed is asked of the
/// phantom, which knows the 3D shapes.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "volumes/colon_phantom.h"

namespace volumes {

/// One haustral fold as the layout sees it: where it is along the colon and the angle of its
/// deepest part.
struct FoldSite {
    double arcMm = 0.0;
    double angleRad = 0.0;
};

/// The colon the polyps go into.
struct RandomPolypRoom {
    double lengthMm = 0.0;  ///< centreline length
    double lumenRadiusMm = 11.0;
    double foldDepthMm = 4.0;
    double foldHalfWidthMm = 1.6;
    double foldFullDepthHalfAngleRad = 0.0;  ///< a fold reaches its full depth within this of its angle
    double foldHalfAngleRad = 0.0;           ///< and is absent beyond this (its gap)
    double centrelineClearanceMm = 1.5;      ///< free space every polyp leaves around the centreline
    double supportSlope = 0.5;               ///< a polyp on a fold: how fast its support widens with depth
    std::vector<FoldSite> folds;
    /// Arc ranges with no polyps: collapses (tapers included) and fluid pools.
    std::vector<std::array<double, 2>> blockedArcMm;
};

/// One polyp of a random layout, in tube coordinates.
struct RandomPolyp {
    PolypKind kind = PolypKind::Sessile;
    double diameterMm = 0.0;  ///< the head's for a pedunculated polyp, the base's for a flat one
    double arcMm = 0.0;       ///< along the centreline; a fold's own arc length when on a fold
    double angleDeg = 0.0;    ///< around the centreline, from the curve's reference normal
    double stalkLengthMm = 0.0;
    bool isOnFold = false;
};

/// Whether `candidate` keeps the centreline clear and stays apart from every polyp in `placed`,
/// judged on the shapes in the volume.
using PolypFitCheck = std::function<bool(const RandomPolyp& candidate, const std::vector<RandomPolyp>& placed)>;

/// Lays out `count` polyps (1..kMaxRandomPolyps) from `seed`, sorted by arc length.
/// Kinds: sessile 45 %, pedunculated 25 %, flat 30 %; diameters uniform in 5..15 mm where they fit
/// (pedunculated: stalk + diameter at most lumen radius - clearance, the stalk drawn within what
/// is left; a sessile polyp on a fold must keep the clearance above the ridge). round(count / 4)
/// polyps sit on a fold's ridge (sessile or flat, at the fold's arc, within its full-depth
/// angles), the others on the plain wall, clear of the folds' feet by kFoldGapMm. None within
/// kEndMarginMm of the colon's ends or kPolypGapMm of a blocked arc range. Throws VolumeError
/// for a count outside 1..kMaxRandomPolyps or when the polyps do not all fit.
std::vector<RandomPolyp> layOutRandomPolyps(int count, std::uint64_t seed, const RandomPolypRoom& room,
                                            const PolypFitCheck& fits);

/// Least gap (mm) between two polyps of a random layout, and between one and a blocked arc range.
inline constexpr double kPolypGapMm = 3.0;
/// Least gap (mm) between a polyp on the plain wall and the foot of a fold beside it.
inline constexpr double kFoldGapMm = 1.0;
/// No random polyp within this (mm) of either end of the colon.
inline constexpr double kEndMarginMm = 10.0;

}  // namespace volumes
