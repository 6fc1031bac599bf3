#!/usr/bin/env python3
"""Writes the seed corpora of the mesh fuzzers (corpus/{off,obj,ply,stl}):
small valid meshes in every variant the readers accept (a tetrahedron and an
octahedron; comments, CRLF, tabs, colors, quads, hex floats, big endian,
extra elements). Run once; the seeds are in the repository. The malformed
files of tests/data/malformed are seeds too (scripts/fuzz.sh adds them)."""
import os
import struct
import sys

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
V = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
F = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5),
     (3, 1, 5), (0, 3, 5)]
TV = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TF = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def write(kind, name, data):
    os.makedirs(os.path.join(OUT, kind), exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(OUT, kind, name), "wb") as f:
        f.write(data)


def off(vs, fs, sep=" ", eol="\n", counts_on_keyword=False, extra=""):
    s = "OFF" + (sep + "%d %d 0" % (len(vs), len(fs)) if counts_on_keyword
                 else eol + "# comment" + eol + "%d%s%d%s0" % (len(vs), sep, len(fs), sep))
    s += eol
    for v in vs:
        s += sep.join(str(c) for c in v) + eol
    for f in fs:
        s += "3" + sep + sep.join(str(i) for i in f) + extra + eol
    return s


def obj(vs, fs, eol="\n", slashes=False):
    s = "# octahedron" + eol + "mtllib m.mtl" + eol + "o x" + eol
    for v in vs:
        s += "v %r %r %r%s" % (float(v[0]), float(v[1]), float(v[2]), eol)
    s += "vn 0 0 1" + eol + "vt 0 0" + eol
    for f in fs:
        if slashes:
            s += "f " + " ".join("%d/1/1" % (i + 1) for i in f) + eol
        else:
            s += "f " + " ".join(str(i + 1) for i in f) + eol
    return s


def ply_header(fmt, nv, nf, vtype="float", itype="int", ctype="uchar"):
    return ("ply\nformat %s 1.0\ncomment seed\nelement vertex %d\n"
            "property %s x\nproperty %s y\nproperty %s z\nelement face %d\n"
            "property list %s %s vertex_indices\nend_header\n"
            % (fmt, nv, vtype, vtype, vtype, nf, ctype, itype)).encode()


def ply_binary(vs, fs, endian, vtype="f", pv="float"):
    out = ply_header("binary_little_endian" if endian == "<" else
                     "binary_big_endian", len(vs), len(fs), vtype=pv)
    for v in vs:
        out += struct.pack(endian + vtype * 3, *v)
    for f in fs:
        out += struct.pack(endian + "B3i", 3, *f)
    return out


def stl_ascii(vs, fs):
    s = "solid seed\n"
    for f in fs:
        s += " facet normal 0 0 0\n  outer loop\n"
        for i in f:
            s += "   vertex %r %r %r\n" % tuple(float(c) for c in vs[i])
        s += "  endloop\n endfacet\n"
    return s + "endsolid seed\n"


def stl_binary(vs, fs, header=b"binary seed"):
    out = header.ljust(80, b" ") + struct.pack("<I", len(fs))
    for f in fs:
        out += struct.pack("<3f", 0, 0, 0)
        for i in f:
            out += struct.pack("<3f", *vs[i])
        out += b"\0\0"
    return out


write("off", "octahedron.off", off(V, F))
write("off", "tetrahedron_crlf_tabs.off", off(TV, TF, sep="\t", eol="\r\n"))
write("off", "counts_on_keyword_colors.off",
      off(V, F, counts_on_keyword=True, extra=" 0.7 0 0"))
write("off", "hex_and_big.off",
      "COFF\n4 4 0\n0x1p-3 1e300 0 255 0 0\n1 0 0 1 1 1\n0 1 0 1 1 1\n"
      "0 0 1 1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
write("off", "quads.off",
      "OFF\n8 6 12\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n")
write("obj", "octahedron.obj", obj(V, F))
write("obj", "tetrahedron_slashes_crlf.obj", obj(TV, TF, eol="\r\n", slashes=True))
write("obj", "forward_and_quads.obj",
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1 1\nv 1 0 1\nv 1 1 1 0.5 0.5 0.5\nv 0 1 1\n")
asc = ply_header("ascii", len(V), len(F))
for v in V:
    asc += ("%r %r %r\n" % tuple(float(c) for c in v)).encode()
for f in F:
    asc += ("3 %d %d %d\n" % f).encode()
write("ply", "octahedron_ascii.ply", asc)
write("ply", "octahedron_le_float.ply", ply_binary(V, F, "<"))
write("ply", "octahedron_be_double.ply", ply_binary(V, F, ">", "d", "double"))
extra = (b"ply\r\nformat binary_little_endian 1.0\r\nobj_info x\r\nelement vertex 4\r\n"
         b"property uchar red\r\nproperty short x\r\nproperty short y\r\nproperty short z\r\n"
         b"property list uchar float uv\r\nelement edge 1\r\nproperty int a\r\n"
         b"element face 4\r\nproperty list ushort uint vertex_index\r\nend_header\r\n")
for v in TV:
    extra += struct.pack("<B3hBf", 9, *v, 1, 0.5)
extra += struct.pack("<i", 0)
for f in TF:
    extra += struct.pack("<H3I", 3, *f)
write("ply", "tetrahedron_extra_elements.ply", extra)
write("stl", "octahedron_ascii.stl", stl_ascii(V, F))
write("stl", "octahedron_binary.stl", stl_binary(V, F))
write("stl", "tetrahedron_binary_solid_header.stl",
      stl_binary(TV, TF, header=b"solid but binary"))
write("stl", "two_solids.stl", stl_ascii(TV, TF[:2]) + stl_ascii(TV, TF[2:]))
