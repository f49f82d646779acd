/// @brief The statistics the benchmarks report: medians (of times and of paired ratios).
#pragma once

#include <algorithm>
#include <vector>

namespace bench {

/// The median of `values`; 0 for none.
inline double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace bench
