#!/usr/bin/python3
"""Pieces for driving a live polycut-server from Python, written from docs/protocol.md alone.

- `ServerProcess`: starts polycut-server on ephemeral loopback ports, reads the endpoints it
  prints, keeps its stderr in a file, stops it.
- `Rpc`: JSON-RPC 2.0 over a DEALER socket, with a timeout that also notices a dead server.
- `StreamReader`: a thread that reads every stream message (surface frames and events) from the
  start and checks each positions frame (finite, within a bound of a centre), `seq` continuity
  and that a topology change carries its arrays.
- geometry: triangle areas, the area of a triangle inside a box (exact clipping) and inside a
  closed triangle surface (exact plane section), used to score cuts.

Python 3 with python3-zmq and python3-numpy (Debian packages) only.
"""

import json
import os
import queue
import signal
import subprocess
import threading
import time

import numpy as np
import zmq

PROTOCOL = "polycut/1"


class ServerDied(RuntimeError):
    """The server process exited (or never started)."""


class RpcTimeout(RuntimeError):
    """No reply within the timeout while the server process was still running."""


class RpcError(RuntimeError):
    """A JSON-RPC error reply."""

    def __init__(self, method, error):
        self.method = method
        self.error = error
        self.code = error.get("code")
        data = error.get("data") or {}
        self.pointer = data.get("pointer")
        self.reason = data.get("reason")
        super().__init__(f"{method}: {self.code} {error.get('message')} at "
                         f"{self.pointer!r}: {self.reason}")


# --------------------------------------------------------------------------------------------
# The server process


class ServerProcess:
    """polycut-server on `tcp://127.0.0.1:*` ports (docs/server.md): once both sockets are
    bound it prints one JSON line with the endpoints on stdout; stderr goes to `stderr_path`."""

    def __init__(self, binary, args=(), stderr_path=None, start_timeout=300.0):
        self.binary = binary
        self.args = list(args)
        self.stderr_path = stderr_path
        self.start_timeout = start_timeout
        self.proc = None
        self.ready = None
        self._stdout_lines = queue.Queue()
        self._stderr_file = None

    def start(self):
        cmd = [self.binary, "--control", "tcp://127.0.0.1:*", "--stream", "tcp://127.0.0.1:*",
               *self.args]
        self._stderr_file = open(self.stderr_path, "wb") if self.stderr_path else subprocess.DEVNULL
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=self._stderr_file)
        threading.Thread(target=self._drain_stdout, daemon=True).start()
        deadline = time.monotonic() + self.start_timeout
        while True:
            try:
                line = self._stdout_lines.get(timeout=0.1)
            except queue.Empty:
                line = None
            if line is not None:
                try:
                    ready = json.loads(line)
                except ValueError:
                    continue  # not the endpoint line
                if isinstance(ready, dict) and "control" in ready:
                    self.ready = ready
                    return ready
            if self.proc.poll() is not None and self._stdout_lines.empty():
                raise ServerDied(f"polycut-server exited with status {self.proc.returncode} "
                                 f"before printing its endpoints")
            if time.monotonic() > deadline:
                raise ServerDied("polycut-server did not print its endpoints within "
                                 f"{self.start_timeout:.0f} s")

    def _drain_stdout(self):
        for raw in self.proc.stdout:
            self._stdout_lines.put(raw.decode("utf-8", "replace"))

    def exited(self):
        return self.proc is None or self.proc.poll() is not None

    def returncode(self):
        return None if self.proc is None else self.proc.poll()

    def stop(self, timeout=10.0):
        """Waits up to `timeout` for the process to exit, then SIGTERM, then SIGKILL. Returns the
        exit status."""
        if self.proc is None:
            return None
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            pass
        self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(timeout=5.0)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return self.proc.wait()
        finally:
            self.close_files()

    def close_files(self):
        if self._stderr_file not in (None, subprocess.DEVNULL):
            self._stderr_file.close()
            self._stderr_file = None

    def stderr_text(self):
        if not self.stderr_path or not os.path.exists(self.stderr_path):
            return ""
        with open(self.stderr_path, "rb") as f:
            return f.read().decode("utf-8", "replace")


