#!/usr/bin/python3
"""Reads .vtu files with meshio and prints, as a JSON list (one entry per file given on the
command line), what the C++ test compares:
point and cell counts, cell counts per meshio cell type, the cell volumes (sorted, from the
points in the file, by the divergence theorem over outward face loops), and per field its
number of components, Frobenius norm and column sums. Run with /usr/bin/python3 (Debian's
python3-meshio)."""
import json
import sys

import meshio
import numpy as np

# Outward face loops of VTK cells, local node numbers (as in polycut/mesh/mesh.hpp).
TET_FACES = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
HEX_FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]


def volume(points, loops):
    """Signed volume of a polyhedron given as outward loops of point ids (fan from each
    loop's vertex mean, exact for planar loops)."""
    v = 0.0
    for loop in loops:
        p = points[np.asarray(loop)]
        m = p.mean(axis=0)
        q = np.roll(p, -1, axis=0)
        v += np.einsum("ij,ij->i", np.broadcast_to(m, p.shape), np.cross(p, q)).sum()
    return v / 6.0


def cell_loops(block):
    if block.type == "tetra":
        return [[c[f] for f in TET_FACES] for c in block.data]
    if block.type == "hexahedron":
        return [[c[f] for f in HEX_FACES] for c in block.data]
    if block.type.startswith("polyhedron"):
        return [[np.asarray(f) for f in cell] for cell in block.data]
    raise SystemExit(f"unexpected cell type {block.type}")


def block_volumes(points, block):
    return [volume(points, c) for c in cell_loops(block)]


def field_summary(arrays):
    a = np.concatenate([np.asarray(x, dtype=float).reshape(len(x), -1) for x in arrays])
    return {
        "components": int(a.shape[1]),
        "rows": int(a.shape[0]),
        "norm": float(np.linalg.norm(a)),
        "sums": [float(s) for s in a.sum(axis=0)],
    }


def summary(path):
    mesh = meshio.read(path)
    points = np.asarray(mesh.points, dtype=float)
    volumes = []
    types = {}
    for block in mesh.cells:
        types[block.type] = types.get(block.type, 0) + len(block.data)
        volumes += block_volumes(points, block)
    out = {
        "points": int(len(points)),
        "cells": int(len(volumes)),
        "types": types,
        "volumes": sorted(volumes),
        "point_data": {k: field_summary([v]) for k, v in mesh.point_data.items()},
        # meshio splits cell data by cell block (and may order the blocks differently from
        # the cells for polyhedra), so only order-free summaries are compared.
        "cell_data": {k: field_summary(v) for k, v in mesh.cell_data.items()},
    }
    # Polyhedral files carry each cell's index in the polycut mesh: volumes in mesh order.
    if "polycut_cell" in mesh.cell_data:
        ids = np.concatenate([np.asarray(x).ravel() for x in mesh.cell_data["polycut_cell"]])
        by_cell = [0.0] * len(volumes)
        for i, v in zip(ids, (v for block in mesh.cells for v in block_volumes(points, block))):
            by_cell[int(i)] = v
        out["volumes_by_cell"] = by_cell
    return out


def main():
    json.dump([summary(path) for path in sys.argv[1:]], sys.stdout)


if __name__ == "__main__":
    main()
