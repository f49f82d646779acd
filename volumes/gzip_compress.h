/// @brief Compressing bytes as one gzip member (zlib's deflate with a gzip wrapper), the
/// `encoding: gzip` of the NRRD files the project writes.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace volumes {

/// `bytes` as one gzip member at zlib level `level` (1 fastest .. 9 smallest). Any size: the
/// input goes to zlib in pieces its 32-bit counters can hold. Throws std::runtime_error when
/// zlib fails.
std::vector<unsigned char> gzipCompressed(std::span<const std::byte> bytes, int level);

}  // namespace volumes
