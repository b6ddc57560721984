#!/usr/bin/env python3
"""Writes the scripted cut scenes of issue 5 into assets/scenes/ (run with /usr/bin/python3).

Sweep triangles are world-space [m]; a blade is a segment, and two consecutive blade samples
(a0, b0) -> (a1, b1) sweep the triangles (a0, b0, a1) and (b0, b1, a1).
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.dirname(HERE)


def block(method, cells=(4, 4, 4), elements="hex"):
    return {
        "geometry": {"type": "box", "origin": [-0.05, -0.05, 0.0], "size": [0.1, 0.1, 0.1],
                     "cells": list(cells), "elements": elements},
        "method": method,
        "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.3, "density": 1000,
                     "rayleigh_stiffness": 0.02},
        "integrator": {"type": "implicit_euler", "dt": 0.01, "corotated": True},
        "solver": {"type": "pcg", "preconditioner": "block_jacobi", "tolerance": 1e-6},
        "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-9}}],
        "loads": {"gravity": [0, 0, -9.81]},
    }


def sweep(samples):
    """Triangles swept by consecutive blade samples [(a, b), ...]."""
    tris = []
    for (a0, b0), (a1, b1) in zip(samples, samples[1:]):
        tris.append([a0, b0, a1])
        tris.append([b0, b1, a1])
    return tris


def write(name, scene):
    scene = {"name": name, **scene}
    with open(os.path.join(OUT, name + ".json"), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


# cut_halves: a full cut through the middle (x = 0.0125 m, between grid planes), then settling.
x0 = 0.0125
halves = block("mvc")
halves["description"] = ("A 10 cm block fixed at its bottom, cut fully in two by one sweep through "
                         "its middle at tick 5, then left to settle: 2 components.")
halves["cutting"] = {"method": "split", "sweeps": [{"tick": 5, "triangles": sweep(
    [([x0, -0.08, 0.13], [x0, -0.08, -0.03]), ([x0, 0.08, 0.13], [x0, 0.08, -0.03])])}]}
halves["output"] = {"steps": 40, "vtu_every": 10}
write("cut_halves", halves)

# cut_halves_tet: the same with P1 tets and face snapping (seed 002).
halves_tet = block("tet", cells=(6, 6, 6), elements="tet")
halves_tet["description"] = "cut_halves on Kuhn tets with face snapping (seed 002 sec. 3.2)."
halves_tet["cutting"] = {"method": "snap", "sweeps": halves["cutting"]["sweeps"]}
halves_tet["output"] = {"steps": 40, "vtu_every": 10}
write("cut_halves_tet", halves_tet)

# cut_progressive: a partial incision advancing 2.5 mm per tick across the top, 3 cm deep
# (seed 000 Fig. 8): the blade never leaves the tissue until the end.
prog = block("mvc")
prog["description"] = ("A partial incision advancing over 30 ticks across the block's top, "
                       "3 cm deep (seed 000 Fig. 8).")
steps = []
for k in range(31):
    y = -0.0375 + 0.0025 * k
    steps.append({"tick": 2 + k, "blade": ([x0, y, 0.11], [x0, y, 0.07])})
prog["cutting"] = {"method": "split", "sweeps": [
    {"tick": s1["tick"], "triangles": sweep([s0["blade"], s1["blade"]])}
    for s0, s1 in zip(steps, steps[1:])]}
prog["output"] = {"steps": 45, "vtu_every": 5}
write("cut_progressive", prog)

# cut_slices: five 1 mm slices off one side (seed 000 Fig. 9-10).
slices = block("mvc")
slices["description"] = "Five thin slices, 1 mm thick, cut off the +x side (seed 000 Fig. 9-10)."
slices["cutting"] = {"method": "split", "sweeps": [
    {"tick": 2 + 2 * i, "triangles": sweep([([0.045 - 0.001 * i, -0.08, 0.13], [0.045 - 0.001 * i, -0.08, -0.03]),
                                            ([0.045 - 0.001 * i, 0.08, 0.13], [0.045 - 0.001 * i, 0.08, -0.03])])}
    for i in range(5)]}
slices["fixed"] = [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-9}}]
slices["output"] = {"steps": 20, "vtu_every": 5}
write("cut_slices", slices)

# cut_pencil: one convex cell sharpened by many cuts (seed 003 Fig. 7): planes tilted toward the
# top around the vertical axis remove chips; each chip falls away.
pencil = block("mvc", cells=(1, 1, 1))
pencil["description"] = ("A single 10 cm cell sharpened to a point by 12 planar cuts (seed 003 "
                         "Fig. 7); the chips fall away under gravity.")
sweeps = []
for i in range(12):
    phi = 2 * math.pi * i / 12
    n = [math.cos(phi), math.sin(phi)]
    t = [-n[1], n[0]]
    # Plane through (0.035 n, z = 0.1) leaning inward by 30 degrees: above z ~ 0.04 it removes a chip.
    top = [0.02 * n[0], 0.02 * n[1], 0.101]
    bot = [0.06 * n[0], 0.06 * n[1], 0.03]
    a0 = [top[0] - 0.12 * t[0], top[1] - 0.12 * t[1], top[2]]
    b0 = [bot[0] - 0.12 * t[0], bot[1] - 0.12 * t[1], bot[2]]
    a1 = [top[0] + 0.12 * t[0], top[1] + 0.12 * t[1], top[2]]
    b1 = [bot[0] + 0.12 * t[0], bot[1] + 0.12 * t[1], bot[2]]
    sweeps.append({"tick": 1 + i, "triangles": sweep([(a0, b0), (a1, b1)])})
pencil["cutting"] = {"method": "split", "sweeps": sweeps}
pencil["output"] = {"steps": 20, "vtu_every": 5}
write("cut_pencil", pencil)
