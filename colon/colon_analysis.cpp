#include "colon/colon_analysis.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "colon/colon_error.h"
#include "colon/connected_components.h"

namespace colon {
namespace {

constexpr int kSteps = 4;
/// The largest code of the label volume (a byte's).
constexpr int kMaxLabelCode = 255;

/// The air segmentation's labels turned into the lumen's: colon air and cleansed voxels become
/// unlabelled (to be labelled again by component), the rest keeps its class as a code.
std::vector<int16_t> classCodes(const AirSegmentation& air) {
    std::vector<int16_t> codeOfLabel(air.regions.size() + 1, kLabelNone);
    for (const AirRegion& region : air.regions) {
        int16_t code = kLabelNone;
        switch (region.kind) {
            case AirClass::Outside: code = kLabelOutside; break;
            case AirClass::Small: code = kLabelSmall; break;
            case AirClass::Lung: code = kLabelLung; break;
            case AirClass::Round: code = kLabelRound; break;
            case AirClass::Colon: code = kLabelShortColon; break;
        }
        codeOfLabel[static_cast<std::size_t>(region.label)] = code;
    }
    return codeOfLabel;
}

/// Caecum-likeness of a point: far to the patient's right (low L) and low (low S).
double caecumScore(const volumes::Volume& volume, const glm::dvec3& pointMm) {
    const glm::dvec3 lps = volumes::patientFromVolumeMm(volume, pointMm);
    return -2.0 * lps.x - lps.z;
}

/// Orders the segments from the caecum along the nearest ends, then reverses the chain so it
/// runs rectum -> caecum; fills the gaps between consecutive segments.
void orderAntegrade(const volumes::Volume& volume, std::vector<ColonSegment>& segments, std::vector<double>& gaps) {
    if (segments.empty()) return;
    // The caecal end: the best-scoring end of any segment.
    std::size_t first = 0;
    bool isFirstReversed = false;
    double best = -std::numeric_limits<double>::max();
    for (std::size_t s = 0; s < segments.size(); ++s) {
        const auto& points = segments[s].centreline.pointsMm;
        for (const bool atEnd : {false, true}) {
            const double score = caecumScore(volume, atEnd ? points.back() : points.front());
            if (score > best) {
                best = score;
                first = s;
                isFirstReversed = atEnd;  // the chain must start at this end
            }
        }
    }
    std::vector<ColonSegment> chain;
    std::vector<bool> isUsed(segments.size(), false);
    auto take = [&](std::size_t s, bool isReversed) {
        ColonSegment segment = segments[s];
        if (isReversed) std::reverse(segment.centreline.pointsMm.begin(), segment.centreline.pointsMm.end());
        chain.push_back(std::move(segment));
        isUsed[s] = true;
    };
    take(first, isFirstReversed);
    std::vector<double> chainGaps;
    while (chain.size() < segments.size()) {
        const glm::dvec3 tail = chain.back().centreline.pointsMm.back();
        std::size_t next = 0;
        bool isReversed = false;
        double nearest = std::numeric_limits<double>::max();
        for (std::size_t s = 0; s < segments.size(); ++s) {
            if (isUsed[s]) continue;
            const auto& points = segments[s].centreline.pointsMm;
            const double toFront = glm::length(points.front() - tail), toBack = glm::length(points.back() - tail);
            if (std::min(toFront, toBack) < nearest) {
                nearest = std::min(toFront, toBack);
                next = s;
                isReversed = toBack < toFront;
            }
        }
        chainGaps.push_back(nearest);
        take(next, isReversed);
    }
    // Reverse: rectum -> caecum.
    std::reverse(chain.begin(), chain.end());
    for (ColonSegment& segment : chain) {
        std::reverse(segment.centreline.pointsMm.begin(), segment.centreline.pointsMm.end());
    }
    std::reverse(chainGaps.begin(), chainGaps.end());
    segments = std::move(chain);
    gaps = std::move(chainGaps);
}

}  // namespace

ColonAnalysis analyseColon(volumes::Volume& volume, const ColonSettings& settings, const ColonProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    const auto report = [&](const std::string& step, int done) {
        if (progress) progress(step, done, kSteps);
    };
    if (!(settings.minPathLengthMm >= 0.0)) throw ColonError("the shortest path length must be non-negative");
    ColonAnalysis analysis;
    analysis.anteriorMm = volumes::volumeDirectionFromPatient(volume, kAnteriorLps);

    report("segmenting air", 0);
    AirSegmentation air = segmentAir(volume, settings.segmentation);
    requireColon(air, settings.segmentation);
    analysis.airRegions = air.regions;

    report("cleansing tagged fluid", 1);
    std::vector<int16_t> codeOfLabel = classCodes(air);
    if (settings.cleansing != Cleansing::Off) {
        const std::vector<uint8_t> cleansed = cleanseTaggedFluid(volume, air, settings.cleansingSettings, analysis.cleansing);
        analysis.isCleansed = analysis.cleansing.pools > 0;
        // Cleansed voxels join the colon air, to be labelled by component with it below.
        for (std::size_t n = 0; n < cleansed.size(); ++n) {
            if (cleansed[n] != 0) air.labels[n] = kUnlabelled;
        }
    }
    // The air classes become codes; lumen voxels wait for their segment's label.
    for (int32_t& label : air.labels) {
        if (label == kUnlabelled) continue;
        const int16_t code = label > 0 ? codeOfLabel[static_cast<std::size_t>(label)] : int16_t{kLabelNone};
        label = code == kLabelShortColon ? kUnlabelled : -2 - code;  // -2 - code: kept apart from labelling
    }
    const std::vector<Component> lumenParts = labelComponents(air.grid, air.labels);

    report("extracting centrelines", 2);
    const double voxelMl = air.grid.spacingMm.x * air.grid.spacingMm.y * air.grid.spacingMm.z / 1000.0;
    std::vector<ColonSegment> segments;
    std::vector<int32_t> labelOfSegment;
    std::vector<int16_t> codeOfPart(lumenParts.size() + 1, kLabelShortColon);
    for (const Component& part : lumenParts) {
        if (static_cast<double>(part.voxels) * voxelMl < settings.segmentation.minRegionMl) {
            analysis.shortSegmentsMl.push_back(static_cast<double>(part.voxels) * voxelMl);
            continue;
        }
        ColonSegment segment;
        segment.voxels = part.voxels;
        segment.volumeMl = static_cast<double>(part.voxels) * voxelMl;
        segment.centreline = centrelineOf(air.grid, air.labels, part.label, part.box, settings.centreline);
        // A path needs two points a step apart to be flown or read back.
        if (segment.centreline.pointsMm.size() < 2 ||
            segment.centreline.lengthMm < std::max(settings.minPathLengthMm, settings.centreline.stepMm)) {
            analysis.shortSegmentsMl.push_back(segment.volumeMl);
            continue;
        }
        segments.push_back(std::move(segment));
        labelOfSegment.push_back(part.label);
    }
    if (segments.empty()) {
        throw ColonError("no colon segment is long enough for a path (the longest lumen piece is under " +
                         std::to_string(settings.minPathLengthMm) + " mm)");
    }

    report("ordering segments", 3);
    // Remember which part each segment was, by its first centreline point, through the reordering.
    std::vector<std::pair<glm::dvec3, int32_t>> partOfStart;
    for (std::size_t s = 0; s < segments.size(); ++s) {
        partOfStart.push_back({segments[s].centreline.pointsMm.front(), labelOfSegment[s]});
        partOfStart.push_back({segments[s].centreline.pointsMm.back(), labelOfSegment[s]});
    }
    orderAntegrade(volume, segments, analysis.gapsMm);
    for (std::size_t s = 0; s < segments.size(); ++s) {
        for (const auto& [point, label] : partOfStart) {
            if (point == segments[s].centreline.pointsMm.front()) {
                // Beyond the 245th segment every one shares the last code (the report lists them all).
                codeOfPart[static_cast<std::size_t>(label)] =
                    static_cast<int16_t>(std::min<std::size_t>(kLabelFirstSegment + s, kMaxLabelCode));
            }
        }
    }
    analysis.segments = std::move(segments);

    // The label volume: class codes outside the lumen, segment codes inside. Codes go through
    // a byte per voxel so that the 32-bit labels are freed before the 16-bit volume is made
    // (peak memory stays under 4x the scan's).
    std::vector<uint8_t> codes(air.labels.size());
    for (std::size_t n = 0; n < air.labels.size(); ++n) {
        const int32_t label = air.labels[n];
        const int code = label > 0 ? codeOfPart[static_cast<std::size_t>(label)] : -2 - label;
        codes[n] = static_cast<uint8_t>(std::min(code, kMaxLabelCode));
    }
    std::vector<int32_t>().swap(air.labels);
    analysis.labels.dims = volume.dims;
    analysis.labels.spacingMm = volume.spacingMm;
    analysis.labels.originLps = volume.originLps;
    analysis.labels.directionLps = volume.directionLps;
    analysis.labels.hu.assign(codes.begin(), codes.end());
    analysis.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report("done", kSteps);
    return analysis;
}

}  // namespace colon
