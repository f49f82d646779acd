/// Random polyp layouts of the colon phantom (`cvc phantom --random-polyps N`) and the flat kind,
/// against their own ground truth: the same seed gives the same layout, sizes, kinds and the
/// share on folds are as promised, the polyps stay apart and clear of the centreline, and the
/// voxels straddle the air/tissue boundary on every polyp's truth surface.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"
#include "tests/volumes/test_support.h"
#include "volumes/colon_phantom.h"
#include "volumes/polyline.h"
#include "volumes/random_polyps.h"

namespace volumes {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A phantom with `count` random polyps; noise off unless asked for (the layout does not use it).
ColonPhantomSpec randomSpec(int count, std::uint64_t seed, int size, double spacingMm, double noiseSigmaHu = 0.0) {
    ColonPhantomSpec spec;
    spec.grid = {{size, size, size}, glm::dvec3(spacingMm)};
    spec.randomPolypCount = count;
    spec.seed = seed;
    spec.noiseSigmaHu = noiseSigmaHu;
    return spec;
}

/// Coarse voxels (96^3 x 1.6 mm, the default colon's extent) for what needs only the truth.
ColonPhantom coarsePhantom(int count, std::uint64_t seed) { return makeColonPhantom(randomSpec(count, seed, 96, 1.6)); }

double distanceToPolylineMm(const std::vector<glm::dvec3>& line, const glm::dvec3& p) {
    double best = 1e300;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, distanceToSegmentMm(p, line[i], line[i + 1]));
    return best;
}

/// Least distance between two segments, by brute force along both (0.05 mm steps): an oracle
/// independent of the phantom's closed form.
double segmentGapMm(const glm::dvec3& a0, const glm::dvec3& a1, const glm::dvec3& b0, const glm::dvec3& b1) {
    const int steps = std::max(1, static_cast<int>(std::ceil(glm::length(a1 - a0) / 0.05)));
    double best = 1e300;
    for (int i = 0; i <= steps; ++i) best = std::min(best, distanceToSegmentMm(glm::mix(a0, a1, double(i) / steps), b0, b1));
    return best;
}

int onFoldCount(const ColonPhantom& phantom) {
    return static_cast<int>(std::count_if(phantom.polyps.begin(), phantom.polyps.end(),
                                          [](const PolypTruth& p) { return p.isOnFold; }));
}

TEST(RandomPolyps, SameSeedSameLayoutOtherSeedAnother) {
    const ColonPhantomSpec spec = randomSpec(10, 4, 96, 1.6, 15.0);
    const ColonPhantom a = makeColonPhantom(spec), b = makeColonPhantom(spec);
    EXPECT_EQ(colonTruthJson(spec, a), colonTruthJson(spec, b));
    EXPECT_EQ(a.volume.hu, b.volume.hu);
    const ColonPhantom other = coarsePhantom(10, 5);
    ASSERT_EQ(other.polyps.size(), 10u);
    int samePlaces = 0;
    for (std::size_t i = 0; i < 10; ++i) samePlaces += a.polyps[i].baseMm == other.polyps[i].baseMm ? 1 : 0;
    EXPECT_EQ(samePlaces, 0);
    // The folds are where they are without polyps, whatever the seed.
    EXPECT_EQ(a.foldArcLengthsMm, other.foldArcLengthsMm);
    ColonPhantomSpec noPolyps = randomSpec(0, 4, 96, 1.6);
    noPolyps.polyps.clear();
    EXPECT_EQ(a.foldArcLengthsMm, makeColonPhantom(noPolyps).foldArcLengthsMm);
}

