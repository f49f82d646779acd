#include "volumes/gzip_compress.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <zlib.h>

namespace volumes {

std::vector<unsigned char> gzipCompressed(std::span<const std::byte> bytes, int level) {
    z_stream stream{};
    if (deflateInit2(&stream, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
        throw std::runtime_error("cannot start the gzip compressor");
    }
    // zlib counts in uInt (32 bits): larger inputs go in pieces, output grows as it fills.
    constexpr std::size_t kPiece = std::size_t{1} << 30;
    std::vector<unsigned char> out;
    std::size_t consumed = 0;
    int result = Z_OK;
    while (result != Z_STREAM_END) {
        if (stream.avail_in == 0 && consumed < bytes.size()) {
            const std::size_t piece = std::min(kPiece, bytes.size() - consumed);
            stream.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(bytes.data() + consumed));
            stream.avail_in = static_cast<uInt>(piece);
            consumed += piece;
        }
        const std::size_t used = out.size();
        const std::size_t room = std::max<std::size_t>(1 << 16, std::min(kPiece, bytes.size() / 4));
        out.resize(used + room);
        stream.next_out = out.data() + used;
        stream.avail_out = static_cast<uInt>(room);
        result = deflate(&stream, consumed == bytes.size() ? Z_FINISH : Z_NO_FLUSH);
        out.resize(used + room - stream.avail_out);
        if (result != Z_OK && result != Z_STREAM_END && result != Z_BUF_ERROR) {
            deflateEnd(&stream);
            throw std::runtime_error("gzip compression failed");
        }
    }
    deflateEnd(&stream);
    return out;
}

}  // namespace volumes