# --------------------------------------------------------------------------------------------
# Control channel


def decode_array(ref, frames, first_binary):
    """A frame reference {"$frame", "dtype", "shape"} (docs/protocol.md, Messages and frames) to
    a numpy array. `frames[first_binary]` is the frame with $frame = 1."""
    dtype = {"float32": "<f4", "uint32": "<u4", "uint8": "u1"}[ref["dtype"]]
    data = frames[first_binary + ref["$frame"] - 1]
    return np.frombuffer(data, dtype=dtype).reshape(ref["shape"])


class Rpc:
    """JSON-RPC over a DEALER (several requests may be in flight; replies matched by id)."""

    def __init__(self, ctx, endpoint, server=None, name="polycut-incision"):
        self.sock = ctx.socket(zmq.DEALER)
        self.sock.setsockopt(zmq.LINGER, 0)
        self.sock.setsockopt(zmq.ROUTING_ID, f"{name}-{os.getpid()}-{id(self)}".encode())
        self.sock.connect(endpoint)
        self.server = server
        self.next_id = 0
        self.replies = {}
        self.sent = 0

    def close(self):
        self.sock.close(0)

    def send(self, method, params=None, frames=(), notify=False):
        msg = {"jsonrpc": "2.0", "method": method, "params": params or {}}
        rid = None
        if not notify:
            self.next_id += 1
            rid = self.next_id
            msg["id"] = rid
        self.sock.send_multipart([json.dumps(msg).encode(), *frames])
        self.sent += 1
        return rid

    def notify(self, method, params=None):
        self.send(method, params, notify=True)

    def wait(self, rid, method="?", timeout=30.0):
        """The reply (result, binary frames) to request `rid`; raises RpcError, RpcTimeout or
        ServerDied."""
        deadline = time.monotonic() + timeout
        while rid not in self.replies:
            if self.sock.poll(100):
                frames = self.sock.recv_multipart()
                reply = json.loads(frames[0])
                self.replies[reply.get("id")] = (reply, frames)
                continue
            if self.server is not None and self.server.exited():
                raise ServerDied(f"{method}: polycut-server exited with status "
                                 f"{self.server.returncode()}")
            if time.monotonic() > deadline:
                raise RpcTimeout(f"{method}: no reply within {timeout:.0f} s")
        reply, frames = self.replies.pop(rid)
        if "error" in reply:
            raise RpcError(method, reply["error"])
        return reply["result"], frames

    def call(self, method, params=None, timeout=30.0, frames=()):
        result, _ = self.wait(self.send(method, params, frames), method, timeout)
        return result

    def get_surface(self, timeout=30.0):
        result, frames = self.wait(self.send("get_surface"), "get_surface", timeout)
        surf = dict(result)
        surf["positions"] = decode_array(result["positions"], frames, 1).astype(np.float64)
        surf["triangles"] = decode_array(result["triangles"], frames, 1).astype(np.int64)
        surf["tags"] = decode_array(result["tags"], frames, 1)
        return surf


# --------------------------------------------------------------------------------------------
# Stream


KNOWN_HEADER = {"seq", "tick", "sim_time", "topology_version", "vertex_count", "triangle_count",
                "has_topology", "step", "applied", "positions", "triangles", "tags"}
KNOWN_STEP = {"step_ms", "solver_iterations", "residual", "warnings"}


