#!/usr/bin/env python3
"""Writes the small files of the malformed corpus into this folder (run once;
the files are in the repository). Every file must make `sdcb check` / `fit`
(meshes) or `sdcb info` / `eval` / `dump` (.sdcb) exit 1 with one sentence
naming it; tests/tools/malformed_corpus_test.sh runs them all, plus large
files it generates itself. Names say what is wrong."""
import os
import random
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
files = {}


def add(name, data):
    files[name] = data.encode("latin-1") if isinstance(data, str) else data


TET_V = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
TET_F = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
OBJ_V = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
OBJ_F = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

# --- OFF -------------------------------------------------------------------
add("off_huge_counts.off", "OFF\n2000000000 2000000000 0\n0 0 0\n")
add("off_negative_counts.off", "OFF\n-5 -3 0\n")
add("off_header_only.off", "OFF\n")
add("off_counts_only.off", "OFF\n4 4 0\n")
add("off_many_corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n999999999 0 1 2\n" + " " * 64)
add("off_truncated_vertices.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n" + " " * 40)
add("off_truncated_faces.off", "OFF\n4 4 0\n" + TET_V + "3 0 2 1\n3 0 1 3\n")
add("off_bad_index.off", "OFF\n4 4 0\n" + TET_V + "3 0 2 1\n3 0 1 9\n3 0 3 2\n3 1 2 3\n")
add("off_negative_index.off", "OFF\n4 4 0\n" + TET_V + "3 0 2 1\n3 0 -1 3\n3 0 3 2\n3 1 2 3\n")
add("off_nan.off", "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n" + TET_F)
add("off_inf.off", "OFF\n4 4 0\n0 0 0\n1 0 -inf\n0 1 0\n0 0 1\n" + TET_F)
add("off_overflow.off", "OFF\n4 4 0\n0 0 0\n1e400 0 0\n0 1 0\n0 0 1\n" + TET_F)
add("off_text_coordinate.off", "OFF\n4 4 0\n0 0 0\n1 abc 0\n0 1 0\n0 0 1\n" + TET_F)
add("off_nul_in_number.off", "OFF\n4 4 0\n0 0 0\n1 0\x00.5 0\n0 1 0\n0 0 1\n" + TET_F)
add("off_two_corners.off", "OFF\n4 4 0\n" + TET_V + "2 0 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
add("off_fewer_corners_listed.off", "OFF\n4 4 0\n" + TET_V + "4 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
add("off_binary.off", "OFF BINARY\n" + "\x00" * 100)
add("off_4d.off", "4OFF\n4 4 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n" + TET_F)
add("off_fractional_counts.off", "OFF\n4.5 4 0\n" + TET_V + TET_F)
add("off_one_count.off", "OFF\n4\n" + TET_V + TET_F)
add("off_comments_only.off", "# nothing\n# here\n")
add("off_no_faces.off", "OFF\n4 0 0\n" + TET_V)
add("off_short_vertex.off", "OFF\n4 4 0\n0 0 0\n1 0\n0 1 0\n0 0 1\n" + TET_F)
add("off_count_overflow.off", "OFF\n99999999999999999999 1 0\n" + TET_V)
add("off_tab_keyword_bad_index.off", "OFF\t4\v4\t0\n" + TET_V + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 4\n")
add("off_wrong_keyword.off", "OBJ\n4 4 0\n" + TET_V + TET_F)
add("off_open_surface.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
add("off_two_components.off",
    "OFF\n8 8 0\n" + TET_V + "5 5 5\n6 5 5\n5 6 5\n5 5 6\n" + TET_F +
    "3 4 6 5\n3 4 5 7\n3 4 7 6\n3 5 6 7\n")
add("off_inconsistent_orientation.off", "OFF\n4 4 0\n" + TET_V + "3 0 1 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
add("off_unreferenced_vertex.off", "OFF\n5 4 0\n" + TET_V + "9 9 9\n" + TET_F)
add("off_non_manifold_edge.off",
    "OFF\n5 5 0\n" + TET_V + "1 1 0\n" + TET_F + "3 0 1 4\n")
add("off_degenerate_faces.off",
    "OFF\n4 4 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n" + TET_F)
torus = []
nu, nv = 8, 6
import math
for i in range(nu):
    for j in range(nv):
        u, v = 2 * math.pi * i / nu, 2 * math.pi * j / nv
        torus.append("%r %r %r" % ((2 + math.cos(v)) * math.cos(u), (2 + math.cos(v)) * math.sin(u), math.sin(v)))
tf = []
for i in range(nu):
    for j in range(nv):
        a, b = i * nv + j, ((i + 1) % nu) * nv + j
        c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
        tf += ["3 %d %d %d" % (a, b, c), "3 %d %d %d" % (a, c, d)]
add("off_torus_genus1.off", "OFF\n%d %d 0\n" % (len(torus), len(tf)) + "\n".join(torus + tf) + "\n")

# --- OBJ -------------------------------------------------------------------
add("obj_out_of_range.obj", OBJ_V + "f 1 3 2\nf 1 2 5\n")
add("obj_zero_index.obj", OBJ_V + "f 0 1 2\n")
add("obj_negative_index.obj", OBJ_V + "f -1 -2 -5\n")
add("obj_nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
add("obj_inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n")
add("obj_text_coordinate.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n")
add("obj_short_vertex.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
add("obj_two_corners.obj", OBJ_V + "f 1 2\n")
add("obj_no_faces.obj", OBJ_V)
add("obj_mtllib_device_no_faces.obj", "mtllib /dev/zero\nmtllib /dev/stdin\nusemtl x\n" + OBJ_V)
add("obj_index_overflow.obj", OBJ_V + "f 1 2 99999999999999999999\n")
add("obj_letters_as_indices.obj", OBJ_V + "f a b c\n")
add("obj_blank.obj", "\n\n   \n# only comments\n")
add("obj_hex_garbage.obj", "v 0x 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
add("obj_open_surface.obj", OBJ_V + "f 1 3 2\nf 1 2 4\n")

# --- PLY -------------------------------------------------------------------
HEAD = "ply\nformat ascii 1.0\n"
VERT = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
FACE = "element face 4\nproperty list uchar int vertex_indices\n"
add("ply_no_end_header.ply", HEAD + VERT)
add("ply_huge_vertex_count.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
    "property float x\nproperty float y\nproperty float z\nend_header\n")
add("ply_property_before_element.ply", HEAD + "property float x\n" + VERT + FACE + "end_header\n" + TET_V + TET_F)
add("ply_format_without_version.ply", "ply\nformat ascii\n" + VERT + FACE + "end_header\n" + TET_V + TET_F)
add("ply_element_too_few_tokens.ply", HEAD + "element vertex\n" + "property float x\nend_header\n")
add("ply_unknown_format.ply", "ply\nformat binary_middle_endian 1.0\n" + VERT + FACE + "end_header\n")
add("ply_unknown_type.ply", HEAD + "element vertex 4\nproperty quad x\nend_header\n")
add("ply_float_list_count.ply", HEAD + VERT + "element face 4\nproperty list float int vertex_indices\nend_header\n" + TET_V + TET_F)
add("ply_missing_z.ply", HEAD + "element vertex 4\nproperty float x\nproperty float y\n" + FACE + "end_header\n")
add("ply_bad_index.ply", HEAD + VERT + FACE + "end_header\n" + TET_V + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 7\n")
add("ply_nan.ply", HEAD + VERT + FACE + "end_header\n0 0 0\nnan 0 0\n0 1 0\n0 0 1\n" + TET_F)
add("ply_negative_element_count.ply", HEAD + "element vertex -4\nproperty float x\nend_header\n")
add("ply_face_without_indices.ply", HEAD + VERT + "element face 4\nproperty uchar flags\nend_header\n" + TET_V + "1\n1\n1\n1\n")
add("ply_float_indices.ply", HEAD + VERT + "element face 4\nproperty list uchar float vertex_indices\nend_header\n" + TET_V + TET_F)
add("ply_negative_list_count.ply", HEAD + VERT + FACE + "end_header\n" + TET_V + "-3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
add("ply_two_corners.ply", HEAD + VERT + FACE + "end_header\n" + TET_V + "2 0 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
add("ply_empty_element_huge.ply", HEAD + "element junk 4000000000\n" + VERT + FACE + "end_header\n" + TET_V + TET_F)
add("ply_no_format.ply", "ply\n" + VERT + FACE + "end_header\n" + TET_V + TET_F)
add("ply_not_ply.ply", "PLY\nformat ascii 1.0\n" + VERT + FACE + "end_header\n" + TET_V + TET_F)
add("ply_no_vertex_element.ply", HEAD + "element point 4\nproperty float x\nend_header\n1\n2\n3\n4\n")
binary = ("ply\nformat binary_big_endian 1.0\n" + VERT + FACE + "end_header\n").encode()
for v in [(0, 0, 0), (1, 0, 0), (0, 1, 0)]:
    binary += struct.pack(">3f", *v)
add("ply_truncated_big_endian.ply", binary)
le = ("ply\nformat binary_little_endian 1.0\n" + VERT + FACE + "end_header\n").encode()
for v in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]:
    le += struct.pack("<3f", *v)
for f in [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]:
    le += struct.pack("<B3i", 255, *f)  # 255 corners declared, 3 given
add("ply_binary_wrong_corner_count.ply", le)

# --- STL -------------------------------------------------------------------
def stl_binary(tris, declared=None, header=b"binary"):
    out = header.ljust(80, b" ") + struct.pack("<I", len(tris) if declared is None else declared)
    for t in tris:
        out += struct.pack("<3f", 0, 0, 0)
        for p in t:
            out += struct.pack("<3f", *p)
        out += b"\0\0"
    return out


P = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TRIS = [(P[0], P[2], P[1]), (P[0], P[1], P[3]), (P[0], P[3], P[2]), (P[1], P[2], P[3])]
add("stl_truncated_binary.stl", stl_binary(TRIS, declared=8))
add("stl_too_short.stl", b"\x01" * 40)
add("stl_binary_nan.stl", stl_binary(TRIS[:3] + [((float("nan"), 0, 0), P[2], P[3])]))
add("stl_declares_4e9.stl", stl_binary(TRIS, declared=0xFFFFFFFF))
ascii_tet = "solid t\n" + "".join(
    " facet normal 0 0 0\n  outer loop\n" + "".join("   vertex %d %d %d\n" % p for p in t) +
    "  endloop\n endfacet\n" for t in TRIS) + "endsolid t\n"
add("stl_ascii_truncated.stl", ascii_tet[: len(ascii_tet) // 2])
add("stl_ascii_four_vertices.stl", ascii_tet.replace("   vertex 0 0 1\n  endloop", "   vertex 0 0 1\n   vertex 1 1 1\n  endloop", 1))
add("stl_ascii_nan.stl", ascii_tet.replace("vertex 1 0 0", "vertex 1 nan 0", 1))
add("stl_ascii_no_outer.stl", "solid x\nfacet normal 0 0 0\nvertex 0 0 0\n")
add("stl_solid_only.stl", "solid x\n")
add("stl_binary_solid_header_truncated.stl", stl_binary(TRIS, declared=5, header=b"solid pretending"))
add("stl_all_zero_triangles.stl", stl_binary([(P[0], P[0], P[0])] * 4))

# --- .sdcb -------------------------------------------------------------------
random.seed(12)
add("sdcb_random_bytes.sdcb", bytes(random.getrandbits(8) for _ in range(3000)))
add("sdcb_bad_magic.sdcb", b"\x89SDCX\r\n\x1a" + b"\0" * 64)
add("sdcb_magic_only.sdcb", b"\x89SDCB\r\n\x1a")
seed = open(os.path.join(HERE, "..", "..", "..", "fuzz", "corpus", "sdcb", "degree1_knots6.sdcb"), "rb").read()
add("sdcb_truncated.sdcb", seed[: len(seed) // 2])
flipped = bytearray(seed)
flipped[len(flipped) // 2] ^= 0x40
add("sdcb_bit_flip.sdcb", bytes(flipped))
add("sdcb_empty.sdcb", b"")


# Format version 3 (QKNT, PCTL) with valid CRCs, so that the chunks' own
# checks must catch them.
def sdcb_chunks(data):
    chunks, at = [], 12
    while at < len(data):
        length = struct.unpack("<Q", data[at + 4:at + 12])[0]
        chunks.append([data[at:at + 4], data[at + 12:at + 12 + length]])
        at += 16 + length
    return data[:8], chunks


def sdcb_join(magic, version, chunks):
    out = magic + struct.pack("<I", version)
    for kind, payload in chunks:
        framed = kind + struct.pack("<Q", len(payload)) + payload
        out += framed + struct.pack("<I", zlib.crc32(framed) & 0xFFFFFFFF)
    return out


def sdcb_edit(seed_name, kind, change, version=3):
    data = open(os.path.join(HERE, "..", "..", "..", "fuzz", "corpus", "sdcb", seed_name), "rb").read()
    magic, chunks = sdcb_chunks(data)
    for c in chunks:
        if c[0] == kind:
            c[1] = change(c[1])
    return sdcb_join(magic, version, chunks)


V3 = "v3_grid_knots_pctl_degree1.sdcb"
add("sdcb_v3_pctl_extra_byte.sdcb", sdcb_edit(V3, b"PCTL", lambda p: p + b"\0"))
add("sdcb_v3_pctl_truncated_stream.sdcb", sdcb_edit(V3, b"PCTL", lambda p: p[:-3]))
add("sdcb_v3_pctl_zero_stream.sdcb", sdcb_edit(V3, b"PCTL", lambda p: p[:68] + b"\xff" * 64))
add("sdcb_v3_qknt_bits_40.sdcb", sdcb_edit(V3, b"QKNT", lambda p: struct.pack("<I", 40) + p[4:]))
add("sdcb_v3_qknt_padding.sdcb", sdcb_edit(V3, b"QKNT", lambda p: p + b"\x01"))
add("sdcb_v3_without_new_chunks.sdcb", sdcb_edit("degree1_knots6.sdcb", b"HEAD", lambda p: p))
add("sdcb_v2_with_v3_chunks.sdcb", sdcb_edit(V3, b"HEAD", lambda p: p, version=2))

for name, data in sorted(files.items()):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)
print(len(files), "files")
