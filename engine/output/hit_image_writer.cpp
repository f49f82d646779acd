#include "engine/output/hit_image_writer.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <limits>
#include <vector>

#include "volumes/gzip_compress.h"

namespace engine {
namespace {

void checkHitImage(const std::string& path, int width, int height, std::span<const float> hitMm, bool overwrite) {
    if (width < 1 || height < 1 || hitMm.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
        throw std::invalid_argument(path + ": hit image does not hold " + std::to_string(width) + "x" +
                                    std::to_string(height) + " 4-vectors");
    }
    if (!overwrite && std::filesystem::exists(path)) {
        throw std::runtime_error(path + ": exists already (pass --force to replace it)");
    }
}

/// Writes a NRRD of float vectors: `components` per pixel of a width x height image, the payload
/// as given (raw, or already gzip-compressed for encoding "gzip").
void writeVectorNrrd(const std::string& path, const std::string& comment, int components, int width, int height,
                     const std::string& encoding, std::span<const std::byte> payload) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
    out << "NRRD0004\n# " << comment << "\ntype: float\ndimension: 3\nsizes: " << components << ' ' << width << ' '
        << height << "\nkinds: " << components << "-vector domain domain\nendian: little\nencoding: " << encoding
        << "\n\n";
    out.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
    if (!out) throw std::runtime_error(path + ": write failed (disk full?)");
}

}  // namespace

void writeHitPositionsNrrd(const std::string& path, int width, int height, std::span<const float> hitMm,
                           bool overwrite) {
    static_assert(std::endian::native == std::endian::little, "the writer assumes a little-endian host");
    checkHitImage(path, width, height, hitMm, overwrite);
    const std::size_t pixels = hitMm.size() / 4;
    std::vector<float> xyz(pixels * 3);
    const float miss = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t i = 0; i < pixels; ++i) {
        const bool isHit = hitMm[4 * i + 3] > 0.0f;
        for (std::size_t c = 0; c < 3; ++c) xyz[3 * i + c] = isHit ? hitMm[4 * i + c] : miss;
    }
    // zlib level 1: the positions of neighbouring pixels differ in every bit, so harder levels gain little.
    const std::vector<unsigned char> payload = volumes::gzipCompressed(std::as_bytes(std::span(xyz)), 1);
    writeVectorNrrd(path, "first-hit positions in volume millimetres (x, y, z); NaN where the ray missed", 3, width,
                    height, "gzip", std::as_bytes(std::span(payload)));
}

void writeHitImageNrrd(const std::string& path, int width, int height, std::span<const float> hitMm, bool overwrite) {
    static_assert(std::endian::native == std::endian::little, "the writer assumes a little-endian host");
    checkHitImage(path, width, height, hitMm, overwrite);
    writeVectorNrrd(path, "first-hit positions in volume millimetres (x, y, z) and a hit flag (1 hit, 0 miss)", 4, width,
                    height, "raw", std::as_bytes(hitMm));
}

}  // namespace engine
