#!/usr/bin/env python3
"""Runs polycut-run on shipped scenes and checks each report against its analytic value or
invariant (issues 2-5). Usage: check_scenes.py POLYCUT_RUN SCENE_DIR GROUP"""
import json
import math
import os
import subprocess
import sys

RUN, DIR, GROUP = sys.argv[1], sys.argv[2], sys.argv[3]
ANALYTIC_TIP = 8.64e-3  # seed 002 sec. 3.3 [m]
failures = []


def run(name, *args):
    out = subprocess.run([RUN, os.path.join(DIR, name + ".json"), *args], capture_output=True,
                         text=True, timeout=900)
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
else:
    sys.exit(f"unknown group {GROUP}")

if failures:
    print("\n".join(failures), file=sys.stderr)
    sys.exit(1)
