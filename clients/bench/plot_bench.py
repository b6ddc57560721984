#!/usr/bin/python3
"""Histograms of a polycut-bench report, drawn with matplotlib (docs/recording.md "Benchmark").

    /usr/bin/python3 clients/bench/plot_bench.py REPORT.json OUT.png

REPORT.json is polycut-bench's JSON report; its "samples" object holds the raw distributions
[ms]. One panel per distribution (command to visible, control round trip, server step), stacked,
with the p50 and p99 marked as dashed lines and labelled. Samples past 1.25 x p99 are counted in
the last bar so one outlier does not squash the histogram. The figure is 900 px wide and 240 px
per panel (dpi 100). polycut-bench --histogram runs this script; it can also be run by hand on a
saved report to restyle the figure.
"""
import json
import sys

PANELS = (
    ("command_to_visible_ms", "command to visible"),
    ("control_rtt_ms", "control round trip"),
    ("server_step_ms", "server step"),
)
WIDTH_PX, PANEL_PX, DPI, BINS = 900, 240, 100, 40


def percentile(values, q):
    """Linear-interpolation percentile (numpy's default), q in [0, 100]."""
    import numpy as np
    return float(np.percentile(values, q))


def draw(report, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    samples = report.get("samples", {})
    size = (WIDTH_PX / DPI, PANEL_PX * len(PANELS) / DPI)
    fig, axes = plt.subplots(len(PANELS), 1, figsize=size, dpi=DPI, squeeze=False)
    for ax, (key, title) in zip(axes[:, 0], PANELS):
        values = [float(v) for v in samples.get(key, [])]
        ax.set_title(title, loc="left", fontsize=10)
        ax.set_xlabel("ms", fontsize=8)
        ax.set_ylabel("count", fontsize=8)
        ax.tick_params(labelsize=8)
        ax.grid(True, alpha=0.3)
        if not values:
            ax.text(0.5, 0.5, "no samples", transform=ax.transAxes, ha="center", va="center")
            continue
        p50, p99 = percentile(values, 50), percentile(values, 99)
        hi = max(p99 * 1.25, max(values) if p99 <= 0 else 0.0, 1e-3)
        clipped = [min(v, hi) for v in values]
        ax.hist(clipped, bins=BINS, range=(0.0, hi), color="#4678be", edgecolor="white",
                linewidth=0.4)
        for value, label, colour in ((p50, "p50", "#2a9d3a"), (p99, "p99", "#e07b00")):
            ax.axvline(value, color=colour, linestyle="--", linewidth=1.4,
                       label=f"{label} {value:.3g} ms")
        ax.set_xlim(0.0, hi)
        ax.legend(fontsize=8, loc="upper right", title=f"n = {len(values)}", title_fontsize=8)
    config = report.get("config", {})
    fig.suptitle(f"polycut-bench: {config.get('command', '?')} at "
                 f"{config.get('command_rate_hz', '?')} Hz, scene {config.get('scene', '?')}",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    try:
        with open(argv[1]) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        sys.stderr.write(f"plot_bench.py: {argv[1]}: {e}\n")
        return 1
    draw(report, argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
