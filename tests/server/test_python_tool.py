#!/usr/bin/python3
"""A client written from docs/protocol.md alone (raw pyzmq, no polycut library) presses the tissue
with a tool through a polycut-server subprocess (issue 15): tool_create, tool_move notifications
at 120 Hz while the server ticks at 60 Hz, the reaction force read back from the stream headers
and get_stats, tool_remove. Asserts that the probe is pushed back up (force z > 0), that the
force grows as it goes deeper, that the stream and get_stats agree on the last frame, and that
a bad tool request is refused with its pointer.

    test_python_tool.py POLYCUT_SERVER
"""

import json
import os
import subprocess
import sys
import tempfile
import time

import zmq

SCENE = {
    "name": "press",
    "geometry": {"type": "box", "origin": [-0.02, -0.02, 0], "size": [0.04, 0.04, 0.02],
                 "cells": [8, 8, 4], "elements": "tet"},
    "method": "tet",
    "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.4, "density": 1000,
                 "rayleigh_stiffness": 0.02},
    "integrator": {"type": "implicit_euler", "dt": 0.0166667, "corotated": True},
    "solver": {"type": "pcg", "preconditioner": "block_jacobi", "tolerance": 1e-8},
    "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
}


def main():
    server_exe = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        scene_path = os.path.join(tmp, "press.json")
        with open(scene_path, "w") as f:
            json.dump(SCENE, f)
        proc = subprocess.Popen(
            [server_exe, "--scene", scene_path, "--control", "tcp://127.0.0.1:*",
             "--stream", "tcp://127.0.0.1:*", "--quiet"],
            stdout=subprocess.PIPE, text=True)
        try:
            ready = json.loads(proc.stdout.readline())
            ctx = zmq.Context()
            ctl = ctx.socket(zmq.DEALER)
            ctl.setsockopt(zmq.LINGER, 0)
            ctl.connect(ready["control"])
            next_id = [0]

            def call(method, params):
                next_id[0] += 1
                ctl.send_multipart([json.dumps({"jsonrpc": "2.0", "id": next_id[0],
                                                "method": method, "params": params}).encode()])
                assert ctl.poll(20000), method
                reply, *_ = ctl.recv_multipart()
                return json.loads(reply)

            def notify(method, params):
                ctl.send_multipart([json.dumps({"jsonrpc": "2.0", "method": method,
                                                "params": params}).encode()])

            hello = call("hello", {"client": "tool-test"})["result"]
            assert "tool_create" in hello["capabilities"], hello["capabilities"]
            sub = ctx.socket(zmq.SUB)
            sub.setsockopt(zmq.LINGER, 0)
            sub.connect(hello["stream"])
            sub.setsockopt(zmq.SUBSCRIBE, b"surface")
            call("resume", {})
            time.sleep(0.3)

            # A 6 mm ball just above the top (z = 0.02), then down 3 mm over 1.5 s at 120 Hz.
            created = call("tool_create", {"shape": "sphere", "radius": 0.006,
                                           "position": [0.0, 0.0, 0.0265], "stiffness": 1e8})
            tool = created["result"]["id"]
            forces = []
            start = time.monotonic()
            for k in range(181):
                z = 0.0265 - 0.0035 * min(k / 180.0, 1.0)
                notify("tool_move", {"id": tool, "position": [0.0, 0.0, z]})
                while sub.poll(0):
                    _, header, *_ = sub.recv_multipart()
                    h = json.loads(header)
                    for c in h.get("contacts", []):
                        if c["kind"] == "tool" and c["id"] == tool:
                            forces.append((h["tick"], c["force"][2]))
                time.sleep(max(0.0, start + (k + 1) / 120.0 - time.monotonic()))
            time.sleep(1.0)  # settle at the last pose
            call("pause", {})
            stats = call("get_stats", {})["result"]
            (report,) = [c for c in stats["contacts"] if c["kind"] == "tool"]
            assert report["id"] == tool and report["points"] > 0, report
            assert report["force"][2] > 0.05, report  # the tissue pushes the probe up [N]
            early = [f for t, f in forces if f > 0][:5]
            assert early and report["force"][2] > 2 * max(early), (early, report)
            # The last frame of the stream (the paused tick) carries the same report.
            last = None
            while sub.poll(200):
                _, header, *_ = sub.recv_multipart()
                last = json.loads(header)
            if last is not None and last["tick"] == stats["tick"]:
                (c,) = [c for c in last["contacts"] if c["kind"] == "tool"]
                assert c == report, (c, report)
            bad = call("tool_create", {"shape": "blade", "size": [0.01, 0.0, 0.01],
                                       "position": [0, 0, 0.05]})
            assert bad["error"]["code"] == -32602, bad
            assert bad["error"]["data"]["pointer"] == "/params/size/1", bad
            assert call("tool_remove", {"id": tool})["result"]["tick"] >= stats["tick"]
            call("shutdown", {})
            assert proc.wait(timeout=20) == 0
            print(f"probe reaction {report['force'][2]:.3f} N at {report['points']} samples, "
                  f"first contact {early[0]:.4f} N")
        finally:
            if proc.poll() is None:
                proc.kill()


if __name__ == "__main__":
    main()