TEST(RandomPolyps, SizesKindsAndFoldsAsPromised) {
    const ColonPhantomSpec spec;  // lumen 11 mm, folds 4 mm deep
    std::map<PolypKind, int> kinds;
    int total = 0;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
        const ColonPhantom phantom = coarsePhantom(12, seed);
        ASSERT_EQ(phantom.polyps.size(), 12u) << "seed " << seed;
        EXPECT_EQ(onFoldCount(phantom), 3) << "seed " << seed << ": round(12 / 4) on folds";
        for (std::size_t i = 0; i < phantom.polyps.size(); ++i) {
            const PolypTruth& p = phantom.polyps[i];
            const double d = 2.0 * p.radiusMm;
            ++kinds[p.kind];
            ++total;
            EXPECT_GE(d, 5.0);
            EXPECT_LE(d, 15.0);
            if (i > 0) {
                EXPECT_LE(phantom.polyps[i - 1].arcLengthMm, p.arcLengthMm) << "sorted along the colon";
            }
            // Each kind's truth: the sphere, its centre and the height above the base.
            const double centreHeight = glm::dot(p.centreMm - p.baseMm, p.baseNormal);
            if (p.kind == PolypKind::Flat) {
                const double h = std::min(2.5, d / 4.0), r = (d * d / 4.0 + h * h) / (2.0 * h);
                EXPECT_NEAR(p.heightMm(), h, 1e-12);
                EXPECT_NEAR(p.sphereRadiusMm(), r, 1e-12);
                EXPECT_NEAR(centreHeight, h - r, 1e-9);
            } else if (p.kind == PolypKind::Sessile) {
                EXPECT_EQ(p.centreMm, p.baseMm);
                EXPECT_DOUBLE_EQ(p.heightMm(), p.radiusMm);
            } else {
                EXPECT_FALSE(p.isOnFold) << "a stalk on a fold would reach the centreline";
                EXPECT_GE(p.stalkLengthMm, 1.0);
                EXPECT_LE(p.heightMm(), spec.lumenRadiusMm - 1.5 + 1e-9);
                EXPECT_NEAR(centreHeight, p.stalkLengthMm + p.radiusMm, 1e-9);
            }
            // On a fold: at the fold's own arc, the base on the ridge's crest (the lumen radius less
            // the fold's depth from the centreline); on the wall: the lumen radius.
            const double baseFromCentreline = distanceToPolylineMm(phantom.centrelineMm, p.baseMm);
            if (p.isOnFold) {
                EXPECT_TRUE(std::any_of(phantom.foldArcLengthsMm.begin(), phantom.foldArcLengthsMm.end(),
                                        [&](double f) { return std::abs(f - p.arcLengthMm) < 1e-9; }));
                EXPECT_NEAR(baseFromCentreline, spec.lumenRadiusMm - spec.foldDepthMm, 0.05);
            } else {
                EXPECT_NEAR(baseFromCentreline, spec.lumenRadiusMm, 0.05);
            }
        }
    }
    // 45 / 25 / 30 % over 96 polyps, within the spread of so few draws.
    EXPECT_NEAR(kinds[PolypKind::Sessile] / double(total), 0.45, 0.12);
    EXPECT_NEAR(kinds[PolypKind::Pedunculated] / double(total), 0.25, 0.12);
    EXPECT_NEAR(kinds[PolypKind::Flat] / double(total), 0.30, 0.12);
}

