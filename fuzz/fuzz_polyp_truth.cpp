/// @brief libFuzzer target: the polyps of a ground-truth JSON (`cvc polyp-check --truth`) and of
/// a candidate list read as polyps (`--candidates`), and the surface test each polyp pixel goes
/// through.
#include <cstddef>
#include <cstdint>

#include "colon/colon_error.h"
#include "colon/polyp_truth.h"
#include "fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = fuzz::writeInputFile(data, size, ".json");
    try {
        for (const colon::PolypSurface& polyp : colon::readPolypTruth(path)) {
            colon::isOnPolyp(polyp, polyp.centreMm + glm::dvec3(0.5 * polyp.diameterMm, 0.0, 0.0), 0.1);
        }
    } catch (const colon::ColonError&) {
        // Rejecting a bad truth with a ColonError is the expected outcome.
    }
    try {
        for (const colon::PolypSurface& polyp : colon::readCandidatesAsPolyps(path)) {
            colon::isOnPolyp(polyp, polyp.centreMm + glm::dvec3(0.5 * polyp.diameterMm, 0.0, 0.0), 0.1);
        }
    } catch (const colon::ColonError&) {
        // So is rejecting a bad candidate list.
    }
    return 0;
}
