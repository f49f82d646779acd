/// @brief Runs a loop's iterations on all hardware threads (the bake and the speed bounds: CPU
/// work over a cube map's rows, independent of each other).
#pragma once

#include <algorithm>
#include <future>
#include <thread>
#include <vector>

namespace conformal {

/// Calls body(k) for k in [0, count), interleaved over one worker per hardware thread; returns
/// when all are done, rethrowing the first exception a worker threw.
template <typename Function>
void parallelFor(int count, Function&& body) {
    const int workers = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::future<void>> jobs;
    for (int w = 0; w < workers; ++w) {
        jobs.push_back(std::async(std::launch::async, [&, w] {
            for (int k = w; k < count; k += workers) body(k);
        }));
    }
    for (auto& job : jobs) job.get();
}

}  // namespace conformal
