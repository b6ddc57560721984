#!/usr/bin/python3
"""Ticks while a large `cut` request runs (issue 14 item 1): one polycut-server per (cutter,
shape, T), the default scene at 60 Hz; a subscriber reads every frame from before the request
until the cut is done (the reply, then no `cut_deferred` left) and one second more. Prints per
run: the reply's wall time, the ticks the cut took, the worst frame interval and step_ms of the
stream during the cut, get_stats' worst tick, and the cut's completion state.

    scripts/cut_load_bench.py POLYCUT_SERVER [--sizes 500,2000,4000] [--cutters snap,split]
        [--shapes stroke,random] [--scene SCENE.json] [--json OUT] [--record-dir DIR]

Shapes: `stroke` = a coherent quarter-circle stroke through the block (T/2 samples, 2
triangles each, down to 2 cm deep); `random` = T random triangles of ~1 cm in the block.
With --scene (instead of assets/scenes/default.json, the 10 x 10 x 5 cm block) the shapes are
placed by the affine map of the block's box onto the scene's bounding box (get_surface's
positions before the cut), so the same cut runs through an organ. Also per run: the frame
rate and the worst step over the second after the cut is done (a cut that leaves a model the
tick cannot step slows every subscriber for good).
"""

import argparse
import json
import math
import os
import random
import sys
import tempfile
import time

import numpy as np
import zmq

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "clients", "python"))
import polycut_live as live  # noqa: E402


