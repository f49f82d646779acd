/// @brief libFuzzer target: centreline files as `cvc render --path` reads them, JSON (a phantom's
/// truth, `cvc colon`'s colon.json: points, segment starts, order, anterior) or text (x y z per
/// line, "# segment N"), and the poses along them. The first byte picks the form.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "engine/sequence/camera_path.h"
#include "fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const bool isJson = (data[0] & 1) != 0;
    const std::string path = fuzz::writeInputFile(data + 1, size - 1, isJson ? ".json" : ".txt");
    try {
        const engine::Centreline centreline = engine::readCentreline(path);
        engine::PathSettings settings;
        settings.stepMm = 5.0;
        settings.maxFrames = 2000;  // bounded work per input
        engine::posesAlongSegments(centreline, settings);
    } catch (const std::runtime_error&) {
        // Refusing a bad file is the expected outcome,
    } catch (const std::invalid_argument&) {
        // and so is refusing a path that gives no poses.
    }
    return 0;
}
