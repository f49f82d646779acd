#include "volumes/parallel_for.h"

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace volumes {

void parallelFor(int count, const std::function<void(int)>& job) {
    const int threads = std::max(1, std::min(static_cast<int>(std::thread::hardware_concurrency()), count));
    if (threads <= 1) {
        for (int i = 0; i < count; ++i) job(i);
        return;
    }
    std::vector<std::thread> pool;
    std::exception_ptr error;
    std::mutex errorMutex;
    for (int t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            try {
                for (int i = t; i < count; i += threads) job(i);
            } catch (...) {
                std::lock_guard<std::mutex> lock(errorMutex);
                if (!error) error = std::current_exception();
            }
        });
    }
    for (std::thread& thread : pool) thread.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace volumes