TEST(RandomPolyps, PolypsStayApartAndClearOfTheCentreline) {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        const ColonPhantom phantom = coarsePhantom(kMaxRandomPolyps, seed);
        ASSERT_EQ(phantom.polyps.size(), static_cast<std::size_t>(kMaxRandomPolyps));
        // Each polyp lies in a capsule from its base to its top as wide as its base (its head):
        // those keep kPolypGapMm apart.
        for (std::size_t i = 0; i < phantom.polyps.size(); ++i)
            for (std::size_t j = i + 1; j < phantom.polyps.size(); ++j) {
                const PolypTruth &a = phantom.polyps[i], &b = phantom.polyps[j];
                const double gap = segmentGapMm(a.baseMm, a.baseMm + a.heightMm() * a.baseNormal, b.baseMm,
                                                b.baseMm + b.heightMm() * b.baseNormal) -
                                   a.radiusMm - b.radiusMm;
                EXPECT_GE(gap, kPolypGapMm - 0.05) << "seed " << seed << ", polyps " << i << " and " << j;
            }
        // Nothing of a polyp within 1.5 mm of the centreline: a fly-through along it stays in air.
        for (const PolypTruth& p : phantom.polyps) {
            const glm::dvec3 top = p.baseMm + p.heightMm() * p.baseNormal;
            for (const glm::dvec3& c : phantom.centrelineMm) {
                ASSERT_GE(glm::length(c - p.centreMm) - p.sphereRadiusMm(), 1.5 - 1e-9) << "seed " << seed;
                ASSERT_GE(glm::length(c - top), 1.5 - 1e-9);
            }
        }
    }
}

TEST(RandomPolyps, KeepOutOfCollapsesAndFluid) {
    ColonPhantomSpec spec = ColonPhantomSpec::withAnatomy(randomSpec(20, 3, 96, 1.6));
    const ColonPhantom phantom = makeColonPhantom(spec);
    ASSERT_EQ(phantom.polyps.size(), 20u);
    std::vector<std::array<double, 2>> blocked = phantom.collapsedArcMm;
    for (const FluidPoolTruth& pool : phantom.fluidPools) blocked.push_back({pool.startArcMm, pool.endArcMm});
    ASSERT_EQ(blocked.size(), 2u);
    for (const PolypTruth& p : phantom.polyps)
        for (const auto& [start, end] : blocked) {
            EXPECT_TRUE(p.arcLengthMm + p.radiusMm < start || p.arcLengthMm - p.radiusMm > end)
                << "polyp at " << p.arcLengthMm << " mm in " << start << ".." << end;
        }
}

TEST(RandomPolyps, RefusesCountsThatDoNotFit) {
    for (int count : {-1, kMaxRandomPolyps + 1, 1000}) {
        try {
            makeColonPhantom(randomSpec(count, 1, 96, 1.6));
            ADD_FAILURE() << count << " random polyps were accepted";
        } catch (const VolumeError& e) {
            EXPECT_NE(std::string(e.what()).find("random polyps asked for; 1..30 fit"), std::string::npos) << e.what();
        }
    }
    // A small grid's short colon (217 mm) has no room for the most polyps: it says how many fit.
    try {
        makeColonPhantom(randomSpec(kMaxRandomPolyps, 1, 72, 1.6));
        ADD_FAILURE() << "a short colon took " << kMaxRandomPolyps << " polyps";
    } catch (const VolumeError& e) {
        EXPECT_NE(std::string(e.what()).find("random polyps fit in the"), std::string::npos) << e.what();
    }
}

