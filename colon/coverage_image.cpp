#include "colon/coverage_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace colon {
namespace {

using Colour = std::array<double, 3>;

constexpr Colour kSeen{232.0, 196.0, 178.0};
constexpr Colour kUnseen{225.0, 30.0, 30.0};
constexpr Colour kUnseenBehind{120.0, 20.0, 20.0};
constexpr std::array<uint8_t, 3> kRing{255, 220, 0};
constexpr std::array<uint8_t, 3> kBackground{24, 24, 28};

/// An orthographic view: image columns along `right`, rows down along -`up`, depth along `toward`
/// the viewer (larger is nearer).
struct ViewAxes {
    glm::dvec3 right, up, toward;
};

struct Panel {
    int width = 0, height = 0;
    glm::dvec2 low{0.0};
    double pixelMm = 1.0;
    std::vector<double> depth;
    std::vector<Colour> colour;
    std::vector<uint8_t> isDrawn;
};

glm::dvec2 project(const ViewAxes& axes, const glm::dvec3& p) { return {glm::dot(p, axes.right), -glm::dot(p, axes.up)}; }

/// Fills the triangle a, b, c (image pixels, with depths) where `accept(pixel, depth)` says so.
template <typename Accept>
void fillTriangle(Panel& panel, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, Accept&& accept) {
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(panel.width - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(panel.height - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
    const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (std::abs(area) < 1e-12) return;
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const double px = x + 0.5, py = y + 0.5;
            const double wa = ((b.x - px) * (c.y - py) - (c.x - px) * (b.y - py)) / area;
            const double wb = ((c.x - px) * (a.y - py) - (a.x - px) * (c.y - py)) / area;
            const double wc = 1.0 - wa - wb;
            if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
            accept(static_cast<std::size_t>(y) * static_cast<std::size_t>(panel.width) + static_cast<std::size_t>(x),
                   wa * a.z + wb * b.z + wc * c.z);
        }
    }
}

Panel drawPanel(const SurfaceCoverage& coverage, const ViewAxes& axes, const std::vector<UnseenPatch>& ringed,
                int panelPixels) {
    const WallSurface& s = coverage.surface();
    glm::dvec2 low(std::numeric_limits<double>::max()), high(std::numeric_limits<double>::lowest());
    for (const auto& v : s.vertices) {
        low = glm::min(low, project(axes, v));
        high = glm::max(high, project(axes, v));
    }
    Panel panel;
    const double marginMm = 0.04 * std::max(high.x - low.x, high.y - low.y) + 1.0;
    low -= marginMm;
    high += marginMm;
    panel.pixelMm = std::max(high.x - low.x, high.y - low.y) / panelPixels;
    panel.low = low;
    panel.width = std::max(1, static_cast<int>(std::ceil((high.x - low.x) / panel.pixelMm)));
    panel.height = std::max(1, static_cast<int>(std::ceil((high.y - low.y) / panel.pixelMm)));
    const std::size_t count = static_cast<std::size_t>(panel.width) * static_cast<std::size_t>(panel.height);
    panel.depth.assign(count, std::numeric_limits<double>::lowest());
    panel.colour.assign(count, Colour{kBackground[0] * 1.0, kBackground[1] * 1.0, kBackground[2] * 1.0});
    panel.isDrawn.assign(count, 0);
    const auto toPixel = [&](const glm::dvec3& p) {
        const glm::dvec2 q = (project(axes, p) - panel.low) / panel.pixelMm;
        return glm::dvec3(q, glm::dot(p, axes.toward));
    };
    const auto shade = [&](const Colour& base, const glm::dvec3& normal) {
        // A headlight from the viewer, lighting both sides: the wall is seen from outside.
        const double light = 0.35 + 0.65 * std::abs(glm::dot(normal, axes.toward));
        return Colour{base[0] * light, base[1] * light, base[2] * light};
    };
    // Pass 1: the nearest wall, lit, as a solid.
    for (std::size_t e = 0; e < s.size(); ++e) {
        const auto& q = s.quads[e];
        const Colour colour = shade(coverage.seen()[e] != 0 ? kSeen : kUnseen, s.normal[e]);
        const auto accept = [&](std::size_t pixel, double depth) {
            if (depth <= panel.depth[pixel]) return;
            panel.depth[pixel] = depth;
            panel.colour[pixel] = colour;
            panel.isDrawn[pixel] = 1;
        };
        const glm::dvec3 a = toPixel(s.vertices[q[0]]), b = toPixel(s.vertices[q[1]]), c = toPixel(s.vertices[q[2]]),
                         d = toPixel(s.vertices[q[3]]);
        fillTriangle(panel, a, b, c, accept);
        fillTriangle(panel, a, c, d, accept);
    }
    // Pass 2: unseen wall behind the nearest wall, so no patch hides behind the colon's front.
    const double behindMm = 2.0;
    for (std::size_t e = 0; e < s.size(); ++e) {
        if (coverage.seen()[e] != 0) continue;
        const auto& q = s.quads[e];
        const auto accept = [&](std::size_t pixel, double depth) {
            if (depth < panel.depth[pixel] - behindMm) panel.colour[pixel] = kUnseenBehind;
        };
        const glm::dvec3 a = toPixel(s.vertices[q[0]]), b = toPixel(s.vertices[q[1]]), c = toPixel(s.vertices[q[2]]),
                         d = toPixel(s.vertices[q[3]]);
        fillTriangle(panel, a, b, c, accept);
        fillTriangle(panel, a, c, d, accept);
    }
    // Rings around the largest patches, sized to their area (at least 6 pixels across).
    for (const UnseenPatch& patch : ringed) {
        const glm::dvec3 centre = toPixel(patch.centreMm);
        const double radius = std::max(6.0, 1.6 * std::sqrt(patch.areaMm2 / 3.14159265358979) / panel.pixelMm);
        for (int step = 0; step < 720; ++step) {
            const double t = step * 3.14159265358979 / 360.0;
            for (double thickness : {0.0, 1.0}) {
                const int x = static_cast<int>(std::lround(centre.x + (radius + thickness) * std::cos(t)));
                const int y = static_cast<int>(std::lround(centre.y + (radius + thickness) * std::sin(t)));
                if (x < 0 || y < 0 || x >= panel.width || y >= panel.height) continue;
                const std::size_t pixel = static_cast<std::size_t>(y) * static_cast<std::size_t>(panel.width) + static_cast<std::size_t>(x);
                panel.colour[pixel] = {1.0 * kRing[0], 1.0 * kRing[1], 1.0 * kRing[2]};
            }
        }
    }
    return panel;
}

}  // namespace

