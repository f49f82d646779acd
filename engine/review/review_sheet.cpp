#include "engine/review/review_sheet.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace engine {
namespace {

constexpr uint8_t kEmpty[3] = {24, 24, 28};  // where no wall is: dark, but not the background black

void blit(RgbaImage& target, const RgbaImage& source, int x0, int y0) {
    for (int y = 0; y < source.height; ++y) {
        const int ty = y0 + y;
        if (ty < 0 || ty >= target.height) continue;
        for (int x = 0; x < source.width; ++x) {
            const int tx = x0 + x;
            if (tx < 0 || tx >= target.width) continue;
            const std::size_t s = 4 * (static_cast<std::size_t>(y) * source.width + x);
            const std::size_t t = 4 * (static_cast<std::size_t>(ty) * target.width + tx);
            std::copy_n(source.rgba.begin() + static_cast<std::ptrdiff_t>(s), 4,
                        target.rgba.begin() + static_cast<std::ptrdiff_t>(t));
        }
    }
}

const DisplayWall* findWall(const Display& display, WallName name) {
    for (const DisplayWall& wall : display.walls) {
        if (wall.name == name) return &wall;
    }
    return nullptr;
}

}  // namespace

RgbaImage filledImage(int width, int height, uint8_t r, uint8_t g, uint8_t b) {
    RgbaImage image{width, height, std::vector<uint8_t>(static_cast<std::size_t>(width) * height * 4)};
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
        image.rgba[i] = r;
        image.rgba[i + 1] = g;
        image.rgba[i + 2] = b;
        image.rgba[i + 3] = 255;
    }
    return image;
}

RgbaImage downsampled(const RgbaImage& image, int factor) {
    if (factor < 1) throw std::invalid_argument("downsampling factor must be at least 1");
    if (factor == 1) return image;
    RgbaImage out;
    out.width = (image.width + factor - 1) / factor;
    out.height = (image.height + factor - 1) / factor;
    out.rgba.resize(static_cast<std::size_t>(out.width) * out.height * 4);
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            unsigned sum[4] = {0, 0, 0, 0};
            unsigned count = 0;
            for (int sy = y * factor; sy < std::min((y + 1) * factor, image.height); ++sy) {
                for (int sx = x * factor; sx < std::min((x + 1) * factor, image.width); ++sx) {
                    const std::size_t i = 4 * (static_cast<std::size_t>(sy) * image.width + sx);
                    for (int c = 0; c < 4; ++c) sum[c] += image.rgba[i + static_cast<std::size_t>(c)];
                    ++count;
                }
            }
            const std::size_t o = 4 * (static_cast<std::size_t>(y) * out.width + x);
            for (int c = 0; c < 4; ++c) out.rgba[o + static_cast<std::size_t>(c)] = static_cast<uint8_t>((sum[c] + count / 2) / count);
        }
    }
    return out;
}

RgbaImage anaglyphOf(const RgbaImage& left, const RgbaImage& right) {
    if (left.width != right.width || left.height != right.height) {
        throw std::invalid_argument("anaglyph: the eyes' images differ in size");
    }
    RgbaImage out = right;
    for (std::size_t i = 0; i < out.rgba.size(); i += 4) {
        const double luma = 0.299 * left.rgba[i] + 0.587 * left.rgba[i + 1] + 0.114 * left.rgba[i + 2];
        out.rgba[i] = static_cast<uint8_t>(std::lround(std::min(luma, 255.0)));
    }
    return out;
}

CrossGeometry crossGeometry(const Display& display) {
    // Cell sizes: each wall at its own pixel size; missing walls take their neighbours' sizes
    // so the cross keeps its shape.
    const auto sizeOf = [&](WallName name, int fallbackWidth, int fallbackHeight) {
        if (const DisplayWall* wall = findWall(display, name)) return std::pair{wall->width, wall->height};
        return std::pair{fallbackWidth, fallbackHeight};
    };
    const auto [frontW, frontH] = sizeOf(WallName::Front, 512, 512);
    const auto [leftW, leftH] = sizeOf(WallName::Left, frontW, frontH);
    const auto [rightW, rightH] = sizeOf(WallName::Right, leftW, leftH);
    const auto [backW, backH] = sizeOf(WallName::Back, frontW, frontH);
    const auto [floorW, floorH] = sizeOf(WallName::Floor, frontW, frontW);
    const auto [ceilingW, ceilingH] = sizeOf(WallName::Ceiling, floorW, floorH);
    const int rowHeight = std::max({frontH, leftH, rightH, backH});
    CrossGeometry geometry;
    geometry.width = leftW + frontW + rightW + backW;
    geometry.height = ceilingH + rowHeight + floorH;
    geometry.cells[WallName::Ceiling] = {leftW + (frontW - ceilingW) / 2, 0, ceilingW, ceilingH};
    geometry.cells[WallName::Left] = {0, ceilingH, leftW, leftH};
    geometry.cells[WallName::Front] = {leftW, ceilingH, frontW, frontH};
    geometry.cells[WallName::Right] = {leftW + frontW, ceilingH, rightW, rightH};
    geometry.cells[WallName::Back] = {leftW + frontW + rightW, ceilingH, backW, backH};
    geometry.cells[WallName::Floor] = {leftW + (frontW - floorW) / 2, ceilingH + rowHeight, floorW, floorH};
    return geometry;
}

RgbaImage crossLayout(const Display& display, const std::map<WallName, RgbaImage>& walls) {
    const CrossGeometry geometry = crossGeometry(display);
    RgbaImage cross = filledImage(geometry.width, geometry.height, 0, 0, 0);
    for (WallName name : {WallName::Ceiling, WallName::Left, WallName::Front, WallName::Right, WallName::Back,
                          WallName::Floor}) {
        const CrossCell& cell = geometry.cells.at(name);
        const auto found = walls.find(name);
        if (found != walls.end()) {
            blit(cross, found->second, cell.x, cell.y);
        } else {
            blit(cross, filledImage(cell.width, cell.height, kEmpty[0], kEmpty[1], kEmpty[2]), cell.x, cell.y);
        }
    }
    return cross;
}

RgbaImage sideBySide(const std::vector<RgbaImage>& images, int gap) {
    int width = 0, height = 0;
    for (const RgbaImage& image : images) {
        width += image.width;
        height = std::max(height, image.height);
    }
    width += gap * std::max<int>(0, static_cast<int>(images.size()) - 1);
    RgbaImage out = filledImage(std::max(width, 1), std::max(height, 1), 0, 0, 0);
    int x = 0;
    for (const RgbaImage& image : images) {
        blit(out, image, x, 0);
        x += image.width + gap;
    }
    return out;
}

}  // namespace engine
