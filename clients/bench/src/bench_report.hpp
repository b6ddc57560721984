// polycut-bench's JSON report from a ProbeResult (the histogram figure is drawn from it by
// clients/bench/plot_bench.py with matplotlib).
#pragma once

#include "latency_probe.hpp"

#include <string>

namespace polycut::bench {

/// The machine the numbers came from: CPU model, logical CPUs, kernel, load average.
std::string machine_json();

/// The report as compact JSON text. Keys: "machine", "config", "control_rtt_ms", "command_ack_ms",
/// "command_to_visible_ms", "command_to_visible_ticks", "server" (step_ms, frame_interval_ms,
/// ticks, ticks_over_budget, worst_tick_ms, ...), "stream", "commands". Each distribution is
/// {"count", "p50", "p95", "p99", "max", "mean"}. "samples" holds the raw distributions the
/// histograms are drawn from [ms]: "command_to_visible_ms", "control_rtt_ms", "server_step_ms".
std::string report_json(const ProbeOptions& options, const ProbeResult& result);

/// A few human-readable lines: command to visible, control round trip, server step and overruns.
std::string report_text(const ProbeResult& result);

/// Draws the report's histograms to `png_path` by running `script` (clients/bench/plot_bench.py)
/// with /usr/bin/python3 on the report saved at `report_path`. Throws polycut::Error when the
/// script cannot be run or fails (its stderr is passed through).
void plot_histograms(
    const std::string& script, const std::string& report_path, const std::string& png_path);

} // namespace polycut::bench
