/// @brief libFuzzer target: cube-map files as `cvc bake` writes them and `cvc render --display`
/// loads them (an 88-byte header, then the texels), and bilinear lookups into a map that loads.
#include <cstddef>
#include <cstdint>

#include "conformal/cube_map.h"
#include "fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = fuzz::writeInputFile(data, size, ".cvcm");
    try {
        const conformal::CubeMap map = conformal::loadCubeMap(path);
        // Lookups on the axes, on a cube edge and at a corner exercise the seamless taps.
        for (const glm::dvec3& direction : {glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1),
                                            glm::dvec3(1, 1, 0), glm::dvec3(-1, 1, -1), glm::dvec3(0.3, -0.2, 0.9)}) {
            conformal::sampleCubeMapBilinear(map, direction);
        }
    } catch (const conformal::CubeMapFileError&) {
        // Refusing a bad file with a CubeMapFileError is the expected outcome.
    }
    return 0;
}
