// Order statistics of per-step timings.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace btbench {

// The q-quantile (0..1) by the nearest-rank rule; NaN for no samples.
inline double quantile(std::vector<double> samples, double q) {
    if (samples.empty()) return std::nan("");
    const size_t rank = size_t(std::ceil(q * double(samples.size())));
    const size_t index = rank == 0 ? 0 : rank - 1;
    std::nth_element(samples.begin(), samples.begin() + long(index), samples.end());
    return samples[index];
}

inline double mean(const std::vector<double>& samples) {
    if (samples.empty()) return std::nan("");
    double sum = 0;
    for (double s : samples) sum += s;
    return sum / double(samples.size());
}

}  // namespace btbench
