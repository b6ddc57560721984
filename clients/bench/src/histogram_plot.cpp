// Histogram figure (see histogram_plot.hpp).
#include "histogram_plot.hpp"

#include "bitmap_font.hpp"
#include "polycut/common/stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace polycut::bench {

namespace {

constexpr Colour kBackground { 250, 250, 250 };
constexpr Colour kInk { 30, 30, 30 };
constexpr Colour kGrid { 215, 215, 215 };
constexpr Colour kBar { 70, 120, 190 };
constexpr Colour kP50 { 30, 150, 60 };
constexpr Colour kP99 { 230, 120, 20 };

std::string number(double v) {
    char text[32];
    if (std::abs(v) >= 100) {
        std::snprintf(text, sizeof text, "%.0f", v);
    } else if (std::abs(v) >= 10) {
        std::snprintf(text, sizeof text, "%.1f", v);
    } else {
        std::snprintf(text, sizeof text, "%.2f", v);
    }
    return text;
}

/// A "nice" upper axis limit >= v: 1, 2 or 5 times a power of ten.
double nice_ceiling(double v) {
    if (!(v > 0)) {
        return 1.0;
    }
    const double p = std::pow(10.0, std::floor(std::log10(v)));
    for (const double m : { 1.0, 2.0, 2.5, 5.0, 10.0 }) {
        if (m * p >= v) {
            return m * p;
        }
    }
    return 10 * p;
}

void vertical_dashes(render::Image& image, int x, int y0, int y1, const Colour& colour) {
    for (int y = y0; y < y1; ++y) {
        if ((y / 4) % 2 == 0) {
            put_pixel(image, x, y, colour);
            put_pixel(image, x + 1, y, colour);
        }
    }
}

void draw_panel(
    render::Image& image, int top, const HistogramPanel& panel, const PlotLayout& layout) {
    const int left = 70, right = layout.width - 20;
    const int plot_top = top + 34, plot_bottom = top + layout.panel_height - 30;
    const Summary s = summarize(panel.samples);

    std::string title = panel.title + " [" + panel.unit + "]  N " + std::to_string(s.count);
    if (s.count > 0) {
        title += "  P50 " + number(s.median) + "  P99 " + number(s.p99) + "  MAX " + number(s.max);
    }
    draw_text(image, left, top + 10, title, kInk, 2);
    // Axes.
    fill_rect(image, left, plot_bottom, right, plot_bottom + 1, kInk);
    fill_rect(image, left - 1, plot_top, left, plot_bottom, kInk);
    if (s.count == 0) {
        draw_text(image, left + 20, (plot_top + plot_bottom) / 2, "NO SAMPLES", kInk, 2);
        return;
    }
    const double x_max = nice_ceiling(std::max({ s.p99 * 1.25, s.median * 2.0, 1e-3 }));
    const int bins = std::max(layout.bins, 1);
    std::vector<long> counts(static_cast<std::size_t>(bins), 0);
    long peak = 1;
    for (const double v : panel.samples) {
        const int bin = std::clamp(static_cast<int>(v / x_max * bins), 0, bins - 1);
        peak = std::max(peak, ++counts[static_cast<std::size_t>(bin)]);
    }
    const double bar_w = double(right - left) / bins;
    for (int g = 1; g <= 4; ++g) { // horizontal grid at quarters of the peak
        const int y = plot_bottom - (plot_bottom - plot_top) * g / 4;
        fill_rect(image, left, y, right, y + 1, kGrid);
    }
    for (int b = 0; b < bins; ++b) {
        const long c = counts[static_cast<std::size_t>(b)];
        if (c == 0) {
            continue;
        }
        const int h
            = std::max(1, static_cast<int>(double(c) / double(peak) * (plot_bottom - plot_top)));
        const int x0 = left + static_cast<int>(b * bar_w) + 1;
        const int x1 = left + static_cast<int>((b + 1) * bar_w);
        fill_rect(image, x0, plot_bottom - h, std::max(x0 + 1, x1), plot_bottom, kBar);
    }
    const auto x_of = [&](double v) {
        return left + static_cast<int>(std::min(v, x_max) / x_max * (right - left));
    };
    vertical_dashes(image, x_of(s.median), plot_top, plot_bottom, kP50);
    vertical_dashes(image, x_of(s.p99), plot_top, plot_bottom, kP99);
    const auto marker = [&](int x, int y, const char* text, const Colour& colour) {
        fill_rect(image, x - 1, y - 1, x + text_width(text) + 1, y + kGlyphHeight + 1, kBackground);
        draw_text(image, x, y, text, colour, 1);
    };
    marker(x_of(s.median) + 4, plot_top + 2, "P50", kP50);
    marker(x_of(s.p99) + 4, plot_top + 12, "P99", kP99);
    // Tick labels: x at 0, 1/4 ... 1; y peak count.
    for (int t = 0; t <= 4; ++t) {
        const double v = x_max * t / 4;
        const std::string label = number(v);
        const int x = left + (right - left) * t / 4;
        fill_rect(image, x, plot_bottom, x + 1, plot_bottom + 4, kInk);
        draw_text(image, x - text_width(label) / 2, plot_bottom + 8, label, kInk, 1);
    }
    const std::string peak_label = std::to_string(peak);
    draw_text(image, left - 6 - text_width(peak_label), plot_top - 3, peak_label, kInk, 1);
    draw_text(image, left - 6 - text_width("0"), plot_bottom - 6, "0", kInk, 1);
    if (s.max > x_max) {
        draw_text(image, right - text_width("LAST BAR: >" + number(x_max)), plot_bottom + 18,
            "LAST BAR: >" + number(x_max), kInk, 1);
    }
}

} // namespace

render::Image plot_histograms(const std::vector<HistogramPanel>& panels, const PlotLayout& layout) {
    render::Image image;
    image.width = layout.width;
    image.height = layout.panel_height * static_cast<int>(std::max<std::size_t>(panels.size(), 1));
    image.rgba.assign(static_cast<std::size_t>(image.width) * image.height * 4, 255);
    fill_rect(image, 0, 0, image.width, image.height, kBackground);
    for (std::size_t k = 0; k < panels.size(); ++k) {
        draw_panel(image, static_cast<int>(k) * layout.panel_height, panels[k], layout);
    }
    return image;
}

} // namespace polycut::bench
