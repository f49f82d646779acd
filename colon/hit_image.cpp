#include "colon/hit_image.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <zlib.h>

#include "colon/colon_error.h"

namespace colon {
namespace {

std::string trimmed(const std::string& text) {
    std::size_t begin = 0, end = text.size();
    while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
    while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
    return text.substr(begin, end - begin);
}

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
    throw ColonError(path + ": not a hit image (" + why + ")");
}

/// Inflates a gzip (or zlib) stream into exactly `expected` bytes; growing the output as data
/// arrives, so a header that claims a huge image over a short payload fails before allocating it.
std::vector<unsigned char> inflated(const std::string& path, const unsigned char* data, std::size_t size,
                                    std::size_t expected) {
    z_stream stream{};
    if (inflateInit2(&stream, 15 + 32) != Z_OK) throw ColonError(path + ": cannot start the gzip decompressor");
    std::vector<unsigned char> out;
    out.reserve(std::min<std::size_t>(expected, std::size_t{1} << 24));
    std::vector<unsigned char> chunk(std::size_t{1} << 20);
    stream.next_in = const_cast<unsigned char*>(data);
    stream.avail_in = static_cast<uInt>(std::min<std::size_t>(size, 0x7fffffff));
    int result = Z_OK;
    while (result != Z_STREAM_END) {
        stream.next_out = chunk.data();
        stream.avail_out = static_cast<uInt>(chunk.size());
        result = inflate(&stream, Z_NO_FLUSH);
        if (result != Z_OK && result != Z_STREAM_END) {
            inflateEnd(&stream);
            if (result == Z_BUF_ERROR) refuse(path, "the gzip data ends early: truncated");
            refuse(path, std::string("corrupt gzip data: ") + (stream.msg ? stream.msg : "inflate failed"));
        }
        const std::size_t produced = chunk.size() - stream.avail_out;
        if (out.size() + produced > expected) {
            inflateEnd(&stream);
            refuse(path, "the gzip data holds more than the " + std::to_string(expected) + " bytes its sizes say");
        }
        out.insert(out.end(), chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(produced));
        if (result != Z_STREAM_END && produced == 0 && stream.avail_in == 0) {
            inflateEnd(&stream);
            refuse(path, "the gzip data ends early: truncated");
        }
    }
    inflateEnd(&stream);
    if (out.size() != expected) {
        refuse(path, "the data holds " + std::to_string(out.size()) + " bytes, its sizes say " +
                         std::to_string(expected) + ": truncated");
    }
    return out;
}

int side(const std::string& path, const std::string& word, const char* name) {
    long long value = 0;
    try {
        std::size_t used = 0;
        value = std::stoll(word, &used);
        if (used != word.size()) throw std::invalid_argument(word);
    } catch (const std::exception&) {
        refuse(path, std::string("the ") + name + " \"" + word + "\" is not a whole number");
    }
    if (value < 1 || value > kMaxHitImageSide) {
        refuse(path, std::string("the ") + name + " " + word + " is outside 1.." + std::to_string(kMaxHitImageSide));
    }
    return static_cast<int>(value);
}

}  // namespace

