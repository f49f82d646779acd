/// @brief Two output folders compared file by file, byte for byte (a resumed or shared render
/// against a clean single-process one).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/run_program.h"

namespace testing_support {

/// Every regular file below `folder`, by its path relative to it, with its bytes.
inline std::map<std::string, std::string> filesIn(const std::filesystem::path& folder) {
    std::map<std::string, std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
        if (entry.is_regular_file()) {
            files[std::filesystem::relative(entry.path(), folder).string()] = readWholeFile(entry.path());
        }
    }
    return files;
}

/// The same file names below both folders, and the same bytes in each.
inline void expectSameFolders(const std::filesystem::path& expected, const std::filesystem::path& actual) {
    const auto want = filesIn(expected), got = filesIn(actual);
    std::vector<std::string> wantNames, gotNames;
    for (const auto& [name, bytes] : want) wantNames.push_back(name);
    for (const auto& [name, bytes] : got) gotNames.push_back(name);
    ASSERT_EQ(gotNames, wantNames);
    for (const auto& [name, bytes] : want) EXPECT_TRUE(got.at(name) == bytes) << name << " differs";
}

}  // namespace testing_support
