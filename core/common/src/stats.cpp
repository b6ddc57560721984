#include "polycut/common/stats.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <numeric>

namespace polycut {

double percentile(std::vector<double> sample, double q) {
    if (sample.empty())
        return 0.0;
    std::sort(sample.begin(), sample.end());
    const double pos = std::clamp(q, 0.0, 100.0) / 100.0 * double(sample.size() - 1);
    const auto lo = std::size_t(std::floor(pos));
    const auto hi = std::min(lo + 1, sample.size() - 1);
    const double t = pos - double(lo);
    return sample[lo] * (1.0 - t) + sample[hi] * t;
}

Summary summarize(const std::vector<double>& sample) {
    Summary s;
    if (sample.empty())
        return s;
    std::vector<double> sorted = sample;
    std::sort(sorted.begin(), sorted.end());
    s.count = long(sorted.size());
    s.mean = std::accumulate(sorted.begin(), sorted.end(), 0.0) / double(sorted.size());
    s.min = sorted.front();
    s.max = sorted.back();
    s.median = percentile(sorted, 50);
    s.p90 = percentile(sorted, 90);
    s.p95 = percentile(sorted, 95);
    s.p99 = percentile(sorted, 99);
    return s;
}

namespace {
double clock_ms(clockid_t clock) {
    timespec t {};
    clock_gettime(clock, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}
} // namespace

double process_cpu_ms() {
    return clock_ms(CLOCK_PROCESS_CPUTIME_ID);
}

double thread_cpu_ms() {
    return clock_ms(CLOCK_THREAD_CPUTIME_ID);
}

} // namespace polycut
