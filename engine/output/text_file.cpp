#include "engine/output/text_file.h"

#include <fstream>
#include <stdexcept>

namespace engine {

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(path.string() + ": write failed");
}

}  // namespace engine
