#!/usr/bin/python3
"""polycut_incision: live incision cases against a polycut-server it starts itself (issue 12,
items 4 and 7, and the way the issue is judged).

Written from docs/protocol.md and docs/server.md only. For every (scene, cutter, case) it starts
`polycut-server --paused --rate 60` on ephemeral loopback ports, subscribes to the stream from the
start (a thread reads every frame), takes the rest surface with `get_surface` at tick 0, resumes,
then drives the case live: `scalpel` NOTIFICATIONS on an absolute 60 Hz schedule, `end_stroke`
as a request, `get_surface`, and scores the cut:

    completeness = (area of the triangles tagged 2) / (2 x swept area inside the tissue)

The swept area inside is exact: the server's own sweep triangles (a_prev, b_prev, a),
(b_prev, b, a) of the case's strokes, clipped to the scene's box (box geometry) or intersected
with the closed rest surface taken at tick 0 (any geometry). The protocol exposes no rest
positions of the cut surface, so the cut area is measured on world positions (the surface is
deformed by gravity and any grab); cases on a strongly deformed body compare with the swept area
inside the deformed surface at the stroke's start instead.

Reported per case (one JSON line each, then a table): server alive (answers get_stats, process
running), its exit status and stderr tail, non-finite / exploded frames (a vertex further than
3 x the rest bounding-box diagonal from its centre), seq gaps, frames received vs ticks elapsed,
tick distribution from the stream headers and get_stats, command-to-visible latency of the
scalpel samples, cut ms from the `topology` events, completeness.

Exit status: 0 when every case passed its assertions (or with --no-assert), 1 when one failed,
2 on a usage or harness error.

    polycut_incision.py                       # default scene, snap and split, all grid cases
    polycut_incision.py --quick               # the ctest subset (live_cut)
    polycut_incision.py --organ --cases 'centre_plane,offset_*'
    polycut_incision.py --list
"""

import argparse
import copy
import fnmatch
import json
import math
import os
import shutil
import sys
import tempfile
import time

import numpy as np
import zmq

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import polycut_live as live  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# --------------------------------------------------------------------------------------------
# Bounds (command-line options override them)

# Cell splitting cuts along the blade itself: issue 12 item 4 asks for 1 % (in rest space).
SPLIT_MIN, SPLIT_MAX = 0.99, 1.01
# Face snapping: THE place for its bound. Issue 12 item 4 leaves it to docs/scenes.md ("a bound
# that a face-conforming cut can actually reach at the mesh's resolution"); until that is stated
# there, 0.8. Change it here (or with --snap-min) when docs/scenes.md gives the figure.
SNAP_MIN = 0.8
# A snapped cut follows mesh faces next to the blade's plane and may be larger than the plane
# (a staircase); this upper bound only catches gross errors.
SNAP_MAX = 1.5
# Cases on a strongly deformed body (grab, pressure): world-space areas, so the bounds widen.
DEFORMED_SLACK = 0.05
# Cases whose blade only touches the surface: the cut area may be at most this fraction of
# the area the blade swept (inside or not).
TANGENT_MAX_FRACTION = 0.01
# A frame is exploded when a vertex lies further than this many rest bounding-box diagonals
# from the rest bounding box's centre.
EXPLODED_DIAGONALS = 3.0

QUICK_CASES = ["grid_plane_y0", "offset_2_5mm", "offset_5_1mm"]


# --------------------------------------------------------------------------------------------
# Scenes


def load_json(path):
    with open(path) as f:
        return json.load(f)


def load_scene(path):
    """A scene file with the files it names (`path`, and `surface` given as a string: relative
    to the scene file, docs/scenes.md) made absolute, so that the copy the runner writes
    elsewhere, with the cutter set, still finds them."""
    base = os.path.dirname(os.path.abspath(path))

    def fix(node):
        if isinstance(node, dict):
            for key, value in node.items():
                if key in ("path", "surface") and isinstance(value, str):
                    node[key] = os.path.normpath(os.path.join(base, value))
                else:
                    fix(value)
        elif isinstance(node, list):
            for value in node:
                fix(value)
        return node
    return fix(load_json(path))


def cutter_of(scene):
    cutting = scene.get("cutting") or {}
    if "method" in cutting:
        return cutting["method"]
    return "snap" if scene.get("method", "tet") == "tet" else "split"


def with_cutter(scene, cutter):
    """snap: `tet` elements with face snapping; split: `mvc` with cell splitting (the method the
    issue used); asis: the scene unchanged."""
    s = copy.deepcopy(scene)
    if cutter == "asis":
        return s
    cutting = dict(s.get("cutting") or {})
    cutting["method"] = cutter
    s["cutting"] = cutting
    s["method"] = "tet" if cutter == "snap" else "mvc"
    return s


