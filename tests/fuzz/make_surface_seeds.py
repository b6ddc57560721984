#!/usr/bin/python3
"""Writes the seed corpus of fuzz_surface_readers (tests/fuzz/fuzz_surface_readers.cpp): byte 0
picks the extension (0 .off, 1 .stl, 2 .ply, 3 .obj; +4 upper case), the rest is the file. Valid
seeds: a tetrahedron and an open/closed box in every format and encoding, the quad cube of
tests/meshing/data; hostile ones: truncated, huge declared counts, negative and out-of-range ids,
NaN and inf coordinates, a binary STL whose triangle count exceeds its size, a self-intersecting
and an inward surface, garbage.

    make_surface_seeds.py OUT_DIR
"""
import os
import struct
import sys

OFF, STL, PLY, OBJ = 0, 1, 2, 3
UPPER = 4

TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]  # outward
# Unit cube as quads, outward.
CUBE_V = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
CUBE_Q = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]


def num(v):
    return repr(float(v)) if isinstance(v, float) else str(v)


def off_ascii(vs, fs, counts=None):
    nv, nf = counts or (len(vs), len(fs))
    out = f"OFF\n{nv} {nf} 0\n"
    out += "".join(" ".join(num(c) for c in v) + "\n" for v in vs)
    out += "".join(f"{len(f)} " + " ".join(str(i) for i in f) + "\n" for f in fs)
    return out.encode()


def off_binary(vs, fs):
    out = b"OFF BINARY\n" + struct.pack(">3i", len(vs), len(fs), 0)
    for v in vs:
        out += struct.pack(">3f", *v)
    for f in fs:
        out += struct.pack(f">{len(f) + 2}i", len(f), *f, 0)
    return out


def triangles(fs):
    for f in fs:
        for k in range(1, len(f) - 1):
            yield (f[0], f[k], f[k + 1])


def stl_ascii(vs, fs):
    out = "solid seed\n"
    for t in triangles(fs):
        out += " facet normal 0 0 0\n  outer loop\n"
        out += "".join("   vertex " + " ".join(num(c) for c in vs[i]) + "\n" for i in t)
        out += "  endloop\n endfacet\n"
    return (out + "endsolid seed\n").encode()


def stl_binary(vs, fs, count=None, header=b"binary seed"):
    ts = list(triangles(fs))
    out = header.ljust(80, b" ") + struct.pack("<I", len(ts) if count is None else count)
    for t in ts:
        out += struct.pack("<3f", 0, 0, 0)
        for i in t:
            out += struct.pack("<3f", *vs[i])
        out += struct.pack("<H", 0)
    return out


def ply_header(fmt, nv, nf, coord="float", list_types="uchar int"):
    return (f"ply\nformat {fmt} 1.0\ncomment seed\nelement vertex {nv}\n"
            f"property {coord} x\nproperty {coord} y\nproperty {coord} z\n"
            f"element face {nf}\nproperty list {list_types} vertex_indices\nend_header\n").encode()


def ply_ascii(vs, fs):
    out = ply_header("ascii", len(vs), len(fs))
    out += "".join(" ".join(num(c) for c in v) + "\n" for v in vs).encode()
    out += "".join(f"{len(f)} " + " ".join(str(i) for i in f) + "\n" for f in fs).encode()
    return out


def ply_binary(vs, fs, big=False):
    e = ">" if big else "<"
    out = ply_header("binary_big_endian" if big else "binary_little_endian", len(vs), len(fs),
                     coord="double")
    for v in vs:
        out += struct.pack(e + "3d", *v)
    for f in fs:
        out += struct.pack(e + "B" + "i" * len(f), len(f), *f)
    return out


def obj(vs, fs, comment="# seed\n"):
    out = comment + "o seed\n"
    out += "".join("v " + " ".join(num(c) for c in v) + "\n" for v in vs)
    out += "".join("f " + " ".join(f"{i + 1}/{i + 1}" if k == 0 else str(i + 1)
                                   for k, i in enumerate(f)) + "\n" for f in fs)
    return out.encode()


