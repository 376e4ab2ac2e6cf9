#pragma once
// Repeated timing with warm-up, and the median / min / max the filter benchmark reports.
#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace aamap::bench {

struct Stats {
    double median = 0.0, min = 0.0, max = 0.0;  // milliseconds
    int repeats = 0;
};

inline Stats summarise(std::vector<double> ms) {
    Stats s;
    if (ms.empty()) return s;
    std::sort(ms.begin(), ms.end());
    const std::size_t n = ms.size();
    s.median = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
    s.min = ms.front();
    s.max = ms.back();
    s.repeats = static_cast<int>(n);
    return s;
}

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Runs `run` warmup + repeats times; `run` returns the milliseconds it measured itself, so the
// caller decides what is inside the timed region (wall time, or GPU timestamps).
inline Stats timeRepeated(int warmup, int repeats, const std::function<double()>& run) {
    for (int i = 0; i < warmup; ++i) run();
    std::vector<double> ms;
    ms.reserve(static_cast<std::size_t>(repeats));
    for (int i = 0; i < repeats; ++i) ms.push_back(run());
    return summarise(std::move(ms));
}

}  // namespace aamap::bench