TEST(RandomPolyps, FlatPolypsAreListedToo) {
    const PolypSpec flat = parsePolypSpec("flat:8:0.4:120");
    EXPECT_EQ(flat.kind, PolypKind::Flat);
    EXPECT_DOUBLE_EQ(flat.diameterMm, 8.0);
    EXPECT_DOUBLE_EQ(flat.arcFraction, 0.4);
    EXPECT_DOUBLE_EQ(flat.angleDeg, 120.0);
    EXPECT_THROW(parsePolypSpec("flat:2:0.4:120"), VolumeError);
    EXPECT_EQ(std::string(polypKindName(PolypKind::Flat)), "flat");
    ColonPhantomSpec spec;
    spec.grid = {{128, 128, 128}, glm::dvec3(1.2)};
    spec.polyps = {flat, parsePolypSpec("sessile:6:0.7:0")};
    const ColonPhantom phantom = makeColonPhantom(spec);
    const nlohmann::json truth = nlohmann::json::parse(colonTruthJson(spec, phantom));
    const nlohmann::json& p = truth["polyps"][0];
    EXPECT_EQ(p["kind"], "flat");
    EXPECT_DOUBLE_EQ(p["height_mm"].get<double>(), 2.0);          // min(2.5, 8 / 4)
    EXPECT_DOUBLE_EQ(p["sphere_radius_mm"].get<double>(), 5.0);   // (16 + 4) / (2 * 2)
    EXPECT_DOUBLE_EQ(p["diameter_mm"].get<double>(), 8.0);
    EXPECT_EQ(p["on_fold"], false);
    EXPECT_FALSE(truth.contains("random_polyps"));
    const PolypTruth& t = phantom.polyps[0];
    EXPECT_NEAR(glm::length(t.centreMm - (t.baseMm - 3.0 * t.baseNormal)), 0.0, 1e-9);  // R - h below the wall
    // Every kind has the new fields: a sessile polyp's sphere is its own radius.
    EXPECT_DOUBLE_EQ(truth["polyps"][1]["sphere_radius_mm"].get<double>(), 3.0);
    EXPECT_DOUBLE_EQ(truth["polyps"][1]["height_mm"].get<double>(), 3.0);
    // The cap is tissue, 2 mm high: air 2 mm above its top, tissue 1.5 mm under it.
    const Volume& v = phantom.volume;
    auto huAt = [&](const glm::dvec3& q) {
        const glm::ivec3 i(glm::round(q / v.spacingMm));
        return v.at(i.x, i.y, i.z);
    };
    const glm::dvec3 top = t.baseMm + 2.0 * t.baseNormal;
    EXPECT_LT(huAt(top + 2.0 * t.baseNormal), -900);
    EXPECT_GT(huAt(top - 1.5 * t.baseNormal), -100);
}

TEST(RandomPolyps, TruthJsonNamesTheLayout) {
    const ColonPhantomSpec spec = randomSpec(12, 7, 96, 1.6);
    const ColonPhantom phantom = makeColonPhantom(spec);
    const nlohmann::json truth = nlohmann::json::parse(colonTruthJson(spec, phantom));
    EXPECT_EQ(truth["random_polyps"]["count"].get<int>(), 12);
    EXPECT_EQ(truth["random_polyps"]["seed"].get<std::uint64_t>(), 7u);
    ASSERT_EQ(truth["polyps"].size(), 12u);
    for (std::size_t i = 0; i < 12; ++i) {
        const nlohmann::json& p = truth["polyps"][i];
        const PolypTruth& t = phantom.polyps[i];
        EXPECT_EQ(p["kind"], polypKindName(t.kind));
        EXPECT_DOUBLE_EQ(p["diameter_mm"].get<double>(), 2.0 * t.radiusMm);
        EXPECT_DOUBLE_EQ(p["sphere_radius_mm"].get<double>(), t.sphereRadiusMm());
        EXPECT_DOUBLE_EQ(p["height_mm"].get<double>(), t.heightMm());
        EXPECT_EQ(p["on_fold"].get<bool>(), t.isOnFold);
    }
}