HitImage readHitImage(const std::string& path) {
    static_assert(std::endian::native == std::endian::little, "the reader assumes a little-endian host");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ColonError(path + ": cannot be read");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.compare(0, 7, "NRRD000") != 0) refuse(path, "no NRRD magic \"NRRD000x\" at its start");

    // The header: lines up to the first empty one; "key: value" fields, "#" comments.
    std::map<std::string, std::string> fields;
    std::size_t position = bytes.find('\n');
    if (position == std::string::npos) refuse(path, "the header ends early");
    ++position;
    bool ended = false;
    while (position < bytes.size()) {
        std::size_t end = bytes.find('\n', position);
        if (end == std::string::npos) break;
        std::string line = bytes.substr(position, end - position);
        position = end + 1;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) {
            ended = true;
            break;
        }
        if (line[0] == '#') continue;
        const std::size_t colon = line.find(':');
        if (colon == std::string::npos) refuse(path, "header line \"" + line + "\" is not \"field: value\"");
        if (colon + 1 < line.size() && line[colon + 1] == '=') continue;  // key:=value pairs
        fields[lower(trimmed(line.substr(0, colon)))] = trimmed(line.substr(colon + 1));
    }
    if (!ended) refuse(path, "the header has no empty line before the data: truncated");

    auto field = [&](const std::string& key) -> std::string {
        const auto found = fields.find(key);
        if (found == fields.end()) refuse(path, "no \"" + key + ":\" field");
        return found->second;
    };
    if (fields.count("data file") != 0 || fields.count("datafile") != 0) {
        refuse(path, "its data lie in a separate file; only attached data are read");
    }
    const std::string type = lower(field("type"));
    if (type != "float" && type != "float32") refuse(path, "type \"" + type + "\", expected float");
    if (trimmed(field("dimension")) != "3") refuse(path, "dimension " + field("dimension") + ", expected 3");
    std::istringstream sizes(field("sizes"));
    std::vector<std::string> words{std::istream_iterator<std::string>(sizes), std::istream_iterator<std::string>()};
    if (words.size() != 3) refuse(path, "sizes \"" + field("sizes") + "\", expected \"3 W H\" or \"4 W H\"");
    if (words[0] != "3" && words[0] != "4") {
        refuse(path, "sizes \"" + field("sizes") + "\": " + words[0] + " components, expected 3 or 4");
    }
    const int components = words[0] == "3" ? 3 : 4;
    HitImage image;
    image.width = side(path, words[1], "width");
    image.height = side(path, words[2], "height");
    if (fields.count("endian") != 0 && lower(fields["endian"]) != "little") {
        refuse(path, "endian " + fields["endian"] + ", expected little");
    }
    const std::string encoding = lower(field("encoding"));
    const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
    const std::size_t expected = pixels * static_cast<std::size_t>(components) * sizeof(float);
    const auto* payload = reinterpret_cast<const unsigned char*>(bytes.data()) + position;
    const std::size_t payloadSize = bytes.size() - position;
    std::vector<unsigned char> data;
    if (encoding == "raw") {
        if (payloadSize != expected) {
            refuse(path, "the data holds " + std::to_string(payloadSize) + " bytes, its sizes say " +
                             std::to_string(expected) + (payloadSize < expected ? ": truncated" : ""));
        }
        data.assign(payload, payload + payloadSize);
    } else if (encoding == "gzip" || encoding == "gz") {
        data = inflated(path, payload, payloadSize, expected);
    } else {
        refuse(path, "encoding \"" + encoding + "\", expected raw or gzip");
    }

    image.hitMm.assign(pixels, glm::dvec3(0.0));
    image.isHit.assign(pixels, 0);
    std::vector<float> values(static_cast<std::size_t>(components));
    for (std::size_t i = 0; i < pixels; ++i) {
        std::memcpy(values.data(), data.data() + i * values.size() * sizeof(float), values.size() * sizeof(float));
        const glm::dvec3 p(values[0], values[1], values[2]);
        const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        bool isHit = false;
        if (components == 4) {
            if (!std::isfinite(values[3])) {
                refuse(path, "pixel (" + std::to_string(i % static_cast<std::size_t>(image.width)) + ", " +
                                 std::to_string(i / static_cast<std::size_t>(image.width)) + ") has a non-finite hit flag");
            }
            isHit = values[3] > 0.0f;
        } else {
            isHit = !(std::isnan(p.x) && std::isnan(p.y) && std::isnan(p.z));
        }
        if (isHit && !finite) {
            refuse(path, "pixel (" + std::to_string(i % static_cast<std::size_t>(image.width)) + ", " +
                             std::to_string(i / static_cast<std::size_t>(image.width)) +
                             ") is a hit with a non-finite position");
        }
        if (isHit) {
            image.hitMm[i] = p;
            image.isHit[i] = 1;
        }
    }
    return image;
}

}  // namespace colon
