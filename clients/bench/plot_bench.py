#!/usr/bin/python3
"""Histograms of a polycut-bench report, drawn with matplotlib (docs/recording.md "Benchmark").

    /usr/bin/python3 clients/bench/plot_bench.py REPORT.json OUT.png

REPORT.json is polycut-bench's JSON report; its "samples" object holds the raw distributions
[ms]. One panel per distribution (command to visible, control round trip, server step), stacked,
with the p50 and p99 marked as dashed lines and labelled; 900 px wide, 240 px per panel. The
drawing is polycut.plots.bench_histograms (clients/python), in the style the trade study's plots
share. polycut-bench --histogram runs this script; run it by hand on a saved report to redraw it.
"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from polycut.plots import bench_histograms  # noqa: E402


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
    bench_histograms(report, argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
