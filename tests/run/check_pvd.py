#!/usr/bin/python3
"""The ParaView time series of polycut-run --vtu and polycut-record --offline --vtu (issue 16
item 4): DIR/series.pvd lists every written step with its simulated time [s]; each .vtu read
back with meshio has, per node, displacement [m], velocity [m/s] and the cut tag, and per cell
the stress tensor [Pa], von Mises stress [Pa] and the cut tag.

    /usr/bin/python3 check_pvd.py POLYCUT_RUN POLYCUT_RECORD SCENES_DIR

Checks (tolerances stated inline): the time values, the rest positions recovered as points -
displacement, von Mises recomputed from the stress tensor, the cut tag before and after the
scene's cut, motion under gravity.
"""
import json
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import meshio
import numpy as np

FAILURES = []
CHECKS = [0]


def check(ok, what):
    CHECKS[0] += 1
    if not ok:
        FAILURES.append(what)
        print("FAIL:", what)


def read_series(directory):
    """[(time [s], meshio.Mesh)] from DIR/series.pvd, in file order."""
    root = ET.parse(os.path.join(directory, "series.pvd")).getroot()
    check(root.get("type") == "Collection", "series.pvd is a VTK Collection")
    steps = []
    for ds in root.iter("DataSet"):
        steps.append((float(ds.get("timestep")), meshio.read(os.path.join(directory, ds.get("file")))))
    return steps


def cell_array(mesh, name):
    return np.concatenate([np.asarray(block).reshape(len(block), -1)
                           for block in mesh.cell_data[name]])


def check_fields(mesh, label):
    for name, k in (("displacement", 3), ("velocity", 3), ("cut", 1)):
        a = np.asarray(mesh.point_data.get(name, np.zeros((0, 0))))
        check(a.shape[0] == len(mesh.points) and a.reshape(len(mesh.points), -1).shape[1] == k,
              f"{label}: point field {name} with {k} components")
    for name, k in (("stress", 9), ("von_mises", 1), ("cut", 1)):
        check(name in mesh.cell_data and cell_array(mesh, name).shape[1] == k,
              f"{label}: cell field {name} with {k} components")
    stress = cell_array(mesh, "stress").reshape(-1, 3, 3)
    vm = cell_array(mesh, "von_mises")[:, 0]
    scale = max(1.0, float(np.abs(stress).max()))
    # Cauchy stress is symmetric; von Mises = sqrt(3/2 dev:dev), to 1e-9 of the largest entry.
    check(np.abs(stress - stress.transpose(0, 2, 1)).max() <= 1e-9 * scale,
          f"{label}: stress symmetric")
    dev = stress - np.trace(stress, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)
    recomputed = np.sqrt(1.5 * np.einsum("cij,cij->c", dev, dev))
    check(np.abs(recomputed - vm).max() <= 1e-9 * scale,
          f"{label}: von_mises = sqrt(3/2 dev:dev), max diff {np.abs(recomputed - vm).max():.3g}")


def main(run, record, scenes):
    scene = os.path.join(scenes, "cut_halves.json")
    doc = json.load(open(scene))
    dt, every, steps = (doc["integrator"]["dt"], doc["output"]["vtu_every"],
                        doc["output"]["steps"])
    lo = np.array(doc["geometry"]["origin"])
    hi = lo + np.array(doc["geometry"]["size"])
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run")
        subprocess.run([run, scene, "--vtu", out], check=True, stdout=subprocess.DEVNULL)
        series = read_series(out)
        times = [t for t, _ in series]
        expected = [k * dt for k in range(0, steps + 1, every)]
        check(len(times) == len(expected) and np.allclose(times, expected, rtol=0, atol=1e-9),
              f"polycut-run: times {times}, expected {expected} (to 1e-9 s)")
        for t, mesh in series:
            check_fields(mesh, f"polycut-run t={t:g}")
        first, last = series[0][1], series[-1][1]
        u0 = np.asarray(first.point_data["displacement"])
        check(np.abs(u0).max() == 0 and np.abs(first.point_data["velocity"]).max() == 0,
              "t=0: zero displacement and velocity")
        check(np.asarray(first.point_data["cut"]).max() == 0
              and cell_array(first, "cut").max() == 0, "t=0 (before the cut at tick 5): no cut tag")
        # After the cut: the cut surface splits the block, so cells and nodes carry the tag.
        check(cell_array(last, "cut").max() >= 1 and np.asarray(last.point_data["cut"]).sum() >= 9,
              "after the cut: cells and nodes tagged cut")
        rest = last.points - np.asarray(last.point_data["displacement"])
        check(np.all(rest >= lo - 1e-9) and np.all(rest <= hi + 1e-9),
              "points - displacement = rest positions inside the block (to 1 nm)")
        moving = [np.abs(np.asarray(m.point_data["velocity"])).max() for _, m in series[1:]]
        check(all(v > 1e-6 for v in moving[:1]), f"under gravity the block moves: |v| {moving}")

        out = os.path.join(tmp, "record")
        subprocess.run([record, "--offline", scene, "--frames", "3", "--vtu", out, "--quiet"],
                       check=True, stdout=subprocess.DEVNULL)
        series = read_series(out)
        times = [t for t, _ in series]
        check(np.allclose(times, [dt, 2 * dt, 3 * dt], rtol=0, atol=1e-9),
              f"polycut-record: times {times}, expected ticks 1..3 x {dt} s")
        for t, mesh in series:
            check_fields(mesh, f"polycut-record t={t:g}")
    print(f"{CHECKS[0] - len(FAILURES)} passed, {len(FAILURES)} failed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
