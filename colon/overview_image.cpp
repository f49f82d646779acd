#include "colon/overview_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "volumes/parallel_for.h"

namespace colon {
namespace {

/// One panel: the patient axis it projects along and the patient axes of its image's columns
/// and rows, with the sign that makes the rows run down the picture.
struct PanelAxes {
    int depth, column, row;
    double rowSign;  // +1: rows increase with the axis; -1: against it
};

// LPS axes: 0 = L (patient's left), 1 = P (posterior), 2 = S (superior).
constexpr std::array<PanelAxes, 3> kPanels{{
    {2, 0, 1, +1.0},  // axial: right -> left across, anterior (low P) at the top
    {1, 0, 2, -1.0},  // coronal: right -> left across, superior at the top
    {0, 1, 2, -1.0},  // sagittal: anterior -> posterior across, superior at the top
}};

constexpr std::array<std::array<uint8_t, 3>, 6> kSegmentColours{
    {{80, 160, 255}, {255, 120, 80}, {120, 220, 120}, {220, 120, 255}, {255, 200, 80}, {80, 220, 220}}};

struct Frame {
    glm::dvec3 lowLps, highLps;
    double pixelMm;
    double depthStepMm;  // along the projection: a pixel, or the finest voxel where that is coarser
};

Frame frameOf(const volumes::Volume& ct, int maxPanelPixels) {
    Frame frame{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(-std::numeric_limits<double>::max()), 1.0,
                1.0};
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 index((corner & 1) ? ct.dims[0] - 1 : 0, (corner & 2) ? ct.dims[1] - 1 : 0,
                               (corner & 4) ? ct.dims[2] - 1 : 0);
        const glm::dvec3 lps = volumes::patientFromVolumeMm(ct, index * ct.spacingMm);
        frame.lowLps = glm::min(frame.lowLps, lps);
        frame.highLps = glm::max(frame.highLps, lps);
    }
    const glm::dvec3 extent = frame.highLps - frame.lowLps;
    frame.pixelMm = std::max({extent.x, extent.y, extent.z, 1.0}) / maxPanelPixels;
    frame.depthStepMm = std::max(frame.pixelMm, std::min({ct.spacingMm.x, ct.spacingMm.y, ct.spacingMm.z}));
    return frame;
}

void blend(uint8_t* pixel, const std::array<uint8_t, 3>& colour, double alpha) {
    for (int c = 0; c < 3; ++c) {
        pixel[c] = static_cast<uint8_t>(std::lround((1.0 - alpha) * pixel[c] + alpha * colour[static_cast<std::size_t>(c)]));
    }
}

}  // namespace