class StreamReader(threading.Thread):
    """Reads every message of the PUB socket (topics `surface` and `event`) in a thread.

    Per surface frame it keeps (seq, tick, topology_version, has_topology, receive time,
    step_ms, solver_iterations, finite, max distance from the centre); it counts seq gaps and
    topology changes without arrays, and keeps the latest surface (positions, triangles, tags).
    Frames received before `set_bound` are checked when it is called."""

    def __init__(self, ctx, endpoint):
        super().__init__(daemon=True)
        self.sock = ctx.socket(zmq.SUB)
        self.sock.setsockopt(zmq.LINGER, 0)
        self.sock.setsockopt(zmq.RCVHWM, 1000000)
        self.sock.setsockopt(zmq.SUBSCRIBE, b"")
        self.sock.connect(endpoint)
        self.lock = threading.Lock()
        self.stop_flag = threading.Event()
        self.frames = []  # dicts, see _on_surface
        self.events = []  # (recv_time, event dict)
        self.seq_gaps = []  # (previous seq, seq)
        self.topology_without_arrays = 0
        self.extra_header = {}  # unknown header members: name -> last value
        self.extra_step = {}
        self.latest = None  # (positions float64 V x 3, triangles, tags, topology_version, tick)
        self.centre = None
        self.bound = None
        self._pending = []  # (frame dict, positions) waiting for set_bound
        self._triangles = None
        self._tags = None
        self._held_tv = None
        self.errors = []

    def set_bound(self, centre, bound):
        with self.lock:
            self.centre = np.asarray(centre, dtype=np.float64)
            self.bound = float(bound)
            for rec, pos in self._pending:
                rec["max_dist"] = self._max_dist(pos)
            self._pending = []

    def seed(self, surface):
        """Takes the topology of a get_surface snapshot (docs/protocol.md, Late joiners: the
        snapshot, then the frames with a later seq; a frame without arrays reuses the latest
        triangles and tags)."""
        with self.lock:
            if self._held_tv is None or surface["topology_version"] >= self._held_tv:
                self._triangles = surface["triangles"]
                self._tags = surface["tags"]
                self._held_tv = surface["topology_version"]
            if self.latest is None:
                self.latest = (surface["positions"], self._triangles, self._tags,
                               surface["topology_version"], surface["tick"])

    def _max_dist(self, pos):
        if pos.size == 0:
            return 0.0
        finite = np.isfinite(pos).all(axis=1)
        if not finite.any():
            return float("inf")
        d = pos[finite] - self.centre
        return float(np.sqrt(np.max(np.einsum("ij,ij->i", d, d))))

    def run(self):
        poller = zmq.Poller()
        poller.register(self.sock, zmq.POLLIN)
        while not self.stop_flag.is_set():
            if not poller.poll(50):
                continue
            while True:
                try:
                    msg = self.sock.recv_multipart(zmq.NOBLOCK)
                except zmq.Again:
                    break
                now = time.perf_counter()
                try:
                    if msg[0] == b"surface":
                        self._on_surface(msg, now)
                    elif msg[0] == b"event":
                        self.events.append((now, json.loads(msg[1])))
                except Exception as e:  # a malformed message is a finding, not a crash
                    self.errors.append(f"{type(e).__name__}: {e}")
        self.sock.close(0)

    def _on_surface(self, msg, now):
        h = json.loads(msg[1])
        pos = decode_array(h["positions"], msg, 2).astype(np.float64)
        step = h.get("step") or {}
        finite = bool(np.isfinite(pos).all())
        rec = {"seq": h["seq"], "tick": h["tick"], "tv": h["topology_version"],
               "has_topology": bool(h.get("has_topology")), "t": now,
               "step_ms": step.get("step_ms"), "iterations": step.get("solver_iterations"),
               "warnings": len(step.get("warnings") or []), "finite": finite,
               "vertex_count": h["vertex_count"], "applied": len(h.get("applied") or []),
               "cut_deferred": int(h.get("cut_deferred") or 0)}
        for k, v in h.items():
            if k not in KNOWN_HEADER:
                self.extra_header[k] = v
                rec.setdefault("extra", {})[k] = v
        for k, v in step.items():
            if k not in KNOWN_STEP:
                self.extra_step[k] = v
                rec.setdefault("extra_step", {})[k] = v
        with self.lock:
            if self.frames:
                prev = self.frames[-1]["seq"]
                if h["seq"] != prev + 1:
                    self.seq_gaps.append((prev, h["seq"]))
            if h.get("has_topology"):
                self._triangles = decode_array(h["triangles"], msg, 2).astype(np.int64)
                self._tags = decode_array(h["tags"], msg, 2)
                self._held_tv = h["topology_version"]
            elif self._held_tv is not None and h["topology_version"] != self._held_tv:
                self.topology_without_arrays += 1
            if self.centre is None:
                rec["max_dist"] = None
                self._pending.append((rec, pos))
            else:
                rec["max_dist"] = self._max_dist(pos)
            self.frames.append(rec)
            if self._triangles is not None and h["topology_version"] == self._held_tv:
                self.latest = (pos, self._triangles, self._tags, h["topology_version"], h["tick"])

    def mark(self):
        """(number of frames received, last tick, last topology_version, now) at this moment."""
        with self.lock:
            if self.frames:
                f = self.frames[-1]
                return len(self.frames), f["tick"], f["tv"], time.perf_counter()
            return 0, None, None, time.perf_counter()

    def wait_tick(self, tick, timeout, server=None, cut_done=False):
        """Waits for a surface frame with tick >= `tick` (a reply's `tick` is the first tick
        whose frame reflects the command); with `cut_done`, also with no sweep triangles left
        to later ticks by the cut budget (header `cut_deferred` 0: an `end_stroke` that
        replied `deferred` > 0 is finished then). Returns False on timeout."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                if self.frames and self.frames[-1]["tick"] >= tick and (
                        not cut_done or self.frames[-1]["cut_deferred"] == 0):
                    return True
            if server is not None and server.exited():
                raise ServerDied(f"polycut-server exited with status {server.returncode()}")
            time.sleep(0.005)
        return False

    def latest_surface(self):
        with self.lock:
            return self.latest

    def stop(self):
        self.stop_flag.set()
        self.join(timeout=5.0)


# --------------------------------------------------------------------------------------------
# Geometry


def triangle_areas(positions, triangles):
    p = positions[triangles]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)


def tagged_area(surface, tag):
    sel = surface["tags"] == tag
    if not sel.any():
        return 0.0
    return float(triangle_areas(surface["positions"], surface["triangles"][sel]).sum())


def _polygon_area(poly):
    if len(poly) < 3:
        return 0.0
    p = np.asarray(poly)
    s = np.zeros(3)
    for i in range(1, len(p) - 1):
        s += np.cross(p[i] - p[0], p[i + 1] - p[0])
    return 0.5 * float(np.linalg.norm(s))


def area_in_box(tri, lo, hi, eps=1e-9):
    """Area of the triangle (3 x 3) strictly inside the box [lo, hi]: the triangle clipped to
    the box shrunk by `eps` on every side (so a triangle lying in a face of the box counts 0)."""
    poly = [np.asarray(p, dtype=np.float64) for p in tri]
    for axis in range(3):
        for sign, bound in ((1.0, lo[axis] + eps), (-1.0, hi[axis] - eps)):
            out = []
            n = len(poly)
            for i in range(n):
                p, q = poly[i], poly[(i + 1) % n]
                fp, fq = sign * (p[axis] - bound), sign * (q[axis] - bound)
                if fp >= 0:
                    out.append(p)
                if (fp >= 0) != (fq >= 0):
                    out.append(p + (q - p) * (fp / (fp - fq)))
            poly = out
            if not poly:
                return 0.0
    return _polygon_area(poly)


def area_in_surface(tri, V, F):
    """Area of the planar triangle `tri` (3 x 3) strictly inside the closed, outward-oriented
    triangle surface (V, F), exactly (up to rounding): the surface's section by the triangle's
    plane gives oriented segments (material on their left); the area of (section region) ∩
    triangle is 1/2 ∮ (u dv - v du) over the segment parts inside the triangle plus the parts of
    the triangle's edges inside the section (found by a parity test). Surface vertices lying in
    the plane are put on one side, then on the other; the smaller area is the one strictly
    inside (a triangle lying in a face of the surface counts 0, not its whole area)."""
    return min(_area_in_surface(tri, V, F, False), _area_in_surface(tri, V, F, True))


def _area_in_surface(tri, V, F, ties_positive):
    a, b, c = (np.asarray(p, dtype=np.float64) for p in tri)
    n = np.cross(b - a, c - a)
    nn = np.linalg.norm(n)
    if nn == 0:
        return 0.0
    n /= nn
    e1 = (b - a) / np.linalg.norm(b - a)
    e2 = np.cross(n, e1)
    s = (V - a) @ n
    pos = s >= 0 if ties_positive else s > 0  # a vertex in the plane goes to one side
    P = pos[F]
    cnt = P.sum(axis=1)
    mixed = (cnt == 1) | (cnt == 2)
    Fm = F[mixed]
    Pm = P[mixed]
    if len(Fm) == 0:
        # No crossing: the triangle is inside iff its centroid is (no boundary in the plane).
        return 0.0
    Vm = V[Fm]  # M x 3 x 3
    Sm = s[Fm]  # M x 3
    ch = np.stack([Pm[:, 0] != Pm[:, 1], Pm[:, 1] != Pm[:, 2], Pm[:, 2] != Pm[:, 0]], axis=1)
    pts = np.empty((len(Fm), 3, 3))
    for k, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
        si, sj = Sm[:, i], Sm[:, j]
        den = np.where(ch[:, k], si - sj, 1.0)
        t = np.where(ch[:, k], si / den, 0.0)
        pts[:, k] = Vm[:, i] + (Vm[:, j] - Vm[:, i]) * t[:, None]
    order = np.argsort(~ch, axis=1, kind="stable")[:, :2]
    rows = np.arange(len(Fm))
    p = pts[rows, order[:, 0]]
    q = pts[rows, order[:, 1]]
    m = np.cross(Vm[:, 1] - Vm[:, 0], Vm[:, 2] - Vm[:, 0])
    d = np.cross(n, m)  # material lies left of d (seen from +n)
    flip = np.einsum("ij,ij->i", q - p, d) < 0
    p, q = np.where(flip[:, None], q, p), np.where(flip[:, None], p, q)

    def to2(x):
        r = x - a
        return np.stack([r @ e1, r @ e2], axis=-1)

    p2, q2 = to2(p), to2(q)
    Q = np.array([[0.0, 0.0], to2(b[None])[0], to2(c[None])[0]])  # counter-clockwise
    total = 0.0
    # 1. Section segments clipped to the triangle (Cyrus-Beck against its three edges).
    t0 = np.zeros(len(p2))
    t1 = np.ones(len(p2))
    dseg = q2 - p2
    for k in range(3):
        E0, E1 = Q[k], Q[(k + 1) % 3]
        inward = np.array([-(E1 - E0)[1], (E1 - E0)[0]])
        f0 = (p2 - E0) @ inward
        df = dseg @ inward
        with np.errstate(divide="ignore", invalid="ignore"):
            tc = -f0 / df
        enter = df > 0
        leave = df < 0
        t0 = np.where(enter, np.maximum(t0, tc), t0)
        t1 = np.where(leave, np.minimum(t1, tc), t1)
        outside = (df == 0) & (f0 < 0)
        t1 = np.where(outside, -1.0, t1)
    keep = t1 > t0
    A = p2[keep] + dseg[keep] * t0[keep, None]
    B = p2[keep] + dseg[keep] * t1[keep, None]
    total += float(np.sum(A[:, 0] * B[:, 1] - B[:, 0] * A[:, 1]))
    # 2. The triangle's edges, split where segments cross them, parts inside the section.
    for k in range(3):
        E0, E1 = Q[k], Q[(k + 1) % 3]
        de = E1 - E0
        den = dseg[:, 0] * de[1] - dseg[:, 1] * de[0]
        w = E0 - p2
        with np.errstate(divide="ignore", invalid="ignore"):
            sseg = (w[:, 0] * de[1] - w[:, 1] * de[0]) / den
            tedge = (w[:, 0] * dseg[:, 1] - w[:, 1] * dseg[:, 0]) / den
        hit = (den != 0) & (sseg >= 0) & (sseg <= 1) & (tedge > 0) & (tedge < 1)
        ts = np.concatenate([[0.0], np.sort(tedge[hit]), [1.0]])
        mids = E0 + np.outer(0.5 * (ts[:-1] + ts[1:]), de)
        inside = _inside_2d(mids, p2, q2)
        for i in np.nonzero(inside)[0]:
            X, Y = E0 + ts[i] * de, E0 + ts[i + 1] * de
            total += float(X[0] * Y[1] - Y[0] * X[1])
    area = 0.5 * total
    return float(min(max(area, 0.0), 0.5 * nn))


def _inside_2d(points, p2, q2):
    """Parity of the crossings of a ray in +u from each point with the segments (p2, q2)."""
    if len(points) == 0:
        return np.zeros(0, dtype=bool)
    x = points[:, 0:1]
    y = points[:, 1:2]
    py, qy = p2[None, :, 1], q2[None, :, 1]
    straddle = (py > y) != (qy > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = p2[None, :, 0] + (y - py) * (q2[None, :, 0] - p2[None, :, 0]) / (qy - py)
    crossings = np.sum(straddle & (xc > x), axis=1)
    return crossings % 2 == 1


def box_surface(lo, hi, n=(3, 3, 2)):
    """A closed, outward-oriented triangulated box (for the self-test)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    verts, tris = [], []

    def add_face(origin, du, dv, nu, nv):
        base = len(verts)
        for j in range(nv + 1):
            for i in range(nu + 1):
                verts.append(origin + du * i / nu + dv * j / nv)
        for j in range(nv):
            for i in range(nu):
                v00 = base + j * (nu + 1) + i
                v10, v01, v11 = v00 + 1, v00 + nu + 1, v00 + nu + 2
                tris.extend([(v00, v10, v11), (v00, v11, v01)])

    d = hi - lo
    X, Y, Z = np.diag(d)
    add_face(lo, Y, X, n[1], n[0])  # z = lo, normal -z
    add_face(lo + Z, X, Y, n[0], n[1])  # z = hi, normal +z
    add_face(lo, X, Z, n[0], n[2])  # y = lo, normal -y
    add_face(lo + Y, Z, X, n[2], n[0])  # y = hi, normal +y
    add_face(lo, Z, Y, n[2], n[1])  # x = lo, normal -x
    add_face(lo + X, Y, Z, n[1], n[2])  # x = hi, normal +x
    return np.array(verts), np.array(tris, dtype=np.int64)


