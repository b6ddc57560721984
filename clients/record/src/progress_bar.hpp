// A progress bar on stderr for offline recordings: redrawn in place on a terminal (at most ~10
// times a second), a plain line every 10 % otherwise (logs, CI).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace polycut::record {

/// Progress of `total` units of work, drawn on `out` (stderr by default).
class ProgressBar {
public:
    /// `label` prefixes the bar; `unit` names the work ("ticks"); disabled draws nothing.
    ProgressBar(long total, std::string label, std::string unit, bool enabled = true,
        std::FILE* out = stderr);
    /// Reports `done` units completed (monotonic).
    void update(long done);
    /// Draws the final state and ends the line.
    void finish();

    /// The bar line for `done` of `total` after `elapsed_s` seconds, e.g.
    /// "record [#######.............]  35% 210/600 ticks  12.0/s  ETA 32 s".
    static std::string line(
        const std::string& label, const std::string& unit, long done, long total, double elapsed_s);

private:
    void draw(bool final);

    long m_total;
    long m_done = 0;
    std::string m_label;
    std::string m_unit;
    bool m_enabled;
    std::FILE* m_out;
    bool m_tty;
    int m_last_decile = -1;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_last_draw;
};

} // namespace polycut::record
