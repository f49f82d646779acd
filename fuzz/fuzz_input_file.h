/// @brief For targets whose parser reads a named file: the input bytes written to one scratch
/// file per process (libFuzzer runs one input at a time), its name ending as the parser expects.
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include <unistd.h>

namespace fuzz {

inline std::string writeInputFile(const uint8_t* data, std::size_t size, const std::string& extension) {
    const std::string path = "/tmp/cvc_fuzz_" + std::to_string(::getpid()) + extension;
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                  static_cast<std::streamsize>(size));
    return path;
}

}  // namespace fuzz