def far_pieces(snapshot, centre, bound):
    """The surface's connected pieces (triangles sharing vertices) with a vertex beyond `bound`
    from `centre`: how many triangles, how far, and whether any is tagged cut (2). A small
    piece far away is a fragment the cut set free (falling), not an exploded model."""
    P = snapshot["positions"]
    T = np.asarray(snapshot["triangles"], dtype=np.int64).reshape(-1, 3)
    tags = np.asarray(snapshot.get("tags", np.ones(len(T))), dtype=np.int64)
    parent = list(range(len(P)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a
    for a, b, c in T:
        for u, v in ((a, b), (b, c)):
            ru, rv = find(int(u)), find(int(v))
            if ru != rv:
                parent[ru] = rv
    roots = np.array([find(int(t[0])) for t in T]) if len(T) else np.zeros(0, dtype=np.int64)
    dist = np.linalg.norm(P - centre, axis=1)
    out = []
    for r in np.unique(roots):
        sel = roots == r
        verts = np.unique(T[sel].ravel())
        d = float(np.max(dist[verts]))
        if d > bound:
            out.append({"triangles": int(sel.sum()), "vertices": int(len(verts)),
                        "max_dist_m": round(d, 3), "has_cut_faces": bool((tags[sel] == 2).any())})
    return {"pieces": int(len(np.unique(roots))), "far": out[:10]}


def organ_scene(base, cell_size):
    """The organ of issue 12: the blob (about 10 x 6.4 x 4.4 cm) meshed by CGAL, standing on its
    bottom 6 mm (fixed), under gravity, AMG-preconditioned PCG."""
    s = copy.deepcopy(base)
    s["name"] = "organ_blob"
    s["description"] = "polycut_incision: the blob organ"
    s["geometry"] = {"type": "implicit", "shape": "blob", "cell_size": cell_size,
                     "center": [0.0, 0.0, 0.025]}
    s["fixed"] = [{"box": {"min": [-1, -1, -1], "max": [1, 1, 0.006]}}]
    s["solver"] = {"type": "pcg", "preconditioner": "amg", "tolerance": 1e-3}
    s.pop("probes", None)
    s.pop("camera", None)
    return s


class Variant:
    """One scene with one cutter."""

    def __init__(self, name, scene, cutter, path=None):
        self.name = name
        self.scene = scene
        self.cutter = cutter
        self.path = path  # the scene file when it is used unchanged
        g = scene.get("geometry", {})
        self.box = None
        if g.get("type") == "box":
            lo = np.array(g.get("origin", [0, 0, 0]), dtype=float)
            size = np.array(g["size"], dtype=float)
            cells = np.array(g.get("cells", [4, 4, 4]), dtype=float)
            self.box = {"lo": lo, "hi": lo + size, "cell": size / cells}


def build_variants(args):
    variants = []
    cutters = [c for c in args.cutters.split(",") if c]
    default = [os.path.join(REPO, "assets", "scenes", "default.json")]
    for path in [] if args.organ_only else args.scene or default:
        scene = load_scene(path)
        if args.no_gravity:
            scene.setdefault("loads", {}).pop("gravity", None)
        base = os.path.splitext(os.path.basename(path))[0]
        for cutter in cutters:
            s = with_cutter(scene, cutter)
            unchanged = cutter == "asis" and not args.no_gravity
            variants.append(Variant(f"{base}/{cutter_of(s)}", s, cutter_of(s),
                                    path if unchanged else None))
    if args.organ or args.organ_only:
        if args.organ_scene:
            organ = load_scene(args.organ_scene)
            name = os.path.splitext(os.path.basename(args.organ_scene))[0]
        else:
            organ = organ_scene(load_json(os.path.join(REPO, "assets", "scenes", "default.json")),
                                args.organ_cell_size)
            name = "organ"
        if args.no_gravity:
            organ.setdefault("loads", {}).pop("gravity", None)
        for cutter in cutters:
            s = with_cutter(organ, cutter)
            variants.append(Variant(f"{name}/{cutter_of(s)}", s, cutter_of(s)))
    return variants


# --------------------------------------------------------------------------------------------
# Strokes and cases


class Stroke:
    """A straight blade (b = a + blade) whose point a runs along `path` (a polyline) in
    `samples` evenly spaced samples, one per tick. `resolve(world)` may fill path and blade from
    the surface at the stroke's start (positions, triangles)."""

    def __init__(self, path=None, blade=None, samples=None, seconds=None, resolve=None,
                 step=None):
        self.path = None if path is None else np.asarray(path, dtype=float)
        self.blade = None if blade is None else np.asarray(blade, dtype=float)
        self.samples = samples
        self.seconds = seconds
        self.step = step  # distance per sample [m]
        self._resolve = resolve

    def resolved(self, world, rate):
        s = Stroke(self.path, self.blade, self.samples, self.seconds, None, self.step)
        if self._resolve is not None:
            s.path, s.blade = (np.asarray(v, dtype=float) for v in self._resolve(world))
        length = float(np.sum(np.linalg.norm(np.diff(s.path, axis=0), axis=1)))
        if s.samples is None:
            if s.step is not None:
                s.samples = int(round(length / s.step)) + 1
            else:
                s.samples = max(2, int(round((s.seconds or 3.0) * rate)) + 1)
        return s

    def points(self):
        """The samples (a, b), a at evenly spaced arc-length positions of the path."""
        seg = np.linalg.norm(np.diff(self.path, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        out = []
        for t in np.linspace(0.0, cum[-1], self.samples):
            i = min(int(np.searchsorted(cum, t, side="right")) - 1, len(seg) - 1)
            u = 0.0 if seg[i] == 0 else (t - cum[i]) / seg[i]
            a = self.path[i] + u * (self.path[i + 1] - self.path[i])
            out.append((a, a + self.blade))
        return out

    def sweep_triangles(self):
        """The server's sweep triangles (docs/protocol.md, scalpel): per pair of consecutive
        samples, (a_prev, b_prev, a) and (b_prev, b, a)."""
        pts = self.points()
        tris = []
        for (ap, bp), (a, b) in zip(pts[:-1], pts[1:]):
            tris.append((ap, bp, a))
            tris.append((bp, b, a))
        return np.array(tris)

    def key(self):
        return (self.path.round(9).tobytes(), self.blade.round(9).tobytes(), self.samples)

    def describe(self):
        return {"path": self.path.round(6).tolist(), "blade": self.blade.round(6).tolist(),
                "samples": self.samples}


class Frame:
    """Where a scene's cases put the blade: a stroke along x from x0 to x1 in the plane y, the
    blade from `above` over the top z_top to `depth` below it. For a box, y is the grid plane
    nearest the centre, x0/x1 and z_top - depth are grid planes."""

    def __init__(self, variant, rest):
        V = rest["positions"]
        self.lo, self.hi = V.min(axis=0), V.max(axis=0)
        self.centre = 0.5 * (self.lo + self.hi)
        self.diag = float(np.linalg.norm(self.hi - self.lo))
        self.box = variant.box
        self.above = 0.02
        if self.box is not None:
            lo, hi, cell = self.box["lo"], self.box["hi"], self.box["cell"]
            size = hi - lo
            grid = lambda axis, v: lo[axis] + cell[axis] * round((v - lo[axis]) / cell[axis])
            self.xc = grid(0, self.centre[0])
            self.y = grid(1, self.centre[1])
            half = cell[0] * max(1, round(0.3 * size[0] / cell[0]))
            self.x0, self.x1 = self.xc - half, self.xc + half
            self.z_top = hi[2]
            self.depth = cell[2] * max(1, round(0.4 * size[2] / cell[2]))
            self.cell = cell
        else:
            size = self.hi - self.lo
            self.xc, self.y = self.centre[0], self.centre[1]
            half = min(0.03, 0.3 * size[0])
            self.x0, self.x1 = self.xc - half, self.xc + half
            self.z_top = top_z(V, self.x0, self.x1, self.y, 0.005)
            self.depth = min(0.02, 0.4 * size[2])
            self.cell = None

    def line(self, y=None, x0=None, x1=None, depth=None, z_top=None):
        y = self.y if y is None else y
        x0 = self.x0 if x0 is None else x0
        x1 = self.x1 if x1 is None else x1
        depth = self.depth if depth is None else depth
        z_top = self.z_top if z_top is None else z_top
        z = z_top + self.above
        return [[x0, y, z], [x1, y, z]], [0.0, 0.0, -(self.above + depth)]


def top_z(V, x0, x1, y, band):
    """The highest surface vertex over the strip x in [x0, x1], |y' - y| <= band."""
    sel = (V[:, 0] >= x0) & (V[:, 0] <= x1) & (np.abs(V[:, 1] - y) <= band)
    if not sel.any():
        sel = np.ones(len(V), dtype=bool)
    return float(V[sel, 2].max())


class Case:
    """A named case: actions run in order, then the cut is measured.

    actions: ("settle", s) | ("stroke", Stroke) | ("strokes", Stroke, n) | ("grab", point,
    stiffness, radius) | ("move_grab", target, seconds) | ("release",) | ("force", point,
    force, radius).
    reference: "rest" (the swept area inside the rest geometry) or "world" (inside the surface at
    the first stroke's start; for a strongly deformed body). expect: "cut" (completeness within
    the cutter's bounds) or "tangent" (the blade only touches the surface: nearly no cut)."""

    def __init__(self, name, description, actions, reference="rest", expect="cut"):
        self.name = name
        self.description = description
        self.actions = actions
        self.reference = reference
        self.expect = expect


def cases_for(frame, args):
    """The cases of issue 12 item 2 for a scene. Box scenes get the grid-aligned ones."""
    F = frame
    sec = args.stroke_seconds
    std = lambda y=None, **kw: Stroke(*F.line(y=y, **kw), seconds=sec)
    off = F.y + 0.0025
    cases = []
    if F.box is not None:
        cx, cy, cz = F.cell
        cases.append(Case("grid_plane_y0", "blade exactly in a plane of grid faces (y = grid "
                          "plane at the centre; for the default block y = 0)",
                          [("settle", args.settle), ("stroke", std())]))
    else:
        cases.append(Case("centre_plane", "blade in the plane y = centre of the bounding box",
                          [("settle", args.settle), ("stroke", std())]))
    cases.append(Case("offset_2_5mm", "blade at y = plane + 2.5 mm",
                      [("settle", args.settle), ("stroke", std(off))]))
    cases.append(Case("offset_5_1mm", "blade at y = plane + 5.1 mm",
                      [("settle", args.settle), ("stroke", std(F.y + 0.0051))]))
    if F.box is not None:
        # y(x) = y0 + cy (i + 1) / 2 at x = xc + i cx: node columns at odd i, blade bottom on the
        # grid plane z_top - depth, so the bottom edge passes through nodes.
        z = F.z_top + F.above
        blade = [0.0, 0.0, -(F.above + F.depth)]
        i0, i1 = (F.x0 - F.xc) / cx, (F.x1 - F.xc) / cx
        path = [[F.x0, F.y + cy * (i0 + 1) / 2, z], [F.x1, F.y + cy * (i1 + 1) / 2, z]]
        cases.append(Case("through_nodes", "vertical blade through columns of grid nodes, its "
                          "bottom edge through nodes (slope 1/2 in cells)",
                          [("settle", args.settle), ("stroke", Stroke(path, blade, seconds=sec))]))
        path = [[F.x0, F.y + (F.x0 - F.xc) * cy / cx, z], [F.x1, F.y + (F.x1 - F.xc) * cy / cx, z]]
        cases.append(Case("along_edges", "vertical blade along the cells' diagonal (x = y in "
                          "cells): its bottom runs along face-diagonal edges on a grid plane, "
                          "its plane holds vertical and main-diagonal (Kuhn) edges and faces",
                          [("settle", args.settle), ("stroke", Stroke(path, blade, seconds=sec))]))
    else:
        V = frame.rest_positions
        top = V[np.argmax(V[:, 2])]
        path, blade = F.line(y=float(top[1]))
        cases.append(Case("through_nodes", "blade in the plane y through the top-most surface "
                          "vertex", [("settle", args.settle), ("stroke", Stroke(path, blade,
                                                                               seconds=sec))]))

    # The highest surface point under the blade: the highest vertex within one cell of the
    # blade's footprint (the surface between vertices is linear, so this bounds it).
    margin = 0.003 if F.cell is None else float(max(F.cell[0], F.cell[1]))

    def tangent_edge(world):
        zt = top_z(world[0], F.x0 - margin, F.x1 + margin, off, margin)
        return F.line(y=off, depth=0.0, z_top=zt)

    def tangent_plane(world):
        zt = top_z(world[0], F.x0 - margin, F.x1 + margin, F.y, 0.01 + margin)
        return [[F.x0, F.y - 0.01, zt], [F.x1, F.y - 0.01, zt]], [0.0, 0.02, 0.0]

    cases.append(Case("tangent_top", "vertical blade whose bottom edge just touches the top "
                      "surface (the highest surface vertex under the path, in world space)",
                      [("settle", args.settle), ("stroke", Stroke(seconds=sec,
                                                                  resolve=tangent_edge))],
                      reference="world", expect="tangent"))
    cases.append(Case("tangent_top_plane", "horizontal blade lying on the top surface (its "
                      "plane is the top face plane at the highest vertex, world space)",
                      [("settle", args.settle), ("stroke", Stroke(seconds=sec,
                                                                  resolve=tangent_plane))],
                      reference="world", expect="tangent"))
    if F.cell is not None:
        x_end = F.xc + F.cell[0] * (round((0.755 * (F.x1 - F.x0) + F.x0 - F.xc) / F.cell[0]) + 0.53)
        depth = F.cell[2] * 1.53
    else:
        x_end = F.x0 + 0.755 * (F.x1 - F.x0)
        depth = 0.0153
    frac = (x_end - F.x0) / (F.x1 - F.x0)
    cases.append(Case("end_inside_cell", "the stroke ends inside the tissue: its end and the "
                      "blade's bottom inside a cell",
                      [("settle", args.settle),
                       ("stroke", Stroke(*F.line(y=off, x1=x_end, depth=depth),
                                         seconds=sec * frac))]))
    cases.append(Case("recut", "a second stroke along the first one",
                      [("settle", args.settle), ("stroke", std(off)), ("stroke", std(off))]))
    # A second stroke at right angles through the first one's middle: it crosses the opened
    # cut (its lips apart in world space, one plane in rest space).
    xc = F.xc + 0.0025
    half_y = min(0.5 * (F.x1 - F.x0), 0.4 * float(F.hi[1] - F.lo[1]))
    ys = (F.y - half_y, F.y + half_y)
    zc = F.z_top
    if F.box is None:  # the highest rest vertex under the second blade's path
        Vr = frame.rest_positions
        strip = (np.abs(Vr[:, 0] - xc) <= 0.005) & (Vr[:, 1] >= ys[0]) & (Vr[:, 1] <= ys[1])
        zc = float(Vr[strip, 2].max()) if strip.any() else F.z_top
    cross = Stroke([[xc, ys[0], zc + F.above], [xc, ys[1], zc + F.above]],
                   [0.0, 0.0, -(F.above + F.depth)], seconds=sec)
    cases.append(Case("crossing", "a second stroke at right angles across the first one, "
                      "through its middle (the first cut's lips apart in world space)",
                      [("settle", args.settle), ("stroke", std(off)), ("stroke", cross)]))
    n = 1000 if args.heavy else args.many
    cases.append(Case(f"many_strokes_{n}", f"{n} strokes in the same place (each "
                      f"{args.many_samples} samples)",
                      [("settle", args.settle),
                       ("strokes", Stroke(*F.line(y=off), samples=args.many_samples), n)]))
    half = 0.01
    cases.append(Case("slow_0_1mm", "a slow stroke: 0.1 mm per tick over 2 cm",
                      [("settle", args.settle),
                       ("stroke", Stroke(*F.line(y=off, x0=F.xc - half, x1=F.xc + half),
                                         step=1e-4))]))
    cases.append(Case("fast", "a fast stroke: the whole path in 3 ticks (2 cm, more than a "
                      "cell, per tick)",
                      [("settle", args.settle), ("stroke", Stroke(*F.line(y=off), samples=4))]))
    def below_world_top(world):
        # On a deformed body the blade enters `depth` below the world top at the stroke's start.
        zt = top_z(world[0], F.x0 - margin, F.x1 + margin, off, margin)
        return F.line(y=off, z_top=zt)

    grab_at = [F.xc, F.y + 0.02, F.z_top]
    cases.append(Case("grabbed", "the +y side grabbed and pulled 3 cm up (stiffness 400 N/m), "
                      "then a stroke at y + 2.5 mm, 2 cm below the world top, while it is held",
                      [("settle", args.settle), ("grab", grab_at, 400.0, 0.01),
                       ("move_grab", [grab_at[0], grab_at[1], grab_at[2] + 0.03], 0.5),
                       ("settle", 0.5), ("stroke", Stroke(seconds=sec, resolve=below_world_top))],
                      reference="world"))
    cases.append(Case("pressed", "the top pressed down by 5 N over a 2 cm radius next to the "
                      "path, then a stroke at y + 2.5 mm, 2 cm below the world top",
                      [("settle", args.settle),
                       ("force", [F.xc, F.y + 0.015, F.z_top], [0.0, 0.0, -5.0], 0.02),
                       ("settle", 1.0), ("stroke", Stroke(seconds=sec, resolve=below_world_top))],
                      reference="world"))
    return cases


def select(cases, patterns):
    if not patterns:
        return cases
    pats = [p for p in patterns.split(",") if p]
    return [c for c in cases if any(fnmatch.fnmatchcase(c.name, p) for p in pats)]


# --------------------------------------------------------------------------------------------
# Statistics


def dist(values):
    v = np.asarray([x for x in values if x is not None and np.isfinite(x)], dtype=float)
    if v.size == 0:
        return {"count": 0}
    return {"count": int(v.size), "p50": round(float(np.percentile(v, 50)), 3),
            "p99": round(float(np.percentile(v, 99)), 3), "max": round(float(v.max()), 3)}


def tail(text, lines=15):
    out = [ln for ln in text.splitlines() if ln.strip()]
    return out[-lines:]


# --------------------------------------------------------------------------------------------
# Running a case


class CaseTimeout(RuntimeError):
    pass


class Runner:
    def __init__(self, args, variant, case_factory, logdir):
        self.args = args
        self.variant = variant
        self.case_factory = case_factory
        self.logdir = logdir

    def run(self, case_name):
        args, v = self.args, self.variant
        t_start = time.perf_counter()
        res = {"scene": v.name.split("/")[0], "cutter": v.cutter, "variant": v.name,
               "case": case_name, "ok": False, "failures": [], "errors": [],
               "loadavg_1min": [round(os.getloadavg()[0], 2)]}
        try:  # the binary may be relinked between cases on a shared machine
            res["server_bin_mtime"] = time.strftime(
                "%Y-%m-%dT%H:%M:%S", time.localtime(os.path.getmtime(args.server_bin)))
        except OSError:
            pass
        tag = f"{v.name.replace('/', '-')}-{case_name}"
        stderr_path = os.path.join(self.logdir, tag + ".stderr")
        scene_path = v.path
        if scene_path is None:
            scene_path = os.path.join(self.logdir, tag + ".scene.json")
            with open(scene_path, "w") as f:
                json.dump(v.scene, f, indent=1)
        # The server's command log beside its stderr: `polycut-server --replay` reproduces a case.
        commands_path = os.path.join(self.logdir, tag + ".commands.log")
        srv = live.ServerProcess(args.server_bin, ["--scene", scene_path, "--rate",
                                                   str(args.rate), "--paused",
                                                   "--record-commands", commands_path],
                                 stderr_path=stderr_path, start_timeout=args.start_timeout)
        ctx = zmq.Context()
        reader = rpc = rest = frame = case = surf = final = stats = None
        self.strokes, self.samples, self.world_at_start = [], [], None
        self.end_reply = None
        self.window = [None, None]
        phase = "start"
        self.deadline = time.monotonic() + args.case_timeout
        try:
            try:
                ready = srv.start()
                rpc = live.Rpc(ctx, ready["control"], srv)
                phase = "hello"
                hello = rpc.call("hello", {"client": "polycut_incision",
                                           "protocol": live.PROTOCOL}, timeout=args.reply_timeout)
                res["server"] = hello.get("server")
                reader = live.StreamReader(ctx, hello["stream"])
                reader.start()
                time.sleep(0.3)  # the subscription reaches the PUB before the first tick
                phase = "rest surface"
                rest = rpc.get_surface(timeout=args.reply_timeout)
                frame = Frame(v, rest)
                frame.rest_positions = rest["positions"]
                res["rest"] = {"tick": rest["tick"], "vertices": int(len(rest["positions"])),
                               "triangles": int(len(rest["triangles"])),
                               "bbox": [frame.lo.round(5).tolist(), frame.hi.round(5).tolist()]}
                reader.set_bound(frame.centre, args.explode_diagonals * frame.diag)
                reader.seed(rest)
                case = {c.name: c for c in self.case_factory(frame)}[case_name]
                res["description"] = case.description
                phase = "resume"
                rpc.call("resume", timeout=args.reply_timeout)
                phase = "case"
                self.drive(case, rpc, reader, res)
                phase = "get_surface after end_stroke"
                surf = self.surface_after_cut(rpc, reader, srv, res)
                self.window[1] = time.perf_counter()
                phase = "watching the stream after the cut"
                self.sleep(args.post)
                phase = "final get_surface"
                final = rpc.get_surface(timeout=args.reply_timeout)
                phase = "done"
            except (live.ServerDied, live.RpcTimeout, CaseTimeout, live.RpcError) as e:
                res["errors"].append(f"{phase}: {type(e).__name__}: {e}")
                res["failed_in"] = phase
            # Alive: the process runs and answers get_stats.
            if rpc is not None and not srv.exited():
                try:
                    stats = rpc.call("get_stats", timeout=args.reply_timeout)
                except (live.ServerDied, live.RpcTimeout, live.RpcError) as e:
                    res["errors"].append(f"get_stats: {type(e).__name__}: {e}")
            res["alive"] = stats is not None and not srv.exited()
            if res["alive"]:
                try:
                    rpc.call("shutdown", timeout=10.0)
                except (live.RpcError, live.RpcTimeout, live.ServerDied) as e:
                    res["errors"].append(f"shutdown: {e}")
                res["exit_status"] = srv.stop(timeout=15.0)
            else:
                res["exit_before_shutdown"] = srv.returncode()
                if res["exit_before_shutdown"] is None:
                    res["hung"] = True  # running but not answering: terminate it
                    srv.proc.terminate()
                res["exit_status"] = srv.stop(timeout=5.0)
        finally:
            if srv.proc is not None and srv.proc.poll() is None:
                srv.proc.kill()
                srv.proc.wait()
            if reader is not None:
                reader.stop()
            if rpc is not None:
                rpc.close()
            ctx.term()
            srv.close_files()
        res["stderr_tail"] = tail(srv.stderr_text())
        if reader is not None:
            self.score(res, case, frame, reader, rest, surf, final, stats)
        self.judge(res, case)
        res["wall_s"] = round(time.perf_counter() - t_start, 2)
        # Other processes on the machine skew the tick figures (not the cut): start and end.
        res["loadavg_1min"].append(round(os.getloadavg()[0], 2))
        return res

    # -- driving

    def surface_after_cut(self, rpc, reader, srv, res):
        """get_surface once the stream has reached the tick of the last end_stroke reply (the
        first tick whose frame reflects it) and, when the reply said triangles were `deferred`
        by the cut budget, a frame whose header says none are left (`cut_deferred` 0: the
        stroke is finished, docs/protocol.md); before that a snapshot may predate the cut."""
        r = self.end_reply
        if r is None:
            return rpc.get_surface(timeout=self.args.reply_timeout)
        deferred = bool(r.get("deferred"))
        if not reader.wait_tick(r["tick"], self.args.reply_timeout, srv, cut_done=deferred):
            raise live.RpcTimeout(f"no stream frame of tick {r['tick']} (end_stroke's) "
                                  f"{'with its deferred triangles cut ' if deferred else ''}"
                                  f"within {self.args.reply_timeout:.0f} s")
        done_tick = reader.mark()[1] if deferred else r["tick"]
        for _ in range(50):
            surf = rpc.get_surface(timeout=self.args.reply_timeout)
            if surf["tick"] >= done_tick:
                break
            time.sleep(0.02)
        if surf["topology_version"] < r["topology_version"]:
            res["errors"].append(f"get_surface at tick {surf['tick']} has topology_version "
                                 f"{surf['topology_version']} < end_stroke's "
                                 f"{r['topology_version']}")
        return surf

    def sleep(self, seconds):
        end = time.perf_counter() + seconds
        while True:
            left = end - time.perf_counter()
            if left <= 0:
                return
            self.check_deadline()
            time.sleep(min(left, 0.05))

    def check_deadline(self):
        if time.monotonic() > self.deadline:
            raise CaseTimeout(f"case took longer than {self.args.case_timeout:.0f} s")

    def drive(self, case, rpc, reader, res):
        """Runs the actions. Returns the resolved strokes (as sent, in order), the samples
        [(send time, reader mark, stroke index, sample index)], the world surface at the first
        stroke's start and the stroke window [t0, t1]."""
        args = self.args
        strokes, samples, window = self.strokes, self.samples, self.window
        grab_id = None
        grab_target = None
        stroke_id = 0
        period = 1.0 / args.rate
        res["requests"] = []
        for action in case.actions:
            kind = action[0]
            if kind == "settle":
                # At least half the nominal ticks must have run (a large scene's first steps,
                # e.g. the AMG set-up, can take seconds), at most 20 s more.
                _, tick0, _, _ = reader.mark()
                self.sleep(action[1])
                want = (tick0 or 0) + math.ceil(0.5 * action[1] * args.rate)
                if not reader.wait_tick(want, 20.0, rpc.server):
                    res.setdefault("notes", []).append(f"settle: tick {want} not reached in 20 s")
            elif kind in ("stroke", "strokes"):
                count = action[2] if kind == "strokes" else 1
                world = reader.latest_surface()
                if world is None:
                    raise live.RpcError("stream", {"code": 0, "message": "no surface frame "
                                                   "received before the stroke"})
                if self.world_at_start is None:
                    self.world_at_start = world
                stroke = action[1].resolved(world, args.rate)
                pts = stroke.points()
                for _ in range(count):
                    stroke_id += 1
                    index = len(strokes)
                    strokes.append(stroke)
                    t0 = time.perf_counter() + period
                    if window[0] is None:
                        window[0] = t0
                    for k, (a, b) in enumerate(pts):
                        target = t0 + k * period
                        while True:
                            left = target - time.perf_counter()
                            if left <= 0:
                                break
                            time.sleep(min(left, 0.05))
                        self.check_deadline()
                        mark = reader.mark()
                        rpc.notify("scalpel", {"stroke": stroke_id, "a": a.tolist(),
                                               "b": b.tolist()})
                        samples.append((time.perf_counter(), mark, index, k))
                    try:
                        r = rpc.call("end_stroke", {"stroke": stroke_id},
                                     timeout=args.reply_timeout)
                        self.end_reply = r
                        if count == 1 or stroke_id <= 3:
                            res["requests"].append({"end_stroke": r})
                    except live.RpcError as e:
                        res["errors"].append(f"end_stroke {stroke_id}: {e}")
            elif kind == "grab":
                _, point, stiffness, radius = action
                r = rpc.call("grab", {"point": list(point), "stiffness": stiffness,
                                      "radius": radius}, timeout=args.reply_timeout)
                grab_id, grab_target = r["id"], np.array(point, dtype=float)
            elif kind == "move_grab":
                _, target, seconds = action
                target = np.array(target, dtype=float)
                n = max(1, int(round(seconds * args.rate)))
                t0 = time.perf_counter()
                for k in range(1, n + 1):
                    p = grab_target + (target - grab_target) * k / n
                    rpc.notify("move_grab", {"id": grab_id, "target": p.tolist()})
                    left = t0 + k * period - time.perf_counter()
                    if left > 0:
                        time.sleep(left)
                grab_target = target
            elif kind == "release":
                rpc.call("release", {"id": grab_id}, timeout=args.reply_timeout)
            elif kind == "force":
                _, point, force, radius = action
                rpc.call("apply_force", {"point": list(point), "force": list(force),
                                         "radius": radius}, timeout=args.reply_timeout)
            else:
                raise ValueError(kind)

    # -- scoring

    def score(self, res, case, frame, reader, rest, surf, final, stats):
        strokes, samples = self.strokes, self.samples
        world_at_start, window = self.world_at_start, self.window
        with reader.lock:
            frames = list(reader.frames)
            events = list(reader.events)
            gaps = list(reader.seq_gaps)
            topo_without = reader.topology_without_arrays
        bound = None if frame is None else self.args.explode_diagonals * frame.diag
        nonfinite = sum(1 for f in frames if not f["finite"])
        exploded = sum(1 for f in frames if f["max_dist"] is not None and bound is not None
                       and f["max_dist"] > bound)
        maxd = max((f["max_dist"] for f in frames if f["max_dist"] is not None
                    and np.isfinite(f["max_dist"])), default=None)
        ticks = [f["tick"] for f in frames]
        fr = {"received": len(frames), "seq_gaps": len(gaps), "gap_samples": gaps[:5],
              "topology_without_arrays": topo_without, "nonfinite": nonfinite,
              "exploded": exploded, "max_dist_m": None if maxd is None else round(maxd, 4),
              "max_dist_over_rest": None if maxd is None or frame is None
              else round(maxd / (0.5 * frame.diag), 3),
              "bound_m": None if bound is None else round(bound, 4)}
        if frames:
            fr["first_tick"], fr["last_tick"] = ticks[0], ticks[-1]
            fr["ticks_elapsed"] = ticks[-1] - ticks[0] + 1
        res["frames"] = fr
        for name, s in (("after_end_stroke", surf), ("final", final)):
            if s is None:
                continue
            P = s["positions"]
            bad = not np.isfinite(P).all()
            far = bound is not None and np.isfinite(P).all() and float(
                np.max(np.linalg.norm(P - frame.centre, axis=1))) > bound
            if bad or far:
                fr.setdefault("bad_snapshots", []).append(name)
                fr.setdefault("far_pieces", {})[name] = far_pieces(s, frame.centre, bound)
        # Ticks: the stroke window from the stream, the whole run from get_stats.
        if window[0] is not None and frames:
            t0 = window[0]
            t1 = window[1] if window[1] is not None else frames[-1]["t"]
            w = [f for f in frames if t0 - 0.02 <= f["t"] <= t1 + 0.02]
        else:
            w = frames
        intervals = [(b["t"] - a["t"]) * 1000 for a, b in zip(w[:-1], w[1:])]
        wall = (w[-1]["t"] - w[0]["t"]) if len(w) > 1 else 0.0
        tk = {"window_frames": len(w),
              "window_ticks": (w[-1]["tick"] - w[0]["tick"] + 1) if w else 0,
              "window_s": round(wall, 3),
              "rate_hz": round((w[-1]["tick"] - w[0]["tick"]) / wall, 2) if wall > 0 else None,
              "stream_step_ms": dist(f["step_ms"] for f in w),
              "frame_interval_ms": dist(intervals),
              "solver_iterations": dist(f["iterations"] for f in w),
              # where the long steps fall: the five slowest frames of the whole run
              "slowest_steps": [{"tick": f["tick"], "step_ms": f["step_ms"],
                                 "iterations": f["iterations"]}
                                for f in sorted(frames, key=lambda f: -(f["step_ms"] or 0))[:5]],
              # every frame: [tick, step_ms, solver_iterations, topology_version]
              "per_frame": [[f["tick"], f["step_ms"], f["iterations"], f["tv"]] for f in frames]}
        if stats is not None:
            tk["stats"] = {k: stats.get(k) for k in ("tick", "worst_tick_ms", "ticks_over_budget",
                                                     "step_ms_p50", "step_ms_p99", "errors",
                                                     "stream_dropped", "requests",
                                                     "topology_version", "vertex_count",
                                                     "cell_count", "open_strokes")}
        over = [e for _, e in events if e.get("kind") == "overrun"]
        tk["overrun_events"] = len(over)
        tk["overrun_max_ms"] = max((e.get("detail", {}).get("tick_ms", 0) for e in over),
                                   default=None)
        res["ticks"] = tk
        # Events.
        kinds = {}
        for _, e in events:
            kinds[e.get("kind")] = kinds.get(e.get("kind"), 0) + 1
        topo = [e for _, e in events if e.get("kind") == "topology"]
        res["events"] = {"counts": kinds,
                         "rejected": [e.get("detail") for _, e in events
                                      if e.get("kind") == "rejected"][:5],
                         "warnings": [e.get("detail") for _, e in events
                                      if e.get("kind") == "warning"][:5]}
        # Per topology event: the wall time of the cuts since the previous event (docs/protocol.md),
        # summed over the ticks whose cuts changed nothing visible (face snapping holds faces
        # back; a re-cut along an earlier cut opens nothing for many ticks). Not a tick's cut
        # time: the tick figures are the stream headers' and get_stats'.
        res["cut_ms"] = dist(e.get("detail", {}).get("cut_ms") for e in topo)
        res["cut_ms"]["total"] = round(sum(e.get("detail", {}).get("cut_ms") or 0 for e in topo), 3)
        if reader.extra_header or reader.extra_step:
            res["extra_header"] = {"header": reader.extra_header, "step": reader.extra_step}
        if reader.errors:
            res["errors"].extend(f"stream: {e}" for e in reader.errors[:5])
        if not strokes or case is None:
            return
        # The reference: distinct strokes, their triangles inside the rest geometry and inside
        # the world surface at the first stroke's start.
        distinct = {}
        for s in strokes:
            distinct.setdefault(s.key(), s)
        ref_rest = ref_world = 0.0
        inside_by_key = {}
        swept_total = 0.0
        for key, s in distinct.items():
            tris = s.sweep_triangles()
            areas = 0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0],
                                                  tris[:, 2] - tris[:, 0]), axis=1)
            swept_total += float(areas.sum())
            if v_box := self.variant.box:
                rest_in = np.array([live.area_in_box(t, v_box["lo"], v_box["hi"]) for t in tris])
            else:
                rest_in = np.array([live.area_in_surface(t, rest["positions"], rest["triangles"])
                                    for t in tris])
            world_in = np.array([live.area_in_surface(t, world_at_start[0], world_at_start[1])
                                 for t in tris]) if world_at_start is not None else rest_in
            inside_by_key[key] = (rest_in, areas)
            ref_rest += float(rest_in.sum())
            ref_world += float(world_in.sum())
        # Cross-check of the box clipping against the rest surface (the same number unless the
        # scene's box is not what the server meshed).
        if self.variant.box is not None:
            s0 = next(iter(distinct.values()))
            res["swept_inside_rest_mesh_cm2"] = round(1e4 * sum(
                live.area_in_surface(t, rest["positions"], rest["triangles"])
                for t in s0.sweep_triangles()) * len(distinct), 4)
        res["strokes"] = {"count": len(strokes),
                          "distinct": [s.describe() for s in distinct.values()]}
        cut = {"measured_on": "world positions (the protocol exposes no rest positions of the "
                              "cut surface)",
               "reference": case.reference,
               "swept_total_cm2": round(1e4 * swept_total, 4),
               "swept_inside_rest_cm2": round(1e4 * ref_rest, 4),
               "swept_inside_world_cm2": round(1e4 * ref_world, 4)}
        if surf is not None:
            area = live.tagged_area(surf, 2)
            cut["area_cm2"] = round(1e4 * area, 4)
            cut["cut_triangles"] = int(np.sum(surf["tags"] == 2))
            cut["topology_version"] = surf["topology_version"]
            cut["vertices"] = int(len(surf["positions"]))
            # On an organ (no box) the body sags before the stroke, so the world blade clipped
            # by the rest surface mixes two spaces (it ran 0.91-0.94 for cuts the server
            # measured complete in rest space): the reference is the world surface at the
            # stroke's start, the space of the cut area it is compared with. The slack of the
            # deformed cases (grabbed, pressed) still applies only to them.
            reference = case.reference if self.variant.box is not None else "world"
            cut["reference"] = reference
            ref = ref_rest if reference == "rest" else ref_world
            cut["swept_inside_cm2"] = round(1e4 * ref, 4)
            if ref > 0:
                cut["completeness"] = round(area / (2 * ref), 4)
            if ref_rest > 0:
                cut["completeness_rest"] = round(area / (2 * ref_rest), 4)
            if ref_world > 0:
                cut["completeness_world"] = round(area / (2 * ref_world), 4)
        if stats is not None and "cut_completeness" in stats:
            # The server's own figure, in rest space where issue 12 item 4 states the bound (the
            # areas above are on world positions).
            cut["completeness_server"] = round(stats["cut_completeness"], 4)
            cut["cut_area_server_cm2"] = round(1e4 * stats.get("cut_area", 0.0), 4)
            cut["swept_area_server_cm2"] = round(1e4 * stats.get("swept_area", 0.0), 4)
            cut["swept_area_undone_server_cm2"] = round(1e4 * stats.get("swept_area_undone", 0.0), 4)
        if final is not None:
            cut["area_final_cm2"] = round(1e4 * live.tagged_area(final, 2), 4)
            if cut.get("area_cm2"):
                # The cut surface should not grow once the blade is gone: growth means lips
                # flapping or a local blow-up the explosion bound does not catch.
                cut["area_drift"] = round(cut["area_final_cm2"] / cut["area_cm2"] - 1, 4)
        res["cut"] = cut
        # Command-to-visible: from sending a sample whose sweep triangles cross the tissue (inside
        # the rest geometry) to the first frame received after it whose topology_version is
        # above the one of the last frame received before it. Only the first stroke along each
        # path counts: a re-cut need not change the topology.
        lat_ms, lat_ticks, never, counted, by_sample = [], [], 0, 0, []
        keys = [s.key() for s in strokes]
        first = {}
        for i, key in enumerate(keys):
            first.setdefault(key, i)
        for t_send, (n, tick, tv, _), index, k in samples:
            if k == 0 or first[keys[index]] != index:
                continue
            rest_in, areas = inside_by_key[keys[index]]
            pair = slice(2 * (k - 1), 2 * k)
            if rest_in[pair].sum() <= 0.01 * areas[pair].sum():
                continue
            counted += 1
            tv = -1 if tv is None else tv
            hit = next((f for f in frames[n:] if f["tv"] > tv and f["t"] >= t_send), None)
            if hit is None:
                never += 1
                continue
            lat_ms.append((hit["t"] - t_send) * 1000)
            if tick is not None:
                lat_ticks.append(hit["tick"] - tick)
                by_sample.append([index, k, hit["tick"] - tick])
        res["latency"] = {"samples_cutting": counted, "never_visible": never,
                          "ms": dist(lat_ms), "ticks": dist(lat_ticks),
                          "by_sample": by_sample}

    def judge(self, res, case):
        a = self.args
        f = res["failures"]
        if res.get("hung"):
            f.append(f"server hung: running but not answering (in "
                     f"{res.get('failed_in', 'the end check')})")
        elif not res.get("alive"):
            f.append(f"server exited with status {res.get('exit_before_shutdown')} (in "
                     f"{res.get('failed_in', 'the end check')})")
        elif res.get("exit_status") not in (0, None):
            f.append(f"server exit status {res.get('exit_status')} after shutdown")
        fr = res.get("frames", {})
        if fr.get("nonfinite"):
            f.append(f"{fr['nonfinite']} non-finite frames")
        if fr.get("exploded"):
            f.append(f"{fr['exploded']} exploded frames (max {fr.get('max_dist_m')} m > "
                     f"{fr.get('bound_m')} m)")
        if fr.get("bad_snapshots"):
            f.append(f"bad get_surface snapshots: {fr['bad_snapshots']}")
        if fr.get("seq_gaps"):
            f.append(f"{fr['seq_gaps']} seq gaps")
        if fr.get("topology_without_arrays"):
            f.append(f"{fr['topology_without_arrays']} topology changes without arrays")
        cut = res.get("cut")
        if cut is not None and "area_cm2" in cut and case is not None:
            if case.expect == "tangent":
                limit = TANGENT_MAX_FRACTION * cut["swept_total_cm2"]
                if cut["area_cm2"] > limit:
                    f.append(f"tangent blade cut {cut['area_cm2']} cm2 > {limit:.3f} cm2")
            elif "completeness" in cut:
                lo, hi = (a.split_min, a.split_max) if res["cutter"] == "split" else \
                    (a.snap_min, a.snap_max)
                if case.reference == "world":
                    lo, hi = lo - a.deformed_slack, hi + a.deformed_slack
                c = cut["completeness"]
                if not (lo <= c <= hi):
                    f.append(f"completeness {c} outside [{lo:.3f}, {hi:.3f}]")
            else:
                f.append("no swept area inside the tissue to compare with")
        elif res.get("alive"):
            f.append("no cut measured")
        tk = res.get("ticks", {})
        worst = (tk.get("stats") or {}).get("worst_tick_ms")
        if a.max_tick_ms is not None and worst is not None and worst > a.max_tick_ms:
            f.append(f"worst tick {worst} ms > {a.max_tick_ms} ms")
        p99 = (res.get("latency", {}).get("ticks") or {}).get("p99")
        if a.max_latency_ticks is not None and p99 is not None and p99 > a.max_latency_ticks:
            f.append(f"command-to-visible p99 {p99} ticks > {a.max_latency_ticks}")
        res["ok"] = not f


# --------------------------------------------------------------------------------------------
# Output


def fmt(v, spec="{:.3f}"):
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "yes" if v else "NO"
    if isinstance(v, float):
        return spec.format(v)
    return str(v)


def table(results):
    cols = ["variant", "case", "ok", "alive", "exit", "bad fr", "gaps", "frames/ticks", "Hz",
            "cut cm2", "ref cm2", "complete", "drift", "worst ms", "over", "step p99",
            "vis p50/p99 t", "cut ms/event max", "wall s"]
    rows = []
    for r in results:
        fr = r.get("frames", {})
        cut = r.get("cut", {})
        tk = r.get("ticks", {})
        st = tk.get("stats") or {}
        lat = r.get("latency", {}).get("ticks", {})
        rows.append([
            r["variant"], r["case"], "PASS" if r["ok"] else "FAIL", fmt(r.get("alive")),
            fmt(r.get("exit_status")),
            f"{fr.get('nonfinite', 0)}/{fr.get('exploded', 0)}", fmt(fr.get("seq_gaps")),
            f"{tk.get('window_frames', '-')}/{tk.get('window_ticks', '-')}",
            fmt(tk.get("rate_hz"), "{:.1f}"),
            fmt(cut.get("area_cm2"), "{:.2f}"), fmt(cut.get("swept_inside_cm2"), "{:.2f}"),
            fmt(cut.get("completeness"), "{:.3f}"), fmt(cut.get("area_drift"), "{:+.2f}"),
            fmt(st.get("worst_tick_ms"), "{:.1f}"),
            fmt(st.get("ticks_over_budget")),
            fmt(tk.get("stream_step_ms", {}).get("p99"), "{:.1f}"),
            f"{fmt(lat.get('p50'))}/{fmt(lat.get('p99'))}",
            fmt(r.get("cut_ms", {}).get("max"), "{:.1f}"), fmt(r.get("wall_s"), "{:.1f}")])
    widths = [max(len(str(x)) for x in col) for col in zip(cols, *rows)]
    line = lambda row: "  ".join(str(x).ljust(w) for x, w in zip(row, widths))
    out = [line(cols), line(["-" * w for w in widths])]
    out += [line(r) for r in rows]
    for r in results:
        if r["failures"]:
            out.append(f"{r['variant']} {r['case']}: " + "; ".join(r["failures"]))
    return "\n".join(out)


def markdown(results):
    """Per scene, the cases as rows and the cutters side by side (for docs/perf.md)."""
    out = []
    scenes = list(dict.fromkeys(r["scene"] for r in results))
    for scene in scenes:
        rs = [r for r in results if r["scene"] == scene]
        cutters = list(dict.fromkeys(r["cutter"] for r in rs))
        head = ["case"]
        for c in cutters:
            head += [f"{c}: completeness", "up", "worst tick ms", "Hz cutting", "cut ms/event max"]
        out.append(f"**{scene}**\n")
        out.append("| " + " | ".join(head) + " |")
        out.append("|" + "---|" * len(head))
        for case in dict.fromkeys(r["case"] for r in rs):
            row = [case]
            for c in cutters:
                r = next((x for x in rs if x["case"] == case and x["cutter"] == c), None)
                if r is None:
                    row += ["-"] * 5
                    continue
                cut = r.get("cut", {})
                comp = cut.get("completeness")
                if comp is None and "area_cm2" in cut:
                    comp_s = f"{cut['area_cm2']:.2f} cm2 (tangent)"
                else:
                    comp_s = fmt(comp, "{:.3f}")
                fr = r.get("frames", {})
                if fr.get("exploded") or fr.get("nonfinite"):
                    comp_s += f" ({fr.get('exploded', 0) + fr.get('nonfinite', 0)} bad frames)"
                up = "hung" if r.get("hung") else ("yes" if r.get("alive") else
                                                   f"exit {r.get('exit_before_shutdown')}")
                tk = r.get("ticks", {})
                row += [comp_s, up, fmt((tk.get("stats") or {}).get("worst_tick_ms"), "{:.0f}"),
                        fmt(tk.get("rate_hz"), "{:.1f}"),
                        fmt(r.get("cut_ms", {}).get("max"), "{:.0f}")]
            out.append("| " + " | ".join(row) + " |")
        out.append("")
    return "\n".join(out)


# --------------------------------------------------------------------------------------------


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--server-bin", default=os.path.join(REPO, "build", "release", "server",
                                                         "polycut-server"))
    p.add_argument("--scene", action="append", help="scene file (repeatable; default "
                   "assets/scenes/default.json)")
    p.add_argument("--cutters", default="snap,split",
                   help="comma list of snap (tet + face snapping), split (mvc + cell splitting), "
                   "asis (the scene's own); default snap,split")
    p.add_argument("--organ", action="store_true", help="also the blob organ (CGAL, ~5k nodes; "
                   "slow)")
    p.add_argument("--organ-only", action="store_true", help="only the organ")
    p.add_argument("--organ-scene", help="a scene file for the organ instead of the built-in "
                   "blob")
    p.add_argument("--organ-cell-size", type=float, default=0.0028)
    p.add_argument("--cases", help="comma list of case names or fnmatch patterns")
    p.add_argument("--quick", action="store_true",
                   help=f"only {','.join(QUICK_CASES)} (the ctest live_cut subset)")
    p.add_argument("--list", action="store_true", help="list the cases and exit")
    p.add_argument("--heavy", action="store_true", help="many_strokes with 1000 strokes")
    p.add_argument("--many", type=int, default=100, help="strokes of many_strokes (100)")
    p.add_argument("--many-samples", type=int, default=13,
                   help="samples per stroke of many_strokes (13 = 0.2 s)")
    p.add_argument("--no-gravity", action="store_true",
                   help="remove gravity from the scenes (world = rest: exact degenerate blades)")
    p.add_argument("--rate", type=float, default=60.0)
    p.add_argument("--stroke-seconds", type=float, default=3.0)
    p.add_argument("--settle", type=float, default=0.5, help="seconds between resume and the "
                   "first action")
    p.add_argument("--post", type=float, default=0.5, help="seconds the stream is watched after "
                   "the cut")
    p.add_argument("--split-min", type=float, default=SPLIT_MIN)
    p.add_argument("--split-max", type=float, default=SPLIT_MAX)
    p.add_argument("--snap-min", type=float, default=SNAP_MIN)
    p.add_argument("--snap-max", type=float, default=SNAP_MAX)
    p.add_argument("--deformed-slack", type=float, default=DEFORMED_SLACK)
    p.add_argument("--explode-diagonals", type=float, default=EXPLODED_DIAGONALS,
                   help="a frame is exploded when a vertex lies further than this many rest "
                   "bounding-box diagonals from the rest centre (3)")
    p.add_argument("--max-tick-ms", type=float, help="also fail when get_stats.worst_tick_ms "
                   "exceeds this")
    p.add_argument("--max-latency-ticks", type=float,
                   help="also fail when command-to-visible p99 exceeds this many ticks")
    p.add_argument("--no-assert", action="store_true", help="benchmark mode: report, exit 0")
    p.add_argument("--json", metavar="OUT", help="write all results to OUT")
    p.add_argument("--markdown", action="store_true", help="also print a markdown table per "
                   "scene (cases x cutters)")
    p.add_argument("--from-json", metavar="FILE", help="run nothing: print the table (and "
                   "--markdown) of a --json file")
    p.add_argument("--log-dir", help="keep the servers' stderr and scenes here")
    p.add_argument("--reply-timeout", type=float, help="seconds to wait for a reply before "
                   "the server counts as hung (default 30, 15 with --quick)")
    p.add_argument("--start-timeout", type=float, default=600.0)
    p.add_argument("--case-timeout", type=float, default=900.0)
    return p.parse_args(argv)


