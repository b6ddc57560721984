#!/usr/bin/python3
"""Writes the seed corpus of fuzz_cut (tests/fuzz/fuzz_cut.cpp documents the format): per mesh
(tet grid, hex grid, CGAL sphere) and cutter, blades in face planes, through nodes (exact and
nudged), along edges, random, and fans, with and without steps between the cut calls.

    make_cut_seeds.py OUT_DIR
"""
import os
import random
import struct
import sys


def record(mode, *w, end=False):
    w = list(w) + [0] * (9 - len(w))
    return bytes([mode + (5 if end else 0)]) + struct.pack("<9H", *[v & 0xFFFF for v in w])


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rng = random.Random(14)
    seeds = {}
    for mesh, mesh_name in ((0, "tetgrid"), (1, "hexgrid"), (2, "sphere")):
        for split in (0, 1):
            if mesh == 1 and split == 0:
                continue
            cutter = "split" if split else "snap"
            for steps in (0, 2):
                head = bytes([split | (mesh << 1) | (steps << 3)])
                tag = f"{mesh_name}_{cutter}_s{steps}"
                # One face plane, then two more in one call (a blade along a grid plane).
                seeds[f"{tag}_face_planes"] = head + record(1, 7, 40000, 40000, 40000, end=True) \
                    + record(1, 23, 65535, 65535, 65535) + record(1, 24, 65535, 20000, 65535)
                seeds[f"{tag}_through_nodes"] = head + record(2, 3, 17, 29, end=True) \
                    + record(2, 5, 11, 40, 0, 0, 0, 0, 0, 0)
                seeds[f"{tag}_nudged_nodes"] = head + record(2, 3, 17, 29, 0, 0, 0, 0, 9000, 1)
                seeds[f"{tag}_along_edges"] = head + record(3, 12, 1, 30000, 500, 60000, 32000,
                                                            end=True) \
                    + record(3, 40, 7, 0, 65000, 100, 32000)
                seeds[f"{tag}_random"] = head + b"".join(
                    record(0, *[rng.randrange(65536) for _ in range(9)], end=k % 3 == 2)
                    for k in range(6))
                seeds[f"{tag}_fan"] = head + record(0, *[rng.randrange(65536) for _ in range(9)]) \
                    + record(4, *[rng.randrange(65536) for _ in range(9)]) \
                    + record(4, *[rng.randrange(65536) for _ in range(9)], end=True)
    for name, data in seeds.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
    print(f"{len(seeds)} seeds in {out}")


if __name__ == "__main__":
    main()