RgbaImage coverageImage(const volumes::Volume& volume, const SurfaceCoverage& coverage,
                        const std::vector<UnseenPatch>& ringed, int panelPixels) {
    const glm::dvec3 left = volumes::volumeDirectionFromPatient(volume, {1.0, 0.0, 0.0});
    const glm::dvec3 anterior = volumes::volumeDirectionFromPatient(volume, {0.0, -1.0, 0.0});
    const glm::dvec3 superior = volumes::volumeDirectionFromPatient(volume, {0.0, 0.0, 1.0});
    // Facing the patient, their left is on the viewer's right; seen from the patient's left
    // side, their front is on the viewer's left.
    const Panel front = drawPanel(coverage, {left, superior, anterior}, ringed, panelPixels);
    const Panel side = drawPanel(coverage, {-anterior, superior, left}, ringed, panelPixels);
    const int gap = 6;
    RgbaImage image;
    image.width = front.width + gap + side.width;
    image.height = std::max(front.height, side.height);
    image.rgba.assign(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4, 0);
    for (std::size_t p = 0; p < image.rgba.size() / 4; ++p) {
        std::copy(kBackground.begin(), kBackground.end(), image.rgba.begin() + static_cast<std::ptrdiff_t>(4 * p));
        image.rgba[4 * p + 3] = 255;
    }
    const auto paste = [&](const Panel& panel, int offsetX) {
        for (int y = 0; y < panel.height; ++y) {
            for (int x = 0; x < panel.width; ++x) {
                const Colour& c = panel.colour[static_cast<std::size_t>(y) * static_cast<std::size_t>(panel.width) + static_cast<std::size_t>(x)];
                uint8_t* out = image.rgba.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                                                        static_cast<std::size_t>(x + offsetX));
                for (int ch = 0; ch < 3; ++ch) out[ch] = static_cast<uint8_t>(std::clamp(std::lround(c[static_cast<std::size_t>(ch)]), 0L, 255L));
            }
        }
    };
    paste(front, 0);
    paste(side, front.width + gap);
    return image;
}

}  // namespace colon