def self_test():
    """area_in_box and area_in_surface agree on boxes and known answers; raises on failure."""
    lo, hi = np.array([-0.05, -0.05, 0.0]), np.array([0.05, 0.05, 0.05])
    V, F = box_surface(lo, hi)
    rng = np.random.default_rng(12)
    cases = [
        (np.array([[-0.03, 0.0025, 0.07], [-0.03, 0.0025, 0.03], [0.03, 0.0025, 0.07]]), 3e-4),
        (np.array([[-0.03, 0.0025, 0.03], [0.03, 0.0025, 0.03], [0.03, 0.0025, 0.07]]), 9e-4),
        (np.array([[-0.2, -0.2, 0.01], [0.2, -0.2, 0.01], [0.0, 0.2, 0.01]]), 0.01),
    ]
    for tri, expect in cases:
        ab, asurf = area_in_box(tri, lo, hi), area_in_surface(tri, V, F)
        assert abs(ab - expect) < 1e-9 * max(1, expect) + 1e-12, (tri, ab, expect)
        assert abs(asurf - expect) < 1e-9, (tri, asurf, expect)
    for _ in range(200):
        tri = rng.uniform(-0.08, 0.08, size=(3, 3)) + np.array([0, 0, 0.025])
        ab, asurf = area_in_box(tri, lo, hi, eps=0.0), area_in_surface(tri, V, F)
        assert abs(ab - asurf) < 1e-9, (tri, ab, asurf)
    # A triangle in the top face plane, either orientation: strictly inside nothing.
    top = np.array([[-0.03, -0.01, 0.05], [0.03, -0.01, 0.05], [0.0, 0.01, 0.05]])
    for t in (top, top[::-1]):
        assert area_in_box(t, lo, hi) == 0.0
        assert area_in_surface(t, V, F) == 0.0, area_in_surface(t, V, F)
    # Through surface vertices (the plane y = 0 holds a row of them): the same either way.
    mid = np.array([[-0.03, 0.0, 0.07], [-0.03, 0.0, 0.03], [0.03, 0.0, 0.07]])
    V2, F2 = box_surface(lo, hi, n=(4, 4, 2))
    for t in (mid, mid[::-1]):
        assert abs(area_in_surface(t, V2, F2) - 3e-4) < 1e-9, area_in_surface(t, V2, F2)
    return True