def seeds():
    here = os.path.dirname(os.path.abspath(__file__))
    cube_quads = open(os.path.join(here, "..", "meshing", "data", "cube_quads.obj"), "rb").read()
    open_box = CUBE_Q[1:]  # one side missing: PMP fills the hole
    inward = [tuple(reversed(f)) for f in TET_F]
    # Two tets through each other: closed 2-manifold pieces that intersect.
    crossing_v = TET_V + [(0.2, 0.2, 0.2), (1.2, 0.2, 0.2), (0.2, 1.2, 0.2), (0.2, 0.2, 1.2)]
    crossing_f = TET_F + [tuple(i + 4 for i in f) for f in TET_F]
    s = {
        # valid
        "off_ascii_tet": (OFF, off_ascii(TET_V, TET_F)),
        "off_ascii_cube_quads": (OFF, off_ascii(CUBE_V, CUBE_Q)),
        "off_binary_tet": (OFF, off_binary(TET_V, TET_F)),
        "off_upper_open_box": (OFF | UPPER, off_ascii(CUBE_V, open_box)),
        "stl_ascii_tet": (STL, stl_ascii(TET_V, TET_F)),
        "stl_binary_tet": (STL, stl_binary(TET_V, TET_F)),
        "stl_binary_solid_header_cube": (STL, stl_binary(CUBE_V, CUBE_Q, header=b"solid cube")),
        "ply_ascii_tet": (PLY, ply_ascii(TET_V, TET_F)),
        "ply_binary_le_cube": (PLY, ply_binary(CUBE_V, CUBE_Q)),
        "ply_binary_be_tet": (PLY, ply_binary(TET_V, TET_F, big=True)),
        "obj_tet": (OBJ, obj(TET_V, TET_F)),
        "obj_cube_quads": (OBJ, cube_quads),
        "obj_upper_open_box": (OBJ | UPPER, obj(CUBE_V, open_box)),
        # valid soups that are not closed or clean (accepted without require_closed only)
        "off_ascii_inward_tet": (OFF, off_ascii(TET_V, inward)),
        "ply_ascii_crossing_tets": (PLY, ply_ascii(crossing_v, crossing_f)),
        # hostile
        "off_huge_counts": (OFF, b"OFF\n999999999 1 0\n0 0 0\n"),
        "off_truncated": (OFF, off_ascii(TET_V, TET_F)[:40]),
        "off_negative_id": (OFF, off_ascii(TET_V, TET_F[:3] + [(0, -1, 2)])),
        "off_nan": (OFF, off_ascii([(0, 0, 0), (1, float("nan"), 0)] + TET_V[2:], TET_F)),
        "off_binary_huge_face": (OFF, off_binary(TET_V, TET_F)[:-20]
                                 + struct.pack(">5i", 1 << 30, 0, 1, 2, 0)),
        "stl_binary_count_past_end": (STL, stl_binary(TET_V, TET_F, count=1000000)),
        "stl_ascii_inf": (STL, stl_ascii([(0, 0, 0), (float("inf"), 0, 0)] + TET_V[2:], TET_F)),
        "stl_ascii_no_endfacet": (STL, stl_ascii(TET_V, TET_F).replace(b"endfacet", b"", 1)),
        "ply_huge_list": (PLY, ply_header("ascii", 3, 1, list_types="uint int")
                          + b"0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n"),
        "ply_id_out_of_range": (PLY, ply_ascii(TET_V, TET_F[:3] + [(0, 3, 7)])),
        "ply_binary_truncated": (PLY, ply_binary(CUBE_V, CUBE_Q)[:-7]),
        "ply_int_coords": (PLY, ply_header("ascii", 4, 4, coord="int")
                           + b"0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"),
        "obj_relative_id": (OBJ, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -3\n"),
        "obj_id_out_of_range": (OBJ, obj(TET_V, TET_F[:3] + [(0, 3, 9)])),
        "obj_two_vertex_face": (OBJ, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"),
        "obj_garbage": (OBJ, bytes(range(256))),
    }
    return s


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name, (selector, body) in seeds().items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(bytes([selector]) + body)


if __name__ == "__main__":
    main()
