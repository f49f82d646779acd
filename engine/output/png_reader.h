/// @brief Reading an 8-bit RGBA PNG back (libpng's simplified API): the sheets of a frame whose
/// walls other processes rendered and wrote, and the tests' comparisons of written files.
#pragma once

#include <string>

#include "colon/rgba_image.h"

namespace engine {

/// The pixels of `path` as 8-bit RGBA, row 0 at the top. Throws std::runtime_error naming the
/// file for a missing, truncated or undecodable file.
colon::RgbaImage readPng(const std::string& path);

}  // namespace engine
