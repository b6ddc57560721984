"""polycut's figures, drawn by matplotlib in one style: polycut-bench's latency histograms
(``clients/bench/plot_bench.py`` is their command line) and the trade study's error-against-cost
plots (``tools/study``) both call :func:`apply_style`; notebooks can too.

    import polycut.plots
    polycut.plots.bench_histograms(json.load(open("out/bench.json")), "out/bench.png")
"""

#: Colours shared by the figures: bars, the median and the 99th percentile.
BAR_COLOUR, P50_COLOUR, P99_COLOUR = "#4678be", "#2a9d3a", "#e07b00"

#: matplotlib settings of every polycut figure.
STYLE = {
    "figure.dpi": 100,
    "savefig.dpi": 100,
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
}

_BENCH_PANELS = (
    ("command_to_visible_ms", "command to visible"),
    ("control_rtt_ms", "control round trip"),
    ("server_step_ms", "server step"),
)


def apply_style():
    """Selects the Agg backend (files, no display) and polycut's rcParams; returns pyplot."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update(STYLE)
    return plt


def bench_histograms(report, path, width_px=900, panel_px=240, bins=40):
    """Draws a polycut-bench report's histograms to `path` (PNG): one panel per distribution of
    its ``samples`` (command to visible, control round trip, server step) [ms], p50 and p99 as
    dashed lines, samples past 1.25 x p99 counted in the last bar; `width_px` wide and `panel_px`
    per panel."""
    import numpy as np
    plt = apply_style()
    dpi = STYLE["figure.dpi"]
    samples = report.get("samples", {})
    size = (width_px / dpi, panel_px * len(_BENCH_PANELS) / dpi)
    fig, axes = plt.subplots(len(_BENCH_PANELS), 1, figsize=size, squeeze=False)
    for ax, (key, title) in zip(axes[:, 0], _BENCH_PANELS):
        values = np.asarray(samples.get(key, []), dtype=float)
        ax.set_title(title, loc="left")
        ax.set_xlabel("ms")
        ax.set_ylabel("count")
        if values.size == 0:
            ax.text(0.5, 0.5, "no samples", transform=ax.transAxes, ha="center", va="center")
            continue
        p50, p99 = np.percentile(values, 50), np.percentile(values, 99)
        hi = max(p99 * 1.25, values.max() if p99 <= 0 else 0.0, 1e-3)
        ax.hist(np.minimum(values, hi), bins=bins, range=(0.0, hi), color=BAR_COLOUR,
                edgecolor="white", linewidth=0.4)
        for value, label, colour in ((p50, "p50", P50_COLOUR), (p99, "p99", P99_COLOUR)):
            ax.axvline(value, color=colour, linestyle="--", linewidth=1.4,
                       label=f"{label} {value:.3g} ms")
        ax.set_xlim(0.0, hi)
        ax.legend(loc="upper right", title=f"n = {values.size}", title_fontsize=8)
    config = report.get("config", {})
    fig.suptitle(f"polycut-bench: {config.get('command', '?')} at "
                 f"{config.get('command_rate_hz', '?')} Hz, scene {config.get('scene', '?')}")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
