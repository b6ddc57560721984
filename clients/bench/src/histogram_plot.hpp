// Histograms of latency samples drawn into an RGBA image (one panel per sample), with the p50
// and p99 marked and labelled; written as PNG by polycut-bench --histogram.
#pragma once

#include "polycut/render/image.hpp"

#include <string>
#include <vector>

namespace polycut::bench {

/// One histogram panel.
struct HistogramPanel {
    std::string title; ///< e.g. "command to visible"
    std::string unit; ///< e.g. "ms"
    std::vector<double> samples; ///< values in `unit`; may be empty
};

/// Layout of the figure.
struct PlotLayout {
    int width = 900; ///< [px]
    int panel_height = 240; ///< [px]
    int bins = 40; ///< bars per panel
};

/// Draws the panels stacked top to bottom. The x range of a panel is [0, max(p99 * 1.25, ...)],
/// samples beyond it are counted in the last bar; dashed vertical lines mark p50 (green) and p99
/// (orange). An empty sample draws "no samples".
render::Image plot_histograms(
    const std::vector<HistogramPanel>& panels, const PlotLayout& layout = {});

} // namespace polycut::bench
