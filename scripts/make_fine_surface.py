#!/usr/bin/python3
"""Loop subdivision of a closed triangle surface (OFF in, OFF out): the detailed surfaces that
scenes embed in a coarser simulation mesh (docs/scenes.md "embedded", issue 15 item 2).

Each level splits every triangle in four and moves the vertices by Loop's rules (Warren's
weights), so the result is a smooth surface with 4^levels times the triangles; it lies within a
fraction of the coarse edge length of the input.

Usage: make_fine_surface.py IN.off OUT.off LEVELS
    assets/meshes/liver_blob_20k.off = make_fine_surface.py assets/meshes/liver_blob.off ... 2
"""
import sys

import numpy as np


def read_off(path):
    tokens = [l for l in open(path).read().split("\n") if l.strip() and not l.startswith("#")]
    assert tokens[0].strip() == "OFF"
    nv, nf = map(int, tokens[1].split()[:2])
    v = np.array([list(map(float, l.split()[:3])) for l in tokens[2:2 + nv]])
    f = np.array([list(map(int, l.split()[1:4])) for l in tokens[2 + nv:2 + nv + nf]])
    return v, f


def loop(v, f):
    edges = {}
    new_f = []
    mids = []
    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in edges:
            edges[key] = len(v) + len(mids)
            mids.append(key)
        return edges[key]
    for a, b, c in f:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        new_f += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
    # Opposite vertices of every edge (closed manifold: exactly two).
    opposite = {}
    for a, b, c in f:
        for x, y, z in ((a, b, c), (b, c, a), (c, a, b)):
            opposite.setdefault((min(x, y), max(x, y)), []).append(z)
    edge_points = np.array([0.375 * (v[a] + v[b]) + 0.125 * (v[opposite[(a, b)][0]] + v[opposite[(a, b)][1]])
                            for a, b in mids])
    neighbours = [set() for _ in range(len(v))]
    for a, b in mids:
        neighbours[a].add(b)
        neighbours[b].add(a)
    moved = np.empty_like(v)
    for i, nb in enumerate(neighbours):
        n = len(nb)
        beta = 3.0 / 16.0 if n == 3 else 3.0 / (8.0 * n)
        moved[i] = (1 - n * beta) * v[i] + beta * v[list(nb)].sum(axis=0)
    return np.vstack([moved, edge_points]), np.array(new_f)


def main():
    v, f = read_off(sys.argv[1])
    for _ in range(int(sys.argv[3])):
        v, f = loop(v, f)
    with open(sys.argv[2], "w") as out:
        out.write(f"OFF\n{len(v)} {len(f)} 0\n")
        out.writelines(f"{x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in v)
        out.writelines(f"3 {a} {b} {c}\n" for a, b, c in f)


if __name__ == "__main__":
    main()
