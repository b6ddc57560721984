#!/usr/bin/env python3
"""Runs polycut-run on shipped scenes and checks each report against its analytic value or
invariant (issues 2-5). Usage: check_scenes.py POLYCUT_RUN SCENE_DIR GROUP"""
import json
import math
import os
import subprocess
import sys
import tempfile

RUN, DIR, GROUP = sys.argv[1], sys.argv[2], sys.argv[3]
ANALYTIC_TIP = 8.64e-3  # seed 002 sec. 3.3 [m]
failures = []


def run(name, *args, path=None):
    out = subprocess.run([RUN, path or os.path.join(DIR, name + ".json"), *args],
                         capture_output=True, text=True, timeout=900)
    if out.returncode != 0:
        failures.append(f"{name}: exit {out.returncode}: {out.stderr.strip()}")
        return None
    report = json.loads(out.stdout)
    for key in ("nodes", "cells", "rest_volume"):
        if key not in report["mesh"]:
            failures.append(f"{name}: mesh.{key} missing")
    for key in ("median", "p99"):
        if key not in report["timing"]["step_ms"]:
            failures.append(f"{name}: timing.step_ms.{key} missing")
    return report


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def tip_error(report):
    u = report["probes"]["tip"]["displacement"]
    return (math.sqrt(sum(x * x for x in u)) - ANALYTIC_TIP) / ANALYTIC_TIP


if GROUP == "cantilever":
    errors = {}
    for name in ("cantilever", "cantilever_hex"):
        r = run(name)
        if r:
            errors[name] = tip_error(r)
            check(abs(errors[name]) <= 0.033, f"{name}: tip error {100 * errors[name]:+.2f} % within 3.3 %")
    if len(errors) == 2:
        check(abs(errors["cantilever_hex"]) <= abs(errors["cantilever"]),
              "cantilever_hex at least as accurate as cantilever (P1)")
elif GROUP == "polyhedral":
    for name in ("cantilever_mvc", "cantilever_mvc_heuristic", "cantilever_harmonic"):
        r = run(name)
        if r:
            e = tip_error(r)
            check(abs(e) <= 0.05, f"{name}: tip error {100 * e:+.2f} % within 5 %")
elif GROUP == "cuts":
    for name, components, vol_tol in (("cut_halves", 2, 1e-9), ("cut_halves_tet", 2, 1e-3),
                                      ("cut_slices", 6, 1e-9), ("cut_progressive", 1, 1e-9),
                                      ("cut_pencil", None, 1e-9)):
        r = run(name)
        if not r:
            continue
        c = r["cut"]
        check(c["surface_closed"], f"{name}: surface closed")
        check(c["rest_volume_relative_change"] <= vol_tol,
              f"{name}: rest volume change {c['rest_volume_relative_change']:.2e} <= {vol_tol:g}")
        if components is not None:
            check(c["components"] == components, f"{name}: {c['components']} components (expect {components})")
        check("max_cut_ms" in c and c["max_cut_ms"] > 0, f"{name}: cut.max_cut_ms reported ({c.get('max_cut_ms')})")
        check(r["solver"]["rolled_back_steps"] == 0, f"{name}: no rolled-back steps")
    r = run("default", "--steps", "5")
    check(r is not None and "top" in r["probes"], "default: runs and reports its probe")
elif GROUP == "falling":
    # seed 000 Fig. 1: one 24-node cell on a slope, base fixed, under gravity (issue 4 item 5)
    with open(os.path.join(DIR, "falling_cell.json")) as f:
        scene = json.load(f)
    height = 2 * math.sqrt(2) * scene["geometry"]["size"]  # truncated octahedron: 2 sqrt(2) a

    def variant(tmp, **integrator):
        s = json.loads(json.dumps(scene))
        s["integrator"].update(integrator)
        path = os.path.join(tmp, "falling_cell_" + "_".join(map(str, integrator.values())) + ".json")
        with open(path, "w") as f:
            json.dump(s, f)
        return run("falling_cell", path=path)

    def top(report):
        return report["probes"]["top"]["displacement"]

    def norm(u):
        return math.sqrt(sum(x * x for x in u))

    r = run("falling_cell")
    with tempfile.TemporaryDirectory() as tmp:
        static = variant(tmp, type="static", tolerance=1e-10)
        linear = variant(tmp, corotated=False)
    if r and static and linear:
        check(r["mesh"]["cells"] == 1 and r["mesh"]["nodes"] == 24, "falling_cell: one cell, 24 nodes")
        check(r["solver"]["rolled_back_steps"] == 0, "falling_cell: no rolled-back steps")
        u, u_static, u_linear = top(r), top(static), top(linear)
        share = norm(u) / height
        check(0.1 <= share <= 0.3, f"falling_cell: top moved {100 * share:.1f} % of the height (10-30 %)")
        gap = norm([a - b for a, b in zip(u, u_static)]) / norm(u_static)
        check(gap <= 1e-3, f"falling_cell: settled after {r['steps']} steps, |u - u_static| / |u_static| = {gap:.1e} <= 1e-3")
        nonlinear = norm([a - b for a, b in zip(u, u_linear)]) / norm(u)
        check(nonlinear >= 0.1, f"falling_cell: corotated and linear differ by {100 * nonlinear:.1f} % (>= 10 %)")
    # A hull point that is not a corner: exit 2, the error names the point and the file (mesh
    # construction errors are reported like parse errors).
    with tempfile.TemporaryDirectory() as tmp:
        bad = os.path.join(tmp, "bad_hull.json")
        with open(bad, "w") as f:
            json.dump({"name": "bad_hull", "material": {"youngs_modulus": 1e4},
                       "geometry": {"type": "convex_hull", "points": [
                           [0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.1, 0.1, 0.1]]}}, f)
        out = subprocess.run([RUN, bad], capture_output=True, text=True, timeout=60)
        check(out.returncode == 2 and "/geometry/points/4" in out.stderr and bad in out.stderr,
              f"bad hull: exit {out.returncode}, error names the point and the file: {out.stderr.strip()}")
else:
    sys.exit(f"unknown group {GROUP}")

if failures:
    print("\n".join(failures), file=sys.stderr)
    sys.exit(1)
