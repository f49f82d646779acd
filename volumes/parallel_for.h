/// @brief A minimal parallel loop for the volume builders (brick min/max, phantoms): the
/// machines this runs on have few cores and no other threading library is needed.
#pragma once

#include <functional>

namespace volumes {

/// Calls job(i) for every i in [0, count), spread over the hardware threads (interleaved, so
/// neighbouring items go to different threads). Each item must write only its own outputs.
/// The first exception a job throws is rethrown here after every thread has finished.
void parallelFor(int count, const std::function<void(int)>& job);

}  // namespace volumes