TEST(RandomPolyps, VoxelsStraddleEveryTruthSurface) {
    // Two layouts at 192^3 x 0.8 mm (the default colon's extent) with CT noise: between them
    // every kind on the wall, and sessile and flat ones on folds (about 2 s to build).
    std::vector<ColonPhantom> phantoms;
    for (std::uint64_t seed : {1, 2}) phantoms.push_back(makeColonPhantom(randomSpec(12, seed, 192, 0.8, 15.0)));
    // Points on each polyp's truth surface: on its sphere, above the wall plane and in the upper
    // half of the polyp's height (sessile, flat), or on the head away from the stalk. Just outside
    // along the sphere's normal is air, just inside tissue. 1.3 mm keeps the nearest voxel
    // (at most 0.7 mm off) beyond the 0.5 mm partial-volume ramp.
    constexpr double kStepMm = 1.3;
    std::vector<glm::dvec3> directions;
    for (int k = 0; k < 200; ++k) {
        const double z = 1.0 - 2.0 * (k + 0.5) / 200.0, r = std::sqrt(1.0 - z * z), phi = k * kPi * (3.0 - std::sqrt(5.0));
        directions.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
    std::map<std::string, int> checkedKinds;
    for (const ColonPhantom& phantom : phantoms) {
        const Volume& v = phantom.volume;
        auto huAt = [&](const glm::dvec3& q) {
            const glm::ivec3 i(glm::round(q / v.spacingMm));
            return v.at(i.x, i.y, i.z);
        };
        for (const PolypTruth& p : phantom.polyps) {
            int checked = 0;
            for (const glm::dvec3& u : directions) {
                const glm::dvec3 onSurface = p.centreMm + p.sphereRadiusMm() * u;
                const double height = glm::dot(onSurface - p.baseMm, p.baseNormal);
                if (p.kind == PolypKind::Pedunculated ? glm::dot(u, p.baseNormal) < -0.3 : height < 0.5 * p.heightMm())
                    continue;
                ++checked;
                const int16_t outside = huAt(onSurface + kStepMm * u), inside = huAt(onSurface - kStepMm * u);
                EXPECT_LT(outside, -700) << polypKindName(p.kind) << (p.isOnFold ? " on a fold" : "") << " at "
                                         << p.arcLengthMm << " mm, height " << height;
                EXPECT_GT(inside, -300) << polypKindName(p.kind) << (p.isOnFold ? " on a fold" : "") << " at "
                                        << p.arcLengthMm << " mm, height " << height;
            }
            EXPECT_GE(checked, 6);
            ++checkedKinds[std::string(polypKindName(p.kind)) + (p.isOnFold ? " on a fold" : "")];
        }
        // And a fly-through along the centreline stays in air.
        for (const glm::dvec3& c : phantom.centrelineMm) ASSERT_LT(huAt(c), -900);
    }
    for (const char* kind : {"sessile", "pedunculated", "flat", "sessile on a fold", "flat on a fold"})
        EXPECT_GT(checkedKinds[kind], 0) << "no " << kind << " polyp in these layouts";
}

TEST(CvcPhantom, RandomPolypsOnTheCommandLine) {
    const std::string folder = testing::scratchFolder("cvc_phantom_random");
    const auto run = testing_support::runCvc("phantom --size 96 --spacing 1.6 --random-polyps 6 --seed 2 -o '" + folder +
                                             "/colon.nrrd'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.out.find("with 6 polyps"), std::string::npos) << run.out;
    std::ifstream in(folder + "/colon.json");
    const nlohmann::json truth = nlohmann::json::parse(in);
    ASSERT_EQ(truth["polyps"].size(), 6u);
    EXPECT_EQ(truth["random_polyps"]["seed"].get<int>(), 2);
    // Bad counts and a list beside a random layout: one line naming the option.
    const std::string out = " --size 96 --spacing 1.6 --force -o '" + folder + "/bad.nrrd'";
    for (const auto& [arguments, message] :
         std::vector<std::pair<std::string, std::string>>{
             {"--random-polyps 0", "--random-polyps 0: 1..30 polyps fit"},
             {"--random-polyps 1000", "--random-polyps 1000: 1..30 polyps fit"},
             {"--random-polyps 4 --polyp sessile:6:0.5:0", "--polyp cannot go with --random-polyps"},
             {"--kind ball --random-polyps 4", "--random-polyps describes the colon phantom"}}) {
        const auto bad = testing_support::runCvc("phantom " + arguments + out);
        EXPECT_NE(bad.exitCode, 0) << arguments;
        EXPECT_NE(bad.err.find(message), std::string::npos) << arguments << ": " << bad.err;
        EXPECT_EQ(testing_support::lineCount(bad.err), 1) << bad.err;
    }
}

}  // namespace
}  // namespace volumes
