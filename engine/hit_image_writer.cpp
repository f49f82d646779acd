#include "engine/hit_image_writer.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace engine {

void writeHitImageNrrd(const std::string& path, int width, int height, std::span<const float> hitMm, bool overwrite) {
    static_assert(std::endian::native == std::endian::little, "the writer assumes a little-endian host");
    if (width < 1 || height < 1 || hitMm.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
        throw std::invalid_argument(path + ": hit image does not hold " + std::to_string(width) + "x" +
                                    std::to_string(height) + " 4-vectors");
    }
    if (!overwrite && std::filesystem::exists(path)) {
        throw std::runtime_error(path + ": exists already (pass --force to replace it)");
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
    out << "NRRD0004\n"
        << "# first-hit positions in volume millimetres (x, y, z) and a hit flag (1 hit, 0 miss)\n"
        << "type: float\ndimension: 3\nsizes: 4 " << width << ' ' << height << '\n'
        << "kinds: 4-vector domain domain\nendian: little\nencoding: raw\n\n";
    out.write(reinterpret_cast<const char*>(hitMm.data()), static_cast<std::streamsize>(hitMm.size_bytes()));
    if (!out) throw std::runtime_error(path + ": write failed (disk full?)");
}

}  // namespace engine
