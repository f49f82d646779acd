/// @brief libFuzzer target: hit images as `cvc measure` reads them (NRRD of float 3- or
/// 4-vectors, raw or gzip), and the measures on them.
#include <cstddef>
#include <cstdint>

#include "colon/colon_error.h"
#include "colon/hit_image.h"
#include "colon/surface_measure.h"
#include "fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = fuzz::writeInputFile(data, size, ".nrrd");
    try {
        const colon::HitImage image = colon::readHitImage(path);
        if (static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) > (1u << 16)) return 0;
        colon::surfaceDistanceMm(image, 0, 0, image.width - 1, image.height - 1);
        colon::polypDiameter(image, image.width / 2, image.height / 2);
    } catch (const colon::ColonError&) {
        // Rejecting a bad file, a miss pixel or a seed with no protrusion is the expected outcome.
    }
    return 0;
}
