// polycut-bench's JSON report and histogram figure from a ProbeResult.
#pragma once

#include "histogram_plot.hpp"
#include "latency_probe.hpp"

#include <string>

namespace polycut::bench {

/// The machine the numbers came from: CPU model, logical CPUs, kernel, load average.
std::string machine_json();

/// The report as compact JSON text. Keys: "machine", "config", "control_rtt_ms", "command_ack_ms",
/// "command_to_visible_ms", "command_to_visible_ticks", "server" (step_ms, frame_interval_ms,
/// ticks, ticks_over_budget, worst_tick_ms, ...), "stream", "commands". Each distribution is
/// {"count", "p50", "p95", "p99", "max", "mean"}.
std::string report_json(const ProbeOptions& options, const ProbeResult& result);

/// A few human-readable lines: command to visible, control round trip, server step and overruns.
std::string report_text(const ProbeResult& result);

/// The histogram panels: command to visible, control round trip, server step time.
std::vector<HistogramPanel> report_panels(const ProbeResult& result);

} // namespace polycut::bench
