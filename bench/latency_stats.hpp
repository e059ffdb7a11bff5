#pragma once
// Nearest-rank percentiles of latency samples (the definition tests/interop/bench_client.js
// uses, so numbers of both stacks compare).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <vector>

namespace skillcell::bench {

using Samples = std::vector<std::chrono::nanoseconds>;

struct LatencyStats {
    double medianUs = NAN;
    double p99Us = NAN;
    double maxUs = NAN;
    std::size_t n = 0;
};

inline LatencyStats summarize(Samples samples) {
    LatencyStats s;
    s.n = samples.size();
    if (samples.empty()) return s;
    std::sort(samples.begin(), samples.end());
    auto pct = [&](double p) {
        auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * double(samples.size())));
        rank = std::clamp<std::size_t>(rank, 1, samples.size());
        return std::chrono::duration<double, std::micro>(samples[rank - 1]).count();
    };
    s.medianUs = pct(50);
    s.p99Us = pct(99);
    s.maxUs = std::chrono::duration<double, std::micro>(samples.back()).count();
    return s;
}

/// One row of a latency table: what, then median, p99 and max in milliseconds, and n.
inline void printLatencyRow(const char* what, const Samples& samples, int width = 38) {
    const auto s = summarize(samples);
    std::printf("  %-*s %9.2f %9.2f %9.2f %5zu\n", width, what, s.medianUs / 1000, s.p99Us / 1000,
                s.maxUs / 1000, s.n);
}

}  // namespace skillcell::bench
