#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_mesh_reader and fuzz_pipeline (small valid
inputs; the first byte of a mesh input picks the extension: 0 .ply, 1 .obj,
2 .off, 3 .stl, 4 .vtk). The image reader's corpus comes from ITK's writers:
build-fuzz/test/fuzz/fuzz_make_image_corpus test/fuzz/corpus/fuzz_image_reader
Usage: python3 test/fuzz/make_corpus.py   (from anywhere)"""
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))

# A closed, outward tetrahedron and an octahedron (mm).
tet_v = [(0, 0, 0), (4, 0, 0), (0, 4, 0), (0, 0, 4)]
tet_f = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
oct_v = [(5, 0, 0), (-5, 0, 0), (0, 5, 0), (0, -5, 0), (0, 0, 5), (0, 0, -5)]
oct_f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]


def ply_ascii(v, f):
    s = "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n" % len(v)
    s += "property int generation\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(f)
    s += "".join("%g %g %g 0\n" % p for p in v) + "".join("3 %d %d %d\n" % t for t in f)
    return s.encode()


def ply_binary(v, f):
    s = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
         "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(v), len(f)))
    b = s.encode() + b"".join(struct.pack("<3f", *p) for p in v)
    return b + b"".join(struct.pack("<B3i", 3, *t) for t in f)


def obj(v, f):
    return ("# gdm\n" + "".join("v %g %g %g\n" % p for p in v) + "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in f)).encode()


def obj_quads():
    v = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)]
    q = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return ("".join("v %g %g %g\n" % p for p in v) + "vn 0 0 1\n" +
            "".join("f %d//1 %d//1 %d//1 %d//1\n" % tuple(i + 1 for i in t) for t in q)).encode()


def off(v, f):
    return ("OFF\n%d %d 0\n" % (len(v), len(f)) + "".join("%g %g %g\n" % p for p in v) +
            "".join("3 %d %d %d\n" % t for t in f)).encode()


def stl_ascii(v, f):
    s = "solid gdm\n"
    for t in f:
        s += " facet normal 0 0 0\n  outer loop\n" + "".join("   vertex %g %g %g\n" % v[i] for i in t)
        s += "  endloop\n endfacet\n"
    return (s + "endsolid gdm\n").encode()


def stl_binary(v, f):
    b = b"gdm".ljust(80, b" ") + struct.pack("<I", len(f))
    for t in f:
        b += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v[i]) for i in t) + b"\0\0"
    return b


def vtk_ascii(v, f):
    s = "# vtk DataFile Version 3.0\ngdm\nASCII\nDATASET POLYDATA\nPOINTS %d double\n" % len(v)
    s += "".join("%g %g %g\n" % p for p in v) + "POLYGONS %d %d\n" % (len(f), 4 * len(f))
    s += "".join("3 %d %d %d\n" % t for t in f)
    s += "POINT_DATA %d\nSCALARS generation int 1\nLOOKUP_TABLE default\n" % len(v) + "0\n" * len(v)
    return s.encode()


def vtk_binary(v, f):
    s = ("# vtk DataFile Version 3.0\ngdm\nBINARY\nDATASET POLYDATA\nPOINTS %d float\n" % len(v)).encode()
    s += b"".join(struct.pack(">3f", *p) for p in v) + ("\nPOLYGONS %d %d\n" % (len(f), 4 * len(f))).encode()
    return s + b"".join(struct.pack(">4i", 3, *t) for t in f) + b"\n"


def write(target, name, data):
    d = os.path.join(here, "corpus", target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as out:
        out.write(data)


meshes = {
    "ply_ascii_tet": (0, ply_ascii(tet_v, tet_f)), "ply_binary_oct": (0, ply_binary(oct_v, oct_f)),
    "obj_tet": (1, obj(tet_v, tet_f)), "obj_quads_cube": (1, obj_quads()),
    "off_oct": (2, off(oct_v, oct_f)), "stl_ascii_tet": (3, stl_ascii(tet_v, tet_f)),
    "stl_binary_oct": (3, stl_binary(oct_v, oct_f)), "vtk_ascii_tet": (4, vtk_ascii(tet_v, tet_f)),
    "vtk_binary_oct": (4, vtk_binary(oct_v, oct_f)),
}
for name, (ext, data) in meshes.items():
    write("fuzz_mesh_reader", name, bytes([ext]) + data)


# fuzz_pipeline: dims (3 bytes, 4 + b % 9), spacing (3 table indices), value
# mode, then for a blob: centre (3), radius, noise, scale, [noise bytes], then
# global refinements, threshold mode [, threshold], option count, options.
def pipeline(dims, spacing, mode, blob=None, refinements=0, threshold=None, options=()):
    b = bytes(d - 4 for d in dims) + bytes(spacing) + bytes([mode])
    if blob is not None:
        b += bytes(blob)
    b += bytes([refinements])
    b += bytes([0, int(threshold * 2)]) if threshold is not None else bytes([1])
    b += bytes([len(options)]) + b"".join(bytes(o) for o in options)
    return b


write("fuzz_pipeline", "blob_otsu", pipeline((10, 10, 10), (0, 0, 0), 0, (5, 5, 5, 3, 0, 0)))
write("fuzz_pipeline", "blob_given_t", pipeline((12, 11, 10), (1, 2, 0), 0, (6, 5, 5, 4, 0, 0), threshold=50))
write("fuzz_pipeline", "blob_refined", pipeline((12, 12, 12), (7, 7, 7), 0, (6, 6, 6, 4, 0, 0), refinements=1))
write("fuzz_pipeline", "blob_shrink", pipeline((12, 12, 12), (0, 0, 0), 0, (6, 6, 6, 3, 0, 0), threshold=50,
                                              options=[(5, 6)]))  # catalogue entry 5 (mode) = table[6] = 1: shrink
write("fuzz_pipeline", "noise_bytes", pipeline((6, 6, 6), (0, 0, 0), 2) + bytes((i * 73) % 256 for i in range(216)))
