#!/usr/bin/python3
"""The Python client (clients/python/polycut_client.py) against a polycut-server subprocess:
hello, load by name, a binary-frame cut, a SurfaceMirror that ends equal to get_surface, an
RpcError with the field's pointer, and a clean shutdown (exit status 0).

    test_python_client.py POLYCUT_SERVER SOURCE_DIR
"""

import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

SCENE = {
    "name": "small",
    "geometry": {"type": "box", "origin": [-0.02, -0.02, 0], "size": [0.04, 0.04, 0.02],
                 "cells": [4, 4, 2], "elements": "tet"},
    "method": "tet",
    "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.45, "density": 1000},
    "integrator": {"type": "implicit_euler", "dt": 0.0166667, "corotated": True},
    "solver": {"type": "pcg", "preconditioner": "jacobi", "tolerance": 1e-8},
    "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-9}}],
    "loads": {"gravity": [0, 0, -9.81]},
}


def main():
    server_exe, source_dir = sys.argv[1], sys.argv[2]
    sys.path.insert(0, os.path.join(source_dir, "clients", "python"))
    from polycut_client import Client, RpcError

    with tempfile.TemporaryDirectory() as tmp:
        scene_path = os.path.join(tmp, "small.json")
        with open(scene_path, "w") as f:
            json.dump(SCENE, f)
        proc = subprocess.Popen(
            [server_exe, "--scene", scene_path, "--control", "tcp://127.0.0.1:*",
             "--stream", "tcp://127.0.0.1:*", "--quiet"],
            stdout=subprocess.PIPE, text=True)
        try:
            ready = json.loads(proc.stdout.readline())
            with Client(ready["control"], timeout_ms=20000) as c:
                hello = c.hello()
                assert hello["protocol"] == "polycut/1", hello
                assert hello["stream"] == ready["stream"], (hello, ready)
                loaded = c.call("load_scene", name="small")
                assert loaded["cell_count"] == 192, loaded
                mirror = c.surface_mirror()
                time.sleep(0.3)  # let the subscription settle while frames flow
                tris = np.array([[[-0.012, 0.003, 0.03], [-0.012, 0.003, 0.008], [0.012, 0.003, 0.03]],
                                 [[-0.012, 0.003, 0.008], [0.012, 0.003, 0.008], [0.012, 0.003, 0.03]]])
                cut = c.cut(tris, id="py-cut-1")
                assert cut["triangles"] == 2 and cut["topology_version"] > loaded["topology_version"], cut
                again = c.cut(tris, id="py-cut-1")  # a retry: answered from the cache
                assert again == cut, (again, cut)
                # Follow the stream until the frame that reflects the cut (its reply's tick).
                while mirror.header["tick"] < cut["tick"]:
                    assert mirror.update(timeout_ms=2000) > 0, "stream stalled"
                paused = c.call("pause")
                while mirror.header["tick"] < paused["tick"]:
                    assert mirror.update(timeout_ms=2000) > 0, "stream stalled"
                header, positions, triangles, tags = c.get_surface()
                assert mirror.header["seq"] == header["seq"], (mirror.header["seq"], header["seq"])
                assert np.array_equal(mirror.positions, positions)
                assert np.array_equal(mirror.triangles, triangles)
                assert np.count_nonzero(tags == 2) > 0, ("no cut-surface triangles", header, cut, loaded, paused)
                try:
                    c.call("grab", point=[0, 0], stiffness=100.0)
                    raise AssertionError("a 2-vector point was accepted")
                except RpcError as e:
                    assert e.code == -32602 and e.pointer == "/params/point", e
                c.call("shutdown")
            assert proc.wait(timeout=20) == 0
        finally:
            if proc.poll() is None:
                proc.kill()
    print("python client: ok")


if __name__ == "__main__":
    main()
