#!/usr/bin/python3
"""Drives polycut-server from Python: loads a scene, cuts a short incision with scalpel
notifications, pulls one lip open with a grab, and follows the surface stream with a
SurfaceMirror. Prints one JSON summary.

    /usr/bin/python3 clients/python/example.py --server tcp://127.0.0.1:5555 [--scene default]
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from polycut_client import Client, RpcError  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default="tcp://127.0.0.1:5555")
    parser.add_argument("--scene", default="default", help="scene name in the server's directory")
    parser.add_argument("--shutdown", action="store_true", help="stop the server at the end")
    args = parser.parse_args()

    with Client(args.server) as client:
        hello = client.hello()
        scene = client.call("load_scene", name=args.scene)
        mirror = client.surface_mirror()

        # Top of the block: its highest rest vertex.
        top = float(mirror.positions[:, 2].max())
        y = 0.0025
        # A 4 cm stroke sampled at 20 points, the blade reaching 1.5 cm below the top.
        for x in np.linspace(-0.02, 0.02, 20):
            client.notify("scalpel", stroke=1, a=[float(x), y, top + 0.01],
                          b=[float(x), y, top - 0.015])
            time.sleep(0.02)
            mirror.update()
        stroke = client.call("end_stroke", stroke=1)

        grab = client.call("grab", point=[0.0, y + 0.004, top], radius=0.005, stiffness=400.0)
        for k in range(1, 11):
            client.call("move_grab", id=grab["id"], target=[0.0, y + 0.004 + 0.001 * k, top + 0.002])
            mirror.update(timeout_ms=30)
        client.call("release", id=grab["id"])

        # Bad input gets an error pointing at the field.
        try:
            client.call("apply_force", point=[0, 0, top], force=[0, 0, -1], radius=-1)
        except RpcError as e:
            bad = {"code": e.code, "pointer": e.pointer}

        mirror.update(timeout_ms=200)
        stats = client.call("get_stats")
        summary = {
            "server": hello["server"],
            "scene": scene["name"],
            "stroke": stroke,
            "mirror": {"seq": mirror.header["seq"], "vertices": int(mirror.positions.shape[0]),
                       "triangles": int(mirror.triangles.shape[0]),
                       "cut_triangles": int(np.count_nonzero(mirror.tags == 2)),
                       "snapshots": mirror.snapshots},
            "bad_request": bad,
            "stats": {k: stats[k] for k in ("tick", "topology_version", "ticks_over_budget",
                                             "step_ms_p50", "step_ms_p99")},
        }
        if args.shutdown:
            client.call("shutdown")
        print(json.dumps(summary))


if __name__ == "__main__":
    main()
