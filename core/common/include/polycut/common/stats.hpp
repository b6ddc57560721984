// Distribution summaries for timings: medians and percentiles, never single wall-clock numbers.
#pragma once

#include <chrono>
#include <vector>

namespace polycut {

/// Summary of a sample (e.g. step times [ms]).
struct Summary {
    long count = 0;
    double mean = 0, min = 0, max = 0;
    double median = 0, p90 = 0, p95 = 0, p99 = 0;
};

/// Percentile q in [0, 100] by linear interpolation between order statistics.
double percentile(std::vector<double> sample, double q);

/// Summary of a sample; an empty sample gives count 0 and zeros.
Summary summarize(const std::vector<double>& sample);

/// CPU time of the whole process, all threads [ms] (CLOCK_PROCESS_CPUTIME_ID). On a shared,
/// loaded machine it is the fairer cost of a piece of work than a wall time.
double process_cpu_ms();
/// CPU time of the calling thread [ms] (CLOCK_THREAD_CPUTIME_ID).
double thread_cpu_ms();

/// Wall-clock stopwatch on steady_clock.
class Stopwatch {
public:
    Stopwatch()
        : m_start(std::chrono::steady_clock::now()) { }
    void restart() { m_start = std::chrono::steady_clock::now(); }
    /// Elapsed time [ms].
    double ms() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_start)
            .count();
    }

private:
    std::chrono::steady_clock::time_point m_start;
};

} // namespace polycut
