// Private: wall time and resident-memory growth of the parts sim::Simulation builds from a scene
// (build_report.hpp).
#pragma once

#include "polycut/sim/build_report.hpp"

#include <chrono>
#include <string>
#include <vector>

namespace polycut::sim {

/// Resident set size of this process [KiB] (/proc/self/statm; 0 where it cannot be read).
long resident_kb();

/// Measures consecutive parts: each lap() records the time and RSS growth since the previous one
/// (or since construction) and starts the next part.
class PartClock {
public:
    PartClock() { restart(); }
    void restart() {
        m_start = std::chrono::steady_clock::now();
        m_rss = resident_kb();
    }
    /// Appends the part built since the last lap to `out` and starts the next one.
    void lap(std::vector<BuildPart>& out, const char* name, bool built) {
        BuildPart p;
        p.name = name;
        p.built = built;
        p.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_start)
                   .count();
        p.rss_kb = resident_kb() - m_rss;
        out.push_back(std::move(p));
        restart();
    }

private:
    std::chrono::steady_clock::time_point m_start;
    long m_rss = 0;
};

} // namespace polycut::sim
