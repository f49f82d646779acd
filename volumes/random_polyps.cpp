#include "volumes/random_polyps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace volumes {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinDiameterMm = 5.0;
constexpr double kMaxDiameterMm = 15.0;
/// A random pedunculated polyp's stalk is at least this long, so that it reads as a stalk.
constexpr double kMinStalkMm = 1.0;
/// Kept below the pedunculated limit (stalk + diameter <= reach), so rounding never crosses it.
constexpr double kRoundingMarginMm = 1e-6;
/// A polyp on a fold keeps this much of the ridge's full-depth part beyond its base on either side.
constexpr double kRidgeMarginRad = 2.0 * kPi / 180.0;
/// Places tried per polyp before the layout gives up; a polyp meant for a fold tries the ridges
/// for the first half, then the plain wall.
constexpr int kTriesPerPolyp = 4000;

// Kind shares: on a fold only sessile and flat polyps (a stalk there would reach the centreline),
// so the plain wall takes more pedunculated ones; with a quarter on folds the whole layout has
// sessile 0.25 * 0.6 + 0.75 * 0.4 = 45 %, pedunculated 0.75 / 3 = 25 %, flat 30 %.
constexpr double kSessileShareOnFold = 0.6;
constexpr double kSessileShareOnWall = 0.4;
constexpr double kPedunculatedShareOnWall = 1.0 / 3.0;

/// SplitMix64 (Steele, Lea and Flood 2014) as a sequential stream, with doubles made from its top
/// 53 bits: the same numbers on every platform and standard library.
class LayoutRandom {
public:
    explicit LayoutRandom(std::uint64_t seed) : mState(seed * 0xd6e8feb86659fd93ULL + 0x6c61796f7574ULL) {}

    std::uint64_t next() {
        std::uint64_t z = (mState += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1).
    double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    double between(double low, double high) { return low + (high - low) * unit(); }
    /// Uniform in 0..n-1 (n > 0).
    std::size_t below(std::size_t n) {
        return std::min(n - 1, static_cast<std::size_t>(unit() * static_cast<double>(n)));
    }

private:
    std::uint64_t mState;
};

std::string mm(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f mm", value);
    return text;
}

/// Largest diameter a kind can have here (below kMinDiameterMm: the kind does not fit).
double largestDiameterMm(PolypKind kind, bool isOnFold, const RandomPolypRoom& room) {
    const double reach = room.lumenRadiusMm - room.centrelineClearanceMm;
    if (kind == PolypKind::Pedunculated) return std::min(kMaxDiameterMm, reach - kMinStalkMm - kRoundingMarginMm);
    // A sessile polyp rises its radius above the ridge, which already stands foldDepth high.
    if (kind == PolypKind::Sessile && isOnFold) return std::min(kMaxDiameterMm, 2.0 * (reach - room.foldDepthMm));
    return kMaxDiameterMm;
}

PolypKind drawKind(LayoutRandom& random, bool isOnFold, const RandomPolypRoom& room) {
    const double u = random.unit();
    PolypKind kind = PolypKind::Flat;
    if (isOnFold) {
        if (u < kSessileShareOnFold) kind = PolypKind::Sessile;
    } else if (u < kSessileShareOnWall) {
        kind = PolypKind::Sessile;
    } else if (u < kSessileShareOnWall + kPedunculatedShareOnWall) {
        kind = PolypKind::Pedunculated;
    }
    // A lumen too narrow for the drawn kind gets the next flatter one (flat always fits).
    if (kind == PolypKind::Pedunculated && largestDiameterMm(kind, isOnFold, room) < kMinDiameterMm)
        kind = PolypKind::Sessile;
    if (kind == PolypKind::Sessile && largestDiameterMm(kind, isOnFold, room) < kMinDiameterMm)
        kind = PolypKind::Flat;
    return kind;
}

/// How far (mm) a polyp reaches along the colon from its arc: its base radius, and on a fold
/// the foot of the support that widens the fold under it.
double arcReachMm(const RandomPolyp& p, const RandomPolypRoom& room) {
    return 0.5 * p.diameterMm + (p.isOnFold ? room.supportSlope * room.foldDepthMm : 0.0);
}

/// A size and a place for a polyp of the given kind (a ridge when on a fold, anywhere otherwise).
RandomPolyp drawCandidate(LayoutRandom& random, PolypKind kind, bool isOnFold, const RandomPolypRoom& room) {
    RandomPolyp p;
    p.kind = kind;
    p.isOnFold = isOnFold;
    p.diameterMm = random.between(kMinDiameterMm, largestDiameterMm(kind, isOnFold, room));
    if (kind == PolypKind::Pedunculated) {
        p.stalkLengthMm = random.between(
            kMinStalkMm, room.lumenRadiusMm - room.centrelineClearanceMm - p.diameterMm - kRoundingMarginMm);
    }
    double angleRad = 0.0;
    if (isOnFold) {
        // On the ridge's crest at the fold's own arc, where the fold is at full depth all under
        // the base: there the ridge is flat along the colon and around it, so its normal is radial.
        const FoldSite& fold = room.folds[random.below(room.folds.size())];
        p.arcMm = fold.arcMm;
        const double ridgeRadiusMm = room.lumenRadiusMm - room.foldDepthMm;
        const double spread = std::max(
            0.0, room.foldFullDepthHalfAngleRad - 0.5 * p.diameterMm / ridgeRadiusMm - kRidgeMarginRad);
        angleRad = fold.angleRad + random.between(-spread, spread);
    } else {
        const double reach = arcReachMm(p, room);
        p.arcMm = random.between(reach + kEndMarginMm, room.lengthMm - reach - kEndMarginMm);
        angleRad = random.between(0.0, 2.0 * kPi);
    }
    p.angleDeg = std::fmod(angleRad * 180.0 / kPi + 720.0, 360.0);
    return p;
}

/// Angle between two directions around the centreline, 0..pi.
double angularDistanceRad(double a, double b) {
    const double d = std::fmod(std::abs(a - b), 2.0 * kPi);
    return std::min(d, 2.0 * kPi - d);
}

/// The rules that need no 3D shapes: the colon's ends, blocked arcs, and the folds' feet for a
/// polyp on the plain wall (it may stand beside a fold, not under one).
bool isClearInTube(const RandomPolyp& p, const RandomPolypRoom& room) {
    const double reach = arcReachMm(p, room);
    if (p.arcMm - reach < kEndMarginMm || p.arcMm + reach > room.lengthMm - kEndMarginMm) return false;
    for (const auto& [start, end] : room.blockedArcMm) {
        if (p.arcMm + reach > start - kPolypGapMm && p.arcMm - reach < end + kPolypGapMm) return false;
    }
    if (p.isOnFold) return true;
    const double angleRad = p.angleDeg * kPi / 180.0;
    const double angularReach = reach / room.lumenRadiusMm;
    for (const FoldSite& fold : room.folds) {
        const bool isBesideAlong = std::abs(p.arcMm - fold.arcMm) < reach + room.foldHalfWidthMm + kFoldGapMm;
        const bool isUnderAround = angularDistanceRad(angleRad, fold.angleRad) < room.foldHalfAngleRad + angularReach;
        if (isBesideAlong && isUnderAround) return false;
    }
    return true;
}

}  // namespace