RgbaImage overviewImage(const volumes::Volume& ct, const ColonAnalysis& analysis, int maxPanelPixels) {
    const Frame frame = frameOf(ct, std::max(16, maxPanelPixels));
    const glm::dvec3 extent = frame.highLps - frame.lowLps;
    const glm::dmat3 toVolume = glm::transpose(ct.directionLps);
    const int gap = 8;
    std::array<int, 3> widths{}, heights{};
    for (std::size_t p = 0; p < 3; ++p) {
        widths[p] = static_cast<int>(std::ceil(extent[kPanels[p].column] / frame.pixelMm)) + 1;
        heights[p] = static_cast<int>(std::ceil(extent[kPanels[p].row] / frame.pixelMm)) + 1;
    }
    RgbaImage image;
    image.width = widths[0] + widths[1] + widths[2] + 4 * gap;
    image.height = *std::max_element(heights.begin(), heights.end()) + 2 * gap;
    image.rgba.assign(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4, 0);
    for (std::size_t n = 3; n < image.rgba.size(); n += 4) image.rgba[n] = 255;

    const auto pointToPixel = [&](std::size_t p, const glm::dvec3& lps, int left) {
        const PanelAxes axes = kPanels[p];
        const double u = (lps[axes.column] - frame.lowLps[axes.column]) / frame.pixelMm;
        const double v = axes.rowSign > 0 ? (lps[axes.row] - frame.lowLps[axes.row]) / frame.pixelMm
                                          : (frame.highLps[axes.row] - lps[axes.row]) / frame.pixelMm;
        return glm::dvec2(left + u, gap + v);
    };

    int left = gap;
    for (std::size_t p = 0; p < 3; ++p) {
        const PanelAxes axes = kPanels[p];
        const int width = widths[p], height = heights[p];
        const int depthSamples = static_cast<int>(std::ceil(extent[axes.depth] / frame.depthStepMm)) + 1;
        std::vector<float> meanHu(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0f);
        std::vector<int16_t> lumenCode(meanHu.size(), 0);
        volumes::parallelFor(height, [&](int row) {
            for (int column = 0; column < width; ++column) {
                double sum = 0.0;
                int samples = 0;
                int16_t code = 0;
                for (int d = 0; d < depthSamples; ++d) {
                    glm::dvec3 lps;
                    lps[axes.depth] = frame.lowLps[axes.depth] + d * frame.depthStepMm;
                    lps[axes.column] = frame.lowLps[axes.column] + column * frame.pixelMm;
                    lps[axes.row] = axes.rowSign > 0 ? frame.lowLps[axes.row] + row * frame.pixelMm
                                                     : frame.highLps[axes.row] - row * frame.pixelMm;
                    const glm::dvec3 index = (toVolume * (lps - ct.originLps)) / ct.spacingMm;
                    const int i = static_cast<int>(std::lround(index.x)), j = static_cast<int>(std::lround(index.y)),
                              k = static_cast<int>(std::lround(index.z));
                    if (i < 0 || j < 0 || k < 0 || i >= ct.dims[0] || j >= ct.dims[1] || k >= ct.dims[2]) continue;
                    const std::size_t n = ct.linearIndex(i, j, k);
                    sum += std::clamp<double>(ct.hu[n], -1000.0, 1000.0);
                    ++samples;
                    const int16_t label = analysis.labels.hu.empty() ? int16_t{0} : analysis.labels.hu[n];
                    if (label >= kLabelFirstSegment && (code == 0 || label < code)) code = label;
                }
                const std::size_t at = static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                                       static_cast<std::size_t>(column);
                meanHu[at] = samples > 0 ? static_cast<float>(sum / samples) : -1000.0f;
                lumenCode[at] = code;
            }
        });
        // Window: the 2nd to 99.8th percentile of the panel's mean HU inside the body (above
        // -900 HU on average), so any body size fills the grey range; a gamma darkens the soft
        // tissue that fills most of it, so the lumen and the bones stand out.
        std::vector<float> sorted;
        for (float value : meanHu) {
            if (value > -900.0f) sorted.push_back(value);
        }
        if (sorted.empty()) sorted = meanHu;
        std::sort(sorted.begin(), sorted.end());
        const float low = sorted[sorted.size() * 2 / 100], high = sorted[sorted.size() * 998 / 1000];
        for (int row = 0; row < height; ++row)
            for (int column = 0; column < width; ++column) {
                const std::size_t at = static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                                       static_cast<std::size_t>(column);
                const double grey =
                    std::pow(std::clamp((meanHu[at] - low) / std::max(high - low, 1.0f), 0.0f, 1.0f), 1.8);
                uint8_t* pixel = &image.rgba[(static_cast<std::size_t>(gap + row) * static_cast<std::size_t>(image.width) +
                                              static_cast<std::size_t>(left + column)) * 4];
                pixel[0] = pixel[1] = pixel[2] = static_cast<uint8_t>(std::lround(255.0 * grey));
                if (lumenCode[at] >= kLabelFirstSegment) {
                    const auto s = static_cast<std::size_t>(lumenCode[at] - kLabelFirstSegment) % kSegmentColours.size();
                    blend(pixel, kSegmentColours[s], 0.45);
                }
            }
        // The centreline, then its ends.
        const auto plot = [&](const glm::dvec2& at, const std::array<uint8_t, 3>& colour, int radius) {
            for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx) {
                    if (dx * dx + dy * dy > radius * radius) continue;
                    const int x = static_cast<int>(std::lround(at.x)) + dx, y = static_cast<int>(std::lround(at.y)) + dy;
                    if (x < left || y < gap || x >= left + width || y >= gap + height) continue;
                    uint8_t* pixel = &image.rgba[(static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                                                  static_cast<std::size_t>(x)) * 4];
                    blend(pixel, colour, 1.0);
                }
        };
        for (const ColonSegment& segment : analysis.segments) {
            const auto& points = segment.centreline.pointsMm;
            for (std::size_t i = 0; i + 1 < points.size(); ++i) {
                const glm::dvec2 a = pointToPixel(p, volumes::patientFromVolumeMm(ct, points[i]), left);
                const glm::dvec2 b = pointToPixel(p, volumes::patientFromVolumeMm(ct, points[i + 1]), left);
                const int steps = std::max(1, static_cast<int>(std::ceil(glm::length(b - a) * 2.0)));
                for (int s = 0; s <= steps; ++s) plot(glm::mix(a, b, double(s) / steps), {255, 230, 0}, 1);
            }
        }
        if (!analysis.segments.empty()) {
            plot(pointToPixel(p, volumes::patientFromVolumeMm(ct, analysis.segments.front().centreline.pointsMm.front()), left),
                 {0, 220, 0}, 4);
            plot(pointToPixel(p, volumes::patientFromVolumeMm(ct, analysis.segments.back().centreline.pointsMm.back()), left),
                 {230, 0, 0}, 4);
        }
        left += width + gap;
    }
    return image;
}

}  // namespace colon
