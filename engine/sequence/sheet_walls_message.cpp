#include "engine/sequence/sheet_walls_message.h"

#include <limits>
#include <string>

namespace engine {
namespace {

// No frame has more than the walls of a box for two eyes, nor a reduced wall more than this side.
constexpr std::uint32_t kMaxImages = 12;
constexpr std::uint32_t kMaxSide = 16384;

void putWord(std::vector<unsigned char>& out, std::uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<unsigned char>(value >> shift));
}

/// Reads the message front to back and names what is missing or wrong.
class Reader {
public:
    explicit Reader(const std::vector<unsigned char>& message) : mMessage(message) {}
    std::uint32_t word(const char* what) {
        need(4, what);
        std::uint32_t value = 0;
        for (int i = 0; i < 4; ++i) value |= static_cast<std::uint32_t>(mMessage[mAt++]) << (8 * i);
        return value;
    }
    void bytes(std::vector<uint8_t>& out, std::size_t count) {
        need(count, "pixels");
        out.assign(mMessage.begin() + static_cast<std::ptrdiff_t>(mAt),
                   mMessage.begin() + static_cast<std::ptrdiff_t>(mAt + count));
        mAt += count;
    }
    void expectEnd() const {
        if (mAt != mMessage.size()) {
            throw SheetWallsMessageError("sheet walls message: " + std::to_string(mMessage.size() - mAt) +
                                         " bytes after the last image");
        }
    }

private:
    void need(std::size_t count, const char* what) const {
        if (mMessage.size() - mAt < count) {
            throw SheetWallsMessageError(std::string("sheet walls message: ends before its ") + what + " (" +
                                         std::to_string(mMessage.size()) + " bytes)");
        }
    }
    const std::vector<unsigned char>& mMessage;
    std::size_t mAt = 0;
};

}  // namespace

std::vector<unsigned char> packSheetWalls(const SheetWalls& sheetWalls) {
    std::vector<unsigned char> out;
    std::size_t size = 8;
    for (const auto& wall : sheetWalls.walls) size += 8 + wall.rgba.size();
    out.reserve(size);
    putWord(out, static_cast<std::uint32_t>(sheetWalls.frameIndex));
    putWord(out, static_cast<std::uint32_t>(sheetWalls.walls.size()));
    for (const auto& wall : sheetWalls.walls) {
        if (wall.width < 0 || wall.height < 0 ||
            wall.rgba.size() != 4 * static_cast<std::size_t>(wall.width) * static_cast<std::size_t>(wall.height)) {
            throw SheetWallsMessageError("sheet walls message: an image of " + std::to_string(wall.width) + " x " +
                                         std::to_string(wall.height) + " holds " + std::to_string(wall.rgba.size()) +
                                         " bytes");
        }
        putWord(out, static_cast<std::uint32_t>(wall.width));
        putWord(out, static_cast<std::uint32_t>(wall.height));
        out.insert(out.end(), wall.rgba.begin(), wall.rgba.end());
    }
    return out;
}

SheetWalls unpackSheetWalls(const std::vector<unsigned char>& message) {
    Reader reader(message);
    SheetWalls sheetWalls;
    const std::uint32_t index = reader.word("frame index");
    if (index > static_cast<std::uint32_t>(std::numeric_limits<int>::max())) {
        throw SheetWallsMessageError("sheet walls message: frame index " + std::to_string(index));
    }
    sheetWalls.frameIndex = static_cast<int>(index);
    const std::uint32_t count = reader.word("image count");
    if (count > kMaxImages) throw SheetWallsMessageError("sheet walls message: " + std::to_string(count) + " images");
    for (std::uint32_t i = 0; i < count; ++i) {
        RgbaImage wall;
        const std::uint32_t width = reader.word("image width");
        const std::uint32_t height = reader.word("image height");
        if (width > kMaxSide || height > kMaxSide) {
            throw SheetWallsMessageError("sheet walls message: an image of " + std::to_string(width) + " x " +
                                         std::to_string(height));
        }
        wall.width = static_cast<int>(width);
        wall.height = static_cast<int>(height);
        reader.bytes(wall.rgba, 4 * static_cast<std::size_t>(width) * height);
        sheetWalls.walls.push_back(std::move(wall));
    }
    reader.expectEnd();
    return sheetWalls;
}

}  // namespace engine
