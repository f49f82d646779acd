/// @brief For targets that decode their input into a struct of header values: fixed-size values
/// read off the front of the bytes, zeros once they run out.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

namespace fuzz {

class InputReader {
public:
    InputReader(const uint8_t* data, std::size_t size) : mData(data), mSize(size) {}

    template <typename T>
    T next() {
        T value{};
        const std::size_t n = std::min(sizeof(T), mSize);
        if (n == 0) return value;  // an empty input has no data pointer to copy from
        std::memcpy(&value, mData, n);
        mData += n;
        mSize -= n;
        return value;
    }

    glm::dvec3 vec3() {
        const double x = next<double>();
        const double y = next<double>();
        return {x, y, next<double>()};
    }

    /// The bytes not read yet (e.g. voxel data after a header).
    [[nodiscard]] const uint8_t* rest() const { return mData; }
    [[nodiscard]] std::size_t restSize() const { return mSize; }

private:
    const uint8_t* mData;
    std::size_t mSize;
};

}  // namespace fuzz
