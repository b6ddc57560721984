#!/usr/bin/python3
"""Soak: a live polycut-server under a mixed scripted load (issue 14 item 6).

    test_soak.py POLYCUT_SERVER SOURCE_DIR [--seconds S] [--json OUT]

One server (default scene, running at 60 Hz) for S seconds (default 100) of rounds of ~10 s.
Each round, from separate clients, all scripted with a fixed seed:
  - a scalpel stroke across the block (notifications at 60 Hz, end_stroke as a request);
  - a `cut` request of 2 to 40 sweep triangles through a random plane;
  - a grab pulled up and around with move_grab notifications, then released;
  - apply_force with a duration, and one removed early;
  - a hostile client: 300 bad messages (garbage, bad JSON, unknown methods, invalid params,
    wrong types, a NUL byte, 64 kB JSON, bad notifications, an oversize frame);
  - client churn: 20 fresh DEALER sockets that say hello and vanish;
  - every third round a reload (`load_scene` of the scene by name, built off the loop), the
    other rounds a `reset`.
A monitor client calls get_stats every 0.5 s (every call must be answered within 10 s) and
samples the server's RSS (/proc). A StreamReader (clients/python/polycut_live.py) reads every
stream message.

Asserted:
  - the server answers throughout (no get_stats without a reply, the process never exits) and
    exits 0 on `shutdown`;
  - no published non-finite value: every positions frame finite, every header number finite,
    no vertex further than 3 rest diagonals from the rest centre;
  - RSS flat after warm-up: RSS sampled right after each reload/reset (the scene fresh each
    time) from the third round on stays within max(8 MB, 8 %) of the third round's sample, and
    the peak RSS of the second half is within 25 % of the first half's peak (after warm-up).
Printed (one JSON line, also --json OUT): the tick figures from the stream (frame interval
p50/p99/max, achieved rate), get_stats (worst tick, ticks over budget, step p50/p99), RSS
samples, message counts, the server's drop counters.
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

REPO = os.path.abspath(sys.argv[2]) if len(sys.argv) > 2 else "."
sys.path.insert(0, os.path.join(REPO, "clients", "python"))
import polycut_live as live  # noqa: E402

ROUND_S = 10.0
LO = np.array([-0.05, -0.05, 0.0])  # the default scene's box [m]
HI = np.array([0.05, 0.05, 0.05])


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def percentile(values, q):
    return float(np.percentile(np.asarray(values, dtype=np.float64), q)) if values else None


class Script:
    """The scripted clients of one round, advanced by `tick(t)` at ~60 Hz."""

    def __init__(self, ctx, endpoint, server, seed):
        self.ctx = ctx
        self.endpoint = endpoint
        self.server = server
        self.rng = random.Random(seed)
        self.blade = live.Rpc(ctx, endpoint, server, name="soak-blade")
        self.hands = live.Rpc(ctx, endpoint, server, name="soak-hands")
        self.hostile = ctx.socket(zmq.DEALER)
        self.hostile.setsockopt(zmq.LINGER, 0)
        self.hostile.setsockopt(zmq.RCVHWM, 100000)
        self.hostile.connect(endpoint)
        self.counts = {"scalpel": 0, "cut": 0, "grab": 0, "move_grab": 0, "force": 0,
                       "bad": 0, "churn": 0, "reload": 0, "reset": 0}
        self.errors = {}  # method -> error codes seen (expected ones included)
        self.stroke = 0

    def note_error(self, method, e):
        self.errors.setdefault(method, {})
        code = str(e.error.get("code")) if isinstance(e, live.RpcError) else type(e).__name__
        self.errors[method][code] = self.errors[method].get(code, 0) + 1

    def drain_hostile(self):
        while True:
            try:
                self.hostile.recv_multipart(zmq.NOBLOCK)
            except zmq.Again:
                return

    # ---- pieces
    def stroke_samples(self):
        y = self.rng.uniform(-0.04, 0.04)
        depth = self.rng.uniform(0.01, 0.03)
        x0, x1 = -0.07, 0.07
        n = 60
        for k in range(n + 1):
            x = x0 + (x1 - x0) * k / n
            yield [x, y, 0.07], [x, y, 0.05 - depth]

    def cut_request(self):
        """2 to 40 sweep triangles: a strip in a random vertical plane through the block."""
        n = self.rng.randint(1, 20)
        angle = self.rng.uniform(0, math.pi)
        c = np.array([self.rng.uniform(-0.03, 0.03), self.rng.uniform(-0.03, 0.03)])
        d = np.array([math.cos(angle), math.sin(angle)])
        z_lo = self.rng.uniform(0.01, 0.04)
        tris = []
        for k in range(n):
            s0, s1 = -0.06 + 0.12 * k / n, -0.06 + 0.12 * (k + 1) / n
            p0, p1 = c + s0 * d, c + s1 * d
            a0, b0 = [*p0, 0.07], [*p0, z_lo]
            a1, b1 = [*p1, 0.07], [*p1, z_lo]
            tris += [[a0, b0, a1], [b0, b1, a1]]
        try:
            self.blade.call("cut", {"triangles": tris}, timeout=60)
        except live.RpcError as e:
            self.note_error("cut", e)
        self.counts["cut"] += 1

    def bad_burst(self, n=300):
        big = json.dumps({"jsonrpc": "2.0", "id": 1, "method": "cut",
                          "params": {"triangles": [[[0.0, 0.0, 0.0]] * 3] * 700}})
        samples = [
            [b"\xff\xfe garbage"],
            [b"{not json"],
            [b'{"jsonrpc":"2.0","id":3,"method":"no_such_method"}'],
            [b'{"jsonrpc":"2.0","method":"no_such_method"}'],
            [b'{"jsonrpc":"2.0","id":4,"method":"grab","params":{"point":[1e9,0,0]}}'],
            [b'{"jsonrpc":"2.0","id":5,"method":"apply_force","params":{"point":"x"}}'],
            [b'{"jsonrpc":"2.0","id":6,"method":"cut","params":{"triangles":[[[0,0,0],[0,0,0],[0,0,0]]]}}'],
            [b'{"jsonrpc":"2.0","method":"scalpel","params":{"stroke":1,"a":[NaN,0,0],"b":[0,0,0]}}'],
            [b'{"jsonrpc":"2.0","id":7,"method":"reset"}\x00garbage'],
            [b'{"jsonrpc":"2.0","id":8,"method":"move_grab","params":{"id":999999,"target":[0,0,0]}}'],
            [b'{"jsonrpc":"2.0","id":9,"method":"load_scene","params":{"name":"../../etc/passwd"}}'],
            [b'{"jsonrpc":"2.0","id":10,"method":"load_scene","params":{"scene":{"geometry":'
             b'{"type":"box","size":[1,1,1],"cells":[1000,1000,1000]}}}}'],
            [big.encode()],
            [b'{"jsonrpc":"2.0","id":11,"method":"get_stats"}', b"x" * 10],
            [b'{"jsonrpc":"2.0","id":12,"method":"set_rate","params":{"hz":-1}}'],
        ]
        for _ in range(n):
            try:
                self.hostile.send_multipart(self.rng.choice(samples), zmq.NOBLOCK)
            except zmq.Again:
                pass
            self.counts["bad"] += 1
        self.drain_hostile()

    def churn(self, n=20):
        for k in range(n):
            s = self.ctx.socket(zmq.DEALER)
            s.setsockopt(zmq.LINGER, 0)
            s.connect(self.endpoint)
            s.send(json.dumps({"jsonrpc": "2.0", "id": k, "method": "hello"}).encode())
            if k % 2 == 0 and s.poll(5000):
                s.recv_multipart()
            s.close(0)
            self.counts["churn"] += 1

    # ---- one round
    def round(self, index, stream, on_fresh_scene):
        t0 = time.monotonic()
        # Fresh scene: a reload (built off the loop) every third round, else a reset.
        if index % 3 == 2:
            self.hands.call("load_scene", {"name": "default"}, timeout=120)
            self.counts["reload"] += 1
        else:
            self.hands.call("reset", timeout=60)
            self.counts["reset"] += 1
        on_fresh_scene(index)
        # A grab pulled up and around during the stroke.
        grab = None
        try:
            point = [self.rng.uniform(-0.04, 0.04), self.rng.uniform(-0.04, 0.04), 0.05]
            grab = self.hands.call("grab", {"point": point, "radius": 0.01,
                                            "stiffness": 10 ** self.rng.uniform(1, 9)})["id"]
            self.counts["grab"] += 1
        except live.RpcError as e:
            self.note_error("grab", e)
        force = self.hands.call("apply_force", {"point": [0.0, 0.0, 0.05], "force": [0, 0, -2.0],
                                                "radius": 0.01, "duration": 1.0})["id"]
        self.counts["force"] += 1
        held = self.hands.call("apply_force", {"point": [0.03, 0.0, 0.05],
                                               "force": [0.5, 0, 0], "radius": 0.01})["id"]
        self.counts["force"] += 1
        # The stroke at 60 Hz with the grab moving.
        self.stroke += 1
        next_t = time.monotonic()
        for k, (a, b) in enumerate(self.stroke_samples()):
            self.blade.notify("scalpel", {"stroke": self.stroke, "a": a, "b": b})
            self.counts["scalpel"] += 1
            if grab is not None and k % 4 == 0:
                phase = 2 * math.pi * k / 60
                self.hands.notify("move_grab", {"id": grab, "target": [
                    0.01 * math.cos(phase), 0.01 * math.sin(phase), 0.05 + 0.01 * k / 60]})
                self.counts["move_grab"] += 1
            if k == 30:
                self.bad_burst()
            next_t += 1 / 60
            time.sleep(max(0.0, next_t - time.monotonic()))
        try:
            self.blade.call("end_stroke", {"stroke": self.stroke}, timeout=60)
        except live.RpcError as e:
            self.note_error("end_stroke", e)
        self.cut_request()
        for method, params in (("release", {"id": grab}), ("remove_force", {"id": held})):
            if params["id"] is None:
                continue
            try:
                self.hands.call(method, params)
            except live.RpcError as e:
                self.note_error(method, e)  # -32003 when a cut took the grabbed nodes away
        del force
        self.churn()
        self.bad_burst()
        # The rest of the round: the block settles, the monitor goes on.
        while time.monotonic() - t0 < ROUND_S:
            time.sleep(0.05)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("server")
    ap.add_argument("source_dir")
    ap.add_argument("--seconds", type=float, default=100.0)
    ap.add_argument("--json")
    args = ap.parse_args()

    scenes = os.path.join(args.source_dir, "assets", "scenes")
    stderr_path = tempfile.mktemp(prefix="polycut_soak_", suffix=".log")
    server = live.ServerProcess(args.server, ["--scene", os.path.join(scenes, "default.json"),
                                              "--scene-dir", scenes, "--rate", "60"],
                                stderr_path=stderr_path)
    ready = server.start()
    ctx = zmq.Context.instance()
    stream = live.StreamReader(ctx, ready["stream"])
    stream.start()
    diag = float(np.linalg.norm(HI - LO))
    stream.set_bound((LO + HI) / 2, 3 * diag)
    monitor = live.Rpc(ctx, ready["control"], server, name="soak-monitor")
    script = Script(ctx, ready["control"], server, seed=14)

    import threading
    rss, stats_latency, unanswered, fresh_rss = [], [], [], {}
    done = threading.Event()

    def watch():
        mon_ctx = zmq.Context()
        rpc = live.Rpc(mon_ctx, ready["control"], server, name="soak-watch")
        t_start = time.monotonic()
        while not done.is_set():
            t = time.monotonic()
            try:
                rpc.call("get_stats", timeout=10)
                stats_latency.append((time.monotonic() - t) * 1000)
            except (live.RpcTimeout, live.RpcError, live.ServerDied) as e:
                unanswered.append(f"{t - t_start:.1f} s: {e}")
                if server.exited():
                    break
            rss.append((t - t_start, rss_mb(server.proc.pid)))
            done.wait(max(0.0, 0.5 - (time.monotonic() - t)))
        rpc.close()
        mon_ctx.term()

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    t_start = time.monotonic()

    def on_fresh_scene(index):
        time.sleep(0.3)  # the freed memory is back (malloc_trim runs on install)
        fresh_rss[index] = rss_mb(server.proc.pid)

    rounds = max(3, int(args.seconds // ROUND_S))
    failure = None
    try:
        for index in range(rounds):
            script.round(index, stream, on_fresh_scene)
    except (live.RpcTimeout, live.RpcError, live.ServerDied) as e:
        failure = f"round {index}: {type(e).__name__}: {e}"
    elapsed = time.monotonic() - t_start
    final = None
    try:
        final = monitor.call("get_stats", timeout=10)
        monitor.call("shutdown", timeout=10)
    except (live.RpcTimeout, live.RpcError, live.ServerDied) as e:
        failure = failure or f"final get_stats/shutdown: {e}"
    done.set()
    watcher.join(timeout=15)
    status = server.stop(timeout=15)
    stream.stop()

    frames = stream.frames
    times = [f["t"] for f in frames]
    intervals = list(np.diff(times) * 1000) if len(times) > 1 else []
    non_finite = sum(1 for f in frames if not f["finite"])
    exploded = sum(1 for f in frames if f["max_dist"] is not None and f["max_dist"] > 3 * diag)
    bad_numbers = sum(1 for f in frames if f["step_ms"] is not None
                      and not math.isfinite(f["step_ms"]))
    warm = sorted(k for k in fresh_rss if k >= 2)
    ref = fresh_rss[warm[0]] if warm else float("nan")
    fresh_tol = max(8.0, 0.08 * ref)
    half = elapsed / 2
    after_warm = [m for t, m in rss if t >= ROUND_S * 2]
    first_half = [m for t, m in rss if ROUND_S * 2 <= t < half] or after_warm
    second_half = [m for t, m in rss if t >= half]
    report = {
        "seconds": round(elapsed, 1), "rounds": rounds, "loadavg_1min": os.getloadavg()[0],
        "messages": script.counts, "errors_seen": script.errors,
        "frames": len(frames), "rate_hz": len(frames) / elapsed if elapsed else None,
        "seq_gaps": len(stream.seq_gaps),
        "frame_interval_ms": {"p50": percentile(intervals, 50), "p99": percentile(intervals, 99),
                              "max": max(intervals) if intervals else None},
        "step_ms": {"p50": percentile([f["step_ms"] for f in frames if f["step_ms"]], 50),
                    "p99": percentile([f["step_ms"] for f in frames if f["step_ms"]], 99)},
        "get_stats_ms": {"p50": percentile(stats_latency, 50),
                         "p99": percentile(stats_latency, 99),
                         "max": max(stats_latency) if stats_latency else None,
                         "calls": len(stats_latency)},
        "rss_mb_fresh": {str(k): round(v, 1) for k, v in sorted(fresh_rss.items())},
        "rss_mb": {"warm_first_half_max": max(first_half) if first_half else None,
                   "second_half_max": max(second_half) if second_half else None,
                   "max": max(m for _, m in rss) if rss else None},
        "rss_bound_mb": round(fresh_tol, 1),
        "server": {k: final.get(k) for k in (
            "tick", "worst_tick_ms", "ticks_over_budget", "step_ms_p50", "step_ms_p99",
            "requests", "errors", "busy", "stream_dropped", "replies_dropped",
            "events_coalesced", "events_suppressed", "clients", "client_states")}
        if final else None,
        "exit_status": status, "non_finite_frames": non_finite, "exploded_frames": exploded,
        "stream_errors": stream.errors[:5], "unanswered": unanswered[:5],
    }
    print(json.dumps(report))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1)

    problems = []
    if failure:
        problems.append(failure)
    if unanswered:
        problems.append(f"{len(unanswered)} get_stats unanswered: {unanswered[:3]}")
    if status != 0:
        problems.append(f"exit status {status}; stderr tail: {server.stderr_text()[-2000:]}")
    if non_finite or exploded or bad_numbers or stream.errors:
        problems.append(f"non-finite {non_finite}, exploded {exploded}, bad numbers "
                        f"{bad_numbers}, malformed {stream.errors[:3]}")
    if len(frames) < 0.25 * 60 * elapsed:
        problems.append(f"only {len(frames)} frames in {elapsed:.0f} s")
    for k in warm:
        if abs(fresh_rss[k] - ref) > fresh_tol:
            problems.append(f"RSS after the fresh scene of round {k}: {fresh_rss[k]:.1f} MB, "
                            f"round {warm[0]}: {ref:.1f} MB (bound {fresh_tol:.1f} MB)")
    if first_half and second_half and max(second_half) > 1.25 * max(first_half):
        problems.append(f"RSS peak grew: {max(first_half):.1f} -> {max(second_half):.1f} MB")
    if problems:
        print("soak FAILED:\n  " + "\n  ".join(problems))
        sys.exit(1)
    print("soak: ok")
    try:
        os.remove(stderr_path)
    except OSError:
        pass


if __name__ == "__main__":
    main()