def environment(args):
    """What was measured: the binary's build time and the source tree's commit."""
    env = {"server_bin": os.path.abspath(args.server_bin), "python": sys.version.split()[0],
           "cpus": os.cpu_count(), "time": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    try:
        env["server_bin_mtime"] = time.strftime(
            "%Y-%m-%dT%H:%M:%S%z", time.localtime(os.path.getmtime(args.server_bin)))
    except OSError:
        pass
    try:
        import subprocess
        env["git_head"] = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"],
                                         capture_output=True, text=True).stdout.strip()
        env["git_dirty"] = bool(subprocess.run(
            ["git", "-C", REPO, "status", "--porcelain", "--untracked-files=no"],
            capture_output=True, text=True).stdout.strip())
    except OSError:
        pass
    return env


def main(argv=None):
    args = parse_args(argv)
    if args.reply_timeout is None:
        args.reply_timeout = 15.0 if args.quick else 30.0
    if args.from_json:
        results = load_json(args.from_json)["results"]
        print(table(results))
        if args.markdown:
            print()
            print(markdown(results))
        return 0
    live.self_test()
    variants = build_variants(args)
    patterns = ",".join(QUICK_CASES) if args.quick and not args.cases else args.cases
    if args.list:
        for v in variants:
            print(f"{v.name} ({v.cutter}, {'box' if v.box is not None else 'other geometry'}):")
            if v.box is None:
                print("  (cases depend on the rest surface; the same names as below, "
                      "centre_plane instead of grid_plane_y0, no along_edges)")
                continue
            fake = {"positions": np.array([v.box["lo"], v.box["hi"]])}
            frame = Frame(v, fake)
            frame.rest_positions = fake["positions"]
            for c in select(cases_for(frame, args), patterns):
                print(f"  {c.name}: {c.description}")
        return 0
    if not os.path.exists(args.server_bin):
        print(f"polycut_incision: no server binary at {args.server_bin} (build the release "
              f"preset or pass --server-bin)", file=sys.stderr)
        return 2
    logdir = args.log_dir or tempfile.mkdtemp(prefix="polycut_incision_")
    os.makedirs(logdir, exist_ok=True)
    results = []
    try:
        for v in variants:
            factory = lambda frame, v=v: cases_for(frame, args)
            # The case list depends on the rest surface only through positions; names are known
            # from a box stand-in or from the geometry kind.
            if v.box is not None:
                fake = {"positions": np.array([v.box["lo"], v.box["hi"]])}
            else:
                fake = {"positions": np.array([[-0.05, -0.03, 0.0], [0.05, 0.03, 0.045]])}
            frame = Frame(v, fake)
            frame.rest_positions = fake["positions"]
            names = [c.name for c in select(cases_for(frame, args), patterns)]
            for name in names:
                r = Runner(args, v, factory, logdir).run(name)
                results.append(r)
                print(json.dumps(r), flush=True)
    finally:
        if args.json:
            with open(args.json, "w") as f:
                json.dump({"environment": environment(args), "args": vars(args),
                           "results": results}, f, indent=1)
        if not args.log_dir:
            shutil.rmtree(logdir, ignore_errors=True)
    print()
    print(table(results), flush=True)
    if args.markdown:
        print()
        print(markdown(results), flush=True)
    failed = [r for r in results if not r["ok"]]
    print(f"\n{len(results) - len(failed)} of {len(results)} cases passed"
          f"{' (not asserted: --no-assert)' if args.no_assert else ''}", flush=True)
    if not results:
        print("polycut_incision: no case selected", file=sys.stderr)
        return 2
    return 0 if (args.no_assert or not failed) else 1


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
    except BrokenPipeError:  # output piped into head
        sys.exit(0)
    except Exception:  # a harness error, not a finding: exit status 2
        import traceback
        traceback.print_exc()
        sys.exit(2)
