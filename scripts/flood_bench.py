#!/usr/bin/python3
"""Frame rate of a well-behaved subscriber while another client floods the server (issue 14
item 4): measures surface frames/s over a quiet window, then over the same window while a flood
client sends hostile messages as fast as it can (bad notifications, unknown methods, 200 kB
JSON frames, garbage), and prints both, the ratio and the server's drop counters.

    scripts/flood_bench.py POLYCUT_SERVER [SCENE.json] [--seconds S]
"""

import json
import os
import subprocess
import sys
import threading
import time

import zmq

HERE = os.path.dirname(os.path.abspath(__file__))


def frames_per_second(sub, seconds):
    while sub.poll(0):  # frames queued before the window do not count
        sub.recv_multipart()
    n, end = 0, time.monotonic() + seconds
    while time.monotonic() < end:
        if sub.poll(100):
            sub.recv_multipart()
            n += 1
    return n / seconds


def flood(endpoint, stop, sent):
    ctx = zmq.Context.instance()
    s = ctx.socket(zmq.DEALER)
    s.setsockopt(zmq.LINGER, 0)
    s.setsockopt(zmq.SNDHWM, 100000)
    s.connect(endpoint)
    big = json.dumps({"jsonrpc": "2.0", "id": 1, "method": "cut",
                      "params": {"triangles": [[[0.0, 0.0, 0.0]] * 3] * 2500}}).encode()
    msgs = [b'{"jsonrpc":"2.0","method":"apply_force","params":{"colour":1}}',
            b'{"jsonrpc":"2.0","id":5,"method":"no_such"}', big, b"\x00garbage{{{"]
    k = 0
    while not stop.is_set():
        try:
            s.send(msgs[k % len(msgs)], zmq.NOBLOCK)
            sent[0] += 1
        except zmq.Again:
            time.sleep(0.001)
        k += 1
        while s.poll(0):
            s.recv_multipart()


def main():
    exe = sys.argv[1]
    scene = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--") else \
        os.path.join(HERE, "..", "assets", "scenes", "default.json")
    seconds = float(sys.argv[sys.argv.index("--seconds") + 1]) if "--seconds" in sys.argv else 5.0
    proc = subprocess.Popen([exe, "--scene", scene, "--control", "tcp://127.0.0.1:*",
                             "--stream", "tcp://127.0.0.1:*", "--quiet"], stdout=subprocess.PIPE,
                            text=True)
    try:
        ready = json.loads(proc.stdout.readline())
        ctx = zmq.Context.instance()
        sub = ctx.socket(zmq.SUB)
        sub.connect(ready["stream"])
        sub.setsockopt(zmq.SUBSCRIBE, b"surface")
        time.sleep(0.5)
        quiet = frames_per_second(sub, seconds)
        stop, sent = threading.Event(), [0]
        t = threading.Thread(target=flood, args=(ready["control"], stop, sent))
        t.start()
        time.sleep(0.5)
        loud = frames_per_second(sub, seconds)
        stop.set()
        t.join()
        ctl = ctx.socket(zmq.DEALER)
        ctl.connect(ready["control"])
        ctl.send(b'{"jsonrpc":"2.0","id":1,"method":"get_stats"}')
        stats = json.loads(ctl.recv_multipart()[0])["result"]
        keys = ["busy", "errors", "events_coalesced", "events_suppressed", "replies_dropped",
                "stream_dropped", "ticks_over_budget", "worst_tick_ms"]
        print(json.dumps({"frames_per_s_quiet": round(quiet, 1),
                          "frames_per_s_flooded": round(loud, 1),
                          "ratio": round(loud / quiet, 3), "flood_messages": sent[0],
                          **{k: stats.get(k) for k in keys}}))
    finally:
        proc.terminate()
        proc.wait(timeout=10)


if __name__ == "__main__":
    main()
