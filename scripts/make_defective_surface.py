#!/usr/bin/python3
"""Writes assets/meshes/liver_defects.off: the clean organ surface assets/meshes/liver_blob.off
with the defects scanned and segmented surfaces have (issue 18), for the repair tests and the
organ scenes:

- 10 vertices duplicated (same coordinates, new ids) with half of their faces moved to the copy:
  cracks along two edges each, closed again by merging duplicate points;
- 3 faces repeated (2 as they are, 1 reversed): duplicate polygons;
- 2 faces with a repeated vertex id and 3 zero-area "cap" triangles (a, b, m) with m the exact
  midpoint of edge a-b, which split the neighbouring triangle in two (coordinates are snapped to
  a 2^-32 m grid first, so the midpoint is exactly collinear): degenerate faces;
- 2 faces reversed: inconsistent orientation;
- the faces around one vertex removed (5 here): a small hole;
- one vertex pushed past a neighbour along their edge (by half the edge): its fan folds over the
  neighbouring faces, a local self-intersection.

Every choice comes from a fixed seed, so the output is the same on every run. Usage:
    /usr/bin/python3 scripts/make_defective_surface.py [input.off] [output.off]
Prints the defect counts and the clean surface's enclosed volume.
"""

import math
import os
import random
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GRID = 2.0**-32  # [m] coordinate snapping: sums and halves of coordinates stay exact


def read_off(path):
    with open(path) as f:
        tokens = [t for line in f for t in line.split("#")[0].split()]
    assert tokens[0] == "OFF", path
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = 4
    verts = []
    for _ in range(nv):
        verts.append([float(t) for t in tokens[pos:pos + 3]])
        pos += 3
    faces = []
    for _ in range(nf):
        k = int(tokens[pos])
        faces.append([int(t) for t in tokens[pos + 1:pos + 1 + k]])
        pos += 1 + k
    return verts, faces


def volume(verts, faces):
    six_v = 0.0
    for f in faces:
        for k in range(1, len(f) - 1):
            a, b, c = verts[f[0]], verts[f[k]], verts[f[k + 1]]
            six_v += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2])
                      + a[2] * (b[0] * c[1] - b[1] * c[0]))
    return six_v / 6


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "assets/meshes/liver_blob.off")
    dst = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "assets/meshes/liver_defects.off")
    verts, faces = read_off(src)
    verts = [[round(x / GRID) * GRID for x in v] for v in verts]
    clean_volume = volume(verts, faces)
    rng = random.Random(18)
    used = set()  # vertices already touched by a defect: defects stay apart

    def pick_vertex():
        while True:
            v = rng.randrange(len(verts))
            ring = {u for f in faces if v in f for u in f}
            if not ring & used:
                used.update(ring)
                return v

    def faces_of(v):
        return [i for i, f in enumerate(faces) if v in f]

    # Zero-area caps: edge a-b of face (a, b, c) gets its exact midpoint m.
    for _ in range(3):
        v = pick_vertex()
        i = faces_of(v)[0]
        f = faces[i]
        j = f.index(v)
        a, b, c = f[j], f[(j + 1) % 3], f[(j + 2) % 3]
        m = len(verts)
        verts.append([(verts[a][k] + verts[b][k]) / 2 for k in range(3)])
        faces[i] = [a, m, c]
        faces.append([m, b, c])
        faces.append([a, b, m])  # collinear: supplies b->m, m->a and a->b

    # Duplicated vertices with half of their faces moved to the copy.
    for _ in range(10):
        v = pick_vertex()
        copy = len(verts)
        verts.append(list(verts[v]))
        fan = faces_of(v)
        for i in fan[: len(fan) // 2]:
            faces[i] = [copy if u == v else u for u in faces[i]]

    # Faces with a repeated vertex id (they reference an existing edge).
    for _ in range(2):
        v = pick_vertex()
        f = faces[faces_of(v)[0]]
        faces.append([f[0], f[1], f[1]])

    # Reversed faces.
    for _ in range(2):
        v = pick_vertex()
        i = faces_of(v)[0]
        faces[i] = faces[i][::-1]

    # A small hole: the fan of one vertex removed.
    hole_vertex = pick_vertex()
    hole = faces_of(hole_vertex)
    faces = [f for i, f in enumerate(faces) if i not in set(hole)]

    # A fold: one vertex pushed past a neighbour along their edge.
    v = pick_vertex()
    f = faces[faces_of(v)[0]]
    n = f[(f.index(v) + 1) % 3]
    verts[v] = [verts[n][k] + 0.5 * (verts[n][k] - verts[v][k]) for k in range(3)]
    verts[v] = [round(x / GRID) * GRID for x in verts[v]]

    # Repeated faces, appended last (two as they are, one reversed).
    for _ in range(3):
        i = faces_of(pick_vertex())[0]
        faces.append(list(faces[i]))
    faces[-1] = faces[-1][::-1]

    with open(dst, "w") as out:
        out.write("OFF\n")
        out.write("# assets/meshes/liver_blob.off with deliberate defects; generated by\n")
        out.write("# scripts/make_defective_surface.py (see its docstring). Units: metres.\n")
        out.write("%d %d 0\n" % (len(verts), len(faces)))
        for p in verts:
            out.write("%s %s %s\n" % tuple(repr(x) for x in p))
        for f in faces:
            out.write("%d %s\n" % (len(f), " ".join(str(u) for u in f)))
    print("%s: %d vertices, %d faces; hole of %d faces; clean volume %.9e m^3"
          % (os.path.relpath(dst, ROOT), len(verts), len(faces), len(hole), clean_volume))


if __name__ == "__main__":
    main()