std::vector<RandomPolyp> layOutRandomPolyps(int count, std::uint64_t seed, const RandomPolypRoom& room,
                                            const PolypFitCheck& fits) {
    if (count < 1 || count > kMaxRandomPolyps) {
        throw VolumeError("colon phantom: " + std::to_string(count) + " random polyps asked for; 1.." +
                          std::to_string(kMaxRandomPolyps) + " fit in the colon");
    }
    LayoutRandom random(seed);

    // Which polyps go on a fold: round(count / 4) of them, chosen by a Fisher-Yates shuffle.
    const std::size_t n = static_cast<std::size_t>(count);
    std::vector<bool> isOnFold(n, false);
    const std::size_t onFolds = room.folds.empty() ? 0 : static_cast<std::size_t>(std::lround(count / 4.0));
    std::fill(isOnFold.begin(), isOnFold.begin() + static_cast<std::ptrdiff_t>(onFolds), true);
    for (std::size_t i = n - 1; i > 0; --i) {
        const std::size_t j = random.below(i + 1);
        const bool swapped = isOnFold[i];
        isOnFold[i] = isOnFold[j];
        isOnFold[j] = swapped;
    }

    std::vector<RandomPolyp> placed;
    for (std::size_t i = 0; i < n; ++i) {
        const PolypKind kind = drawKind(random, isOnFold[i], room);
        bool isPlaced = false;
        for (int attempt = 0; attempt < kTriesPerPolyp && !isPlaced; ++attempt) {
            // A polyp meant for a fold whose ridges are all taken stands on the plain wall.
            const bool onFold = isOnFold[i] && attempt < kTriesPerPolyp / 2;
            const RandomPolyp candidate = drawCandidate(random, kind, onFold, room);
            if (isClearInTube(candidate, room) && fits(candidate, placed)) {
                placed.push_back(candidate);
                isPlaced = true;
            }
        }
        if (!isPlaced) {
            throw VolumeError("colon phantom: only " + std::to_string(i) + " of " + std::to_string(count) +
                              " random polyps fit in the " + mm(room.lengthMm) + " colon (each " +
                              mm(kPolypGapMm) + " clear of the others); ask for fewer or use a larger grid");
        }
    }
    std::stable_sort(placed.begin(), placed.end(),
                     [](const RandomPolyp& a, const RandomPolyp& b) { return a.arcMm < b.arcMm; });
    return placed;
}

}  // namespace volumes