def stroke(T):
    n = max(1, T // 2)
    tris = []
    prev = None
    for k in range(n + 1):
        phi = 0.5 * math.pi * k / n
        x, y = -0.04 + 0.08 * math.sin(phi), -0.04 + 0.08 * (1 - math.cos(phi))
        a, b = [x, y, 0.07], [x, y, 0.03]
        if prev is not None:
            pa, pb = prev
            tris += [[pa, pb, a], [pb, b, a]]
        prev = (a, b)
    return tris[:T]


def random_tris(T, seed=1):
    rng = random.Random(seed)
    tris = []
    for _ in range(T):
        c = [rng.uniform(-0.045, 0.045), rng.uniform(-0.045, 0.045), rng.uniform(0.005, 0.045)]
        tris.append([[c[i] + rng.uniform(-0.006, 0.006) for i in range(3)] for _ in range(3)])
    return tris


# The default block's box, in which the shapes above are drawn [m].
BLOCK_LO = np.array([-0.05, -0.05, 0.0])
BLOCK_SIZE = np.array([0.1, 0.1, 0.05])


def placed(tris, lo, hi):
    """The triangles moved from the default block's box onto the box [lo, hi]."""
    scale = (np.asarray(hi) - np.asarray(lo)) / BLOCK_SIZE
    return [[list(np.asarray(lo) + (np.asarray(p) - BLOCK_LO) * scale) for p in t] for t in tris]


def run(exe, scene_path, cutter, shape, T, record_dir=None, place=False):
    extra = []
    if record_dir:
        # a command log per case, for `polycut-server --replay LOG --trace`
        extra = ["--record-commands", os.path.join(record_dir, f"{cutter}_{shape}_{T}.log")]
    server = live.ServerProcess(exe, ["--scene", scene_path, "--rate", "60", "--quiet"] + extra)
    ready = server.start()
    ctx = zmq.Context.instance()
    sub = ctx.socket(zmq.SUB)
    sub.setsockopt(zmq.RCVHWM, 1000000)
    sub.setsockopt(zmq.SUBSCRIBE, b"surface")
    sub.connect(ready["stream"])
    rpc = live.Rpc(ctx, ready["control"], server, name="cut-bench")
    time.sleep(0.5)
    while sub.poll(0):
        sub.recv_multipart()
    tris = stroke(T) if shape == "stroke" else random_tris(T)
    if place:
        at = rpc.get_surface(timeout=120)["positions"]
        tris = placed(tris, at.min(axis=0), at.max(axis=0))
        while sub.poll(0):
            sub.recv_multipart()
    t0 = time.perf_counter()
    # Bulk arrays go in a binary frame (docs/protocol.md, Messages and frames).
    data = np.asarray(tris, dtype="<f4")
    rid = rpc.send("cut", {"triangles": {"$frame": 1, "dtype": "float32",
                                         "shape": list(data.shape)}}, frames=[data.tobytes()])
    reply = None
    frames = []  # (recv time, tick, step_ms, cut_deferred)
    done_t = None
    deadline = time.monotonic() + 600
    while time.monotonic() < deadline:
        if reply is None and rpc.sock.poll(0):
            reply = json.loads(rpc.sock.recv_multipart()[0])
            reply_s = time.perf_counter() - t0
        if sub.poll(20):
            msg = sub.recv_multipart()
            h = json.loads(msg[1])
            frames.append((time.perf_counter(), h["tick"], (h.get("step") or {}).get("step_ms"),
                           h.get("cut_deferred", 0)))
            if reply is not None and h.get("cut_deferred", 0) == 0 and done_t is None:
                done_t = time.perf_counter()
        if done_t is not None and time.perf_counter() - done_t > 1.0:
            break
    stats = rpc.call("get_stats")
    rpc.call("shutdown")
    server.stop()
    sub.close(0)
    rpc.close()
    during = [f for f in frames if done_t is None or f[0] <= done_t]
    after = [f for f in frames if done_t is not None and f[0] > done_t]
    gaps = [1000 * (b[0] - a[0]) for a, b in zip(during, during[1:])]
    deferred_ticks = sum(1 for f in during if f[3] > 0)
    res = reply.get("result") if reply else None
    return {
        "cutter": cutter, "shape": shape, "T": T, "loadavg_1min": os.getloadavg()[0],
        "reply_ms": round(reply_s * 1000, 1) if reply else None,
        "error": reply.get("error") if reply else "no reply",
        "applied_first_tick": res["triangles"] if res else None,
        "deferred_at_reply": res.get("deferred") if res else None,
        "ticks_with_deferred": deferred_ticks,
        "done_ms": round(1000 * (done_t - t0), 1) if done_t else None,
        "frame_gap_ms_max": round(max(gaps), 1) if gaps else None,
        "frame_gap_ms_p99": round(float(np.percentile(gaps, 99)), 1) if gaps else None,
        "step_ms_max": max((f[2] or 0) for f in during) if during else None,
        "worst_tick_ms": stats["worst_tick_ms"], "ticks_over_budget": stats["ticks_over_budget"],
        "after_frames_per_s": round(len(after) / (after[-1][0] - done_t), 1) if after else None,
        "after_step_ms_max": round(max((f[2] or 0) for f in after), 1) if after else None,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("server")
    ap.add_argument("--sizes", default="500,2000,4000")
    ap.add_argument("--cutters", default="snap,split")
    ap.add_argument("--shapes", default="stroke,random")
    ap.add_argument("--json")
    ap.add_argument("--record-dir", help="write each case's command log here (for --replay)")
    ap.add_argument("--scene", help="scene file instead of the default block")
    args = ap.parse_args()
    base = json.load(open(args.scene or os.path.join(HERE, "..", "assets", "scenes",
                                                     "default.json")))
    out = []
    tmp = tempfile.mkdtemp(prefix="polycut_cutbench_")
    for cutter in args.cutters.split(","):
        scene = json.loads(json.dumps(base))
        if cutter == "split":
            scene["method"] = "mvc"
        # the scene's own cut settings (its budget) stay; only the cutter is chosen
        scene["cutting"] = dict(scene.get("cutting", {}), method=cutter)
        path = os.path.join(tmp, f"{cutter}.json")
        with open(path, "w") as f:
            json.dump(scene, f)
        for shape in args.shapes.split(","):
            for T in (int(t) for t in args.sizes.split(",")):
                r = run(args.server, path, cutter, shape, T, args.record_dir,
                        place=args.scene is not None)
                print(json.dumps(r), flush=True)
                out.append(r)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
