#!/usr/bin/python3
"""clients/bench/plot_bench.py draws polycut-bench's histograms with matplotlib: the figure has the
documented size (900 px wide, 240 px per panel), bars in the bar colour, the p50 and p99 lines,
and an empty distribution gives a panel instead of an error; a missing report is exit status 1.

    /usr/bin/python3 tests/record/test_plot_bench.py clients/bench/plot_bench.py
"""
import json
import os
import subprocess
import sys
import tempfile

import matplotlib.image
import numpy as np


def colour_pixels(image, rgb, tol=8):
    """Pixels within `tol` (0..255 per channel) of the colour."""
    diff = np.abs(image[:, :, :3] * 255.0 - np.array(rgb, dtype=float))
    return int(np.count_nonzero(np.all(diff <= tol, axis=2)))


def main(script):
    rng = np.random.default_rng(7)
    report = {
        "config": {"command": "apply_force", "command_rate_hz": 20, "scene": "test"},
        "samples": {
            "command_to_visible_ms": list(np.round(rng.normal(20, 3, 500), 3)),
            "control_rtt_ms": list(np.round(rng.uniform(0.3, 2.0, 500), 3)),
            "server_step_ms": [],
        },
    }
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        path, png = os.path.join(tmp, "r.json"), os.path.join(tmp, "h.png")
        with open(path, "w") as f:
            json.dump(report, f)
        subprocess.run(["/usr/bin/python3", script, path, png], check=True)
        image = matplotlib.image.imread(png)
        height, width = image.shape[:2]
        if (width, height) != (900, 3 * 240):
            failures.append(f"size {width} x {height}, expected 900 x 720")
        bars = colour_pixels(image, (0x46, 0x78, 0xBE))
        p50 = colour_pixels(image, (0x2A, 0x9D, 0x3A))
        p99 = colour_pixels(image, (0xE0, 0x7B, 0x00))
        # Two panels of 500 samples each fill a good part of their plot area with bars.
        if bars < 20000:
            failures.append(f"{bars} bar pixels, expected >= 20000")
        if p50 < 100 or p99 < 100:
            failures.append(f"p50 line {p50} px, p99 line {p99} px, expected >= 100 each")
        # The empty third panel has no bars: the bottom 240 px hold none of the bar colour.
        if colour_pixels(image[-200:], (0x46, 0x78, 0xBE)) != 0:
            failures.append("bars drawn in the empty panel")
        missing = subprocess.run(["/usr/bin/python3", script, os.path.join(tmp, "none.json"), png],
                                 capture_output=True)
        if missing.returncode != 1 or b"none.json" not in missing.stderr:
            failures.append(f"missing report: exit {missing.returncode}, {missing.stderr!r}")
    for f in failures:
        print("FAIL:", f)
    print(f"{1 - bool(failures)} passed, {int(bool(failures))} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
