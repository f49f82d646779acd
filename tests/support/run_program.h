/// @brief Runs the `cvc` binary as a user would and captures its exit code and output.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace testing_support {

struct ProgramRun {
    int exitCode = -1;
    std::string out;
    std::string err;
};

inline std::string readWholeFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// A scratch path of this test process alone: CTest runs the tests of one executable as
/// separate processes in parallel, so a fixture that writes a shared input file (a phantom, a
/// path) must not write it where another test's process may be reading it.
inline std::filesystem::path processTmp(const std::string& name) {
    std::string file = "p";  // appended piece by piece: GCC 12 warns (-Wrestrict) on "p" + a + b
    file += std::to_string(::getpid());
    file += '_';
    file += name;
    return std::filesystem::path(CVC_TEST_TMP_DIR) / file;
}

/// Runs `CVC_BINARY arguments` through the shell with `environment` prefixed (e.g.
/// "VK_DRIVER_FILES=/none"); stdin is closed, as in CI.
inline ProgramRun runCvc(const std::string& arguments, const std::string& environment = "") {
    static int counter = 0;
    const std::filesystem::path base = std::filesystem::path(CVC_TEST_TMP_DIR) /
                                       ("run_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    const std::string command = environment + " \"" CVC_BINARY "\" " + arguments + " </dev/null >\"" +
                                base.string() + ".out\" 2>\"" + base.string() + ".err\"";
    const int status = std::system(command.c_str());
    ProgramRun run;
    run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = readWholeFile(base.string() + ".out");
    run.err = readWholeFile(base.string() + ".err");
    return run;
}

/// Number of lines in `text` (a final line without a newline counts).
inline int lineCount(const std::string& text) {
    int lines = 0;
    for (char c : text) lines += c == '\n' ? 1 : 0;
    if (!text.empty() && text.back() != '\n') ++lines;
    return lines;
}

}  // namespace testing_support
