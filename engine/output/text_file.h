/// @brief Writing a text output file (JSON, Markdown, Slicer markups): one place that truncates,
/// writes and checks, so every command reports a failed write the same way.
#pragma once

#include <filesystem>
#include <string>

namespace engine {

/// Writes `text` to `path`, replacing what was there. Throws std::runtime_error
/// "PATH: write failed" where the file cannot be opened or written.
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace engine
