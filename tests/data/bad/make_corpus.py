#!/usr/bin/env python3
"""Writes the malformed-scene corpus of tests/data/bad/ and its manifest.txt.

Each case is a file a new user might hand octrace by mistake (or a fuzzer found) and the outcome
octrace must give: either a one-line error containing a given text, or a successful load whose
drop report has the given counts. tests/core/bad_input_test.cpp loads every file listed through
loadScene, tests/apps/bad_input_cli_test.cpp runs every one through `octrace info`; both fail on
a file in this folder that the manifest does not list.

Inputs the fuzzer (fuzz/) found are kept in fuzz/ under this folder and listed in FUZZ_FOUND
below with their expected outcome. Run this script again after changing the cases:
    python3 tests/data/bad/make_corpus.py
The output is deterministic (seeded random bytes), so regenerating changes nothing unless a
case changed.
"""
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
rng = random.Random(7)

cases = []  # (name, bytes or None for a file kept as is, expectation)


def add(name, data, expect):
    if isinstance(data, str):
        data = data.encode("latin-1")
    cases.append((name, data, expect))


def garbage(n):
    return bytes(rng.randrange(256) for _ in range(n))


def f32(*values):
    return struct.pack("<%df" % len(values), *values)


TRI = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"

# --- OBJ ------------------------------------------------------------------------------------
add("obj_empty.obj", "", "error:no faces")
add("obj_garbage.obj", garbage(3000), "error:no faces")
add("obj_nul_bytes.obj", b"\0" * 512, "error:no faces")
add("obj_vertices_only.obj", TRI, "error:no faces")
add("obj_index_zero.obj", TRI + "f 0 1 2\nf 1 2 3\n", "ok:invalid_index=1")
add("obj_index_out_of_range.obj", TRI + "f 1 2 4\nf 1 2 3\n", "ok:invalid_index=1")
add("obj_index_negative_out_of_range.obj", TRI + "f -1 -2 -4\nf -1 -2 -3\n",
    "ok:invalid_index=1")
add("obj_index_overflow.obj", TRI + "f 1 2 99999999999999999999\nf 1 2 3\n",
    "ok:invalid_index=1")
# OpenMesh drops a corner whose index overflows int and hands over the rest of the face.
add("obj_index_overflow_in_polygon.obj", TRI + "v 1 1 0\nf 1 2 3 99999999999\nf 1 2 4\n",
    "ok:invalid_index=1")
add("obj_index_int_min.obj", TRI + "f 1 2 -2147483648\nf 1 2 3\n", "ok:invalid_index=1")
add("obj_all_indices_invalid.obj", TRI + "f 0 0 0\nf 4 5 6\nf -4 -5 -6\n",
    "error:none of its 3 faces is usable")
add("obj_too_few_vertices.obj", TRI + "f 1\nf 1 2\nf 1 2 3\n", "ok:too_few_vertices=2")
add("obj_degenerate.obj", TRI + "v 2 0 0\nf 1 2 4\nf 1 1 2\nf 1 2 3\n", "ok:degenerate=2")
add("obj_all_degenerate.obj", TRI + "v 2 0 0\nf 1 2 4\nf 3 3 3\n",
    "error:none of its 2 faces is usable")
add("obj_nan_vertex.obj", TRI + "v nan 0 0\nf 1 2 4\nf 1 2 3\n", "ok:non_finite=1")
add("obj_inf_vertex.obj", TRI + "v 0 inf 0\nv 0 0 1e39\nf 1 2 4\nf 1 2 5\nf 1 2 3\n",
    "ok:non_finite=2")
add("obj_garbage_vertex.obj", TRI + "v zero one two\nf 1 2 4\nf 1 2 3\n", "ok:non_finite=1")
add("obj_all_nan.obj", "v nan nan nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "error:none of its 1 faces is usable")
# Finite floats whose span overflows float: the octree's root cube would be infinite.
add("obj_extent_overflow.obj", "v -3e38 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n",
    "error:rescale")
add("obj_long_face.obj", TRI + "f " + " ".join(["1 2 3"] * 2000) + "\n",
    "ok:degenerate=0")
add("obj_slash_garbage.obj", TRI + "f abc/1 2 3\nf 1 2 3\n", "ok:invalid_index=1")
add("obj_slash_overflow.obj", TRI + "f 1/1 2/1 99999999999/1\nf 1 2 3\n", "ok:invalid_index=1")
# OpenMesh opens "mtllib NAME" relative to the OBJ and reads it to its end: /dev/zero never ends.
add("obj_mtllib_dev_zero.obj", "mtllib " + "../" * 40 + "dev/zero\n" + TRI + "f 1 2 3\n",
    "error:not a regular file")
add("obj_corner_without_vertex.obj", TRI + "f /1 2 3\n", "error:without a vertex index")
add("obj_truncated_line.obj", TRI + "f 1 2", "error:none of its 1 faces is usable")

# --- PLY ------------------------------------------------------------------------------------


def ply_header(fmt, nv, nf, face_list="list uchar int vertex_indices", extra=""):
    h = "ply\nformat %s 1.0\nelement vertex %s\nproperty float x\nproperty float y\n" \
        "property float z\n" % (fmt, nv)
    if nf is not None:
        h += "element face %s\nproperty %s\n" % (nf, face_list)
    return h + extra + "end_header\n"


PLY_V = "0 0 0\n1 0 0\n0 1 0\n"
PLY_VB = f32(0, 0, 0, 1, 0, 0, 0, 1, 0)


def face_b(*idx, count="B"):
    return struct.pack("<" + count, len(idx)) + struct.pack("<%di" % len(idx), *idx)


add("ply_empty.ply", "", "error:PLY")
add("ply_garbage.ply", garbage(2000), "error:PLY")
add("ply_no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n",
    "error:end_header")
add("ply_header_only.ply", "ply\nformat ascii 1.0\nend_header\n", "error:element vertex")
add("ply_bad_format.ply", ply_header("binary_middle_endian", 3, 1) + PLY_V + "3 0 1 2\n",
    "error:binary_middle_endian")
add("ply_huge_vertex_count_ascii.ply", ply_header("ascii", 4000000000, 1) + PLY_V + "3 0 1 2\n",
    "error:4000000000")
add("ply_huge_vertex_count_binary.ply",
    (ply_header("binary_little_endian", 4000000000, 1)).encode() + PLY_VB + face_b(0, 1, 2),
    "error:4000000000")
add("ply_huge_face_count_binary.ply",
    (ply_header("binary_little_endian", 3, 4000000000)).encode() + PLY_VB + face_b(0, 1, 2),
    "error:4000000000")
add("ply_count_overflow.ply", ply_header("ascii", "99999999999999999999999", 1) + PLY_V,
    "error:99999999999999999999999")
add("ply_negative_vertex_count.ply", ply_header("ascii", -5, 1) + PLY_V + "3 0 1 2\n",
    "error:-5")
add("ply_negative_face_count_binary.ply",
    ply_header("binary_little_endian", 3, -1).encode() + PLY_VB + face_b(0, 1, 2), "error:-1")
add("ply_truncated_ascii.ply", ply_header("ascii", 3, 2) + PLY_V + "3 0 1 2\n",
    "error:truncated")
add("ply_truncated_binary_vertices.ply",
    ply_header("binary_little_endian", 3, 1).encode() + PLY_VB[:20], "error:truncated")
add("ply_truncated_binary_faces.ply",
    ply_header("binary_little_endian", 3, 2).encode() + PLY_VB + face_b(0, 1, 2) + b"\x03\0\0",
    "error:truncated")
add("ply_binary_list_count_negative.ply",
    ply_header("binary_little_endian", 3, 1, "list int int vertex_indices").encode() + PLY_VB +
    struct.pack("<i", -1) + struct.pack("<3i", 0, 1, 2), "error:-1")
add("ply_binary_list_count_huge.ply",
    ply_header("binary_little_endian", 3, 1, "list int int vertex_indices").encode() + PLY_VB +
    struct.pack("<i", 2000000000) + struct.pack("<3i", 0, 1, 2), "error:truncated")
add("ply_binary_list_count_type_uint.ply",
    ply_header("binary_little_endian", 3, 1, "list uint int vertex_indices").encode() + PLY_VB +
    struct.pack("<I", 3) + struct.pack("<3i", 0, 1, 2), "error:count type")
# OpenMesh's header loop: a property before any element dereferences an empty vector (SIGSEGV);
# a token its number parser rejects, or a header without end_header, makes it loop forever.
add("ply_property_before_element.ply",
    "ply\nformat ascii 1.0\nproperty float x\n" + ply_header("ascii", 3, None)[19:] + PLY_V,
    "error:before any 'element'")
add("ply_element_count_garbage.ply", ply_header("ascii", "abc", None) + PLY_V, "error:abc")
add("ply_bad_version.ply", ply_header("ascii", 3, None).replace("1.0", "one") + PLY_V,
    "error:version")
add("ply_no_format_line.ply", "ply\nelement vertex 3\nproperty float x\nend_header\n",
    "error:format")
# OpenMesh starts a binary body 12 bytes after the token before end_header: a comment line or a
# trailing blank there shifts every value (a silent misread).
add("ply_binary_comment_before_end_header.ply",
    ply_header("binary_little_endian", 3, None).replace("end_header", "comment x\nend_header")
    .encode() + PLY_VB, "error:instead of")
add("ply_binary_trailing_blank.ply",
    ply_header("binary_little_endian", 3, None).replace("z\nend_header", "z \nend_header")
    .encode() + PLY_VB, "error:instead of")
# Types the binary reader reads as zero bytes, shifting every later value.
add("ply_binary_int_coordinates.ply",
    ply_header("binary_little_endian", 3, None).replace("float", "int").encode() +
    struct.pack("<9i", 0, 0, 0, 1, 0, 0, 0, 1, 0), "error:float or double")
add("ply_binary_double_colour.ply",
    ply_header("binary_little_endian", 3, None).replace(
        "property float z\n", "property float z\nproperty double red\n").encode() +
    b"".join(f32(*v) + struct.pack("<d", 0.5) for v in ((0, 0, 0), (1, 0, 0), (0, 1, 0))),
    "error:integer type")
add("ply_list_entry_float.ply",
    ply_header("ascii", 3, 1, "list uchar float vertex_indices") + PLY_V + "3 0 1 2\n",
    "error:not an integer type")
add("ply_face_without_indices.ply",
    ply_header("ascii", 3, 1, "uchar flags") + PLY_V + "1\n", "error:vertex_indices")
add("ply_empty_element_huge.ply",
    ply_header("ascii", 3, None).replace("end_header", "element edge 4000000000\nend_header") +
    PLY_V, "error:no properties")
add("ply_ascii_hex_coordinate.ply",
    ply_header("ascii", 3, 1) + "0 0 0\n0x1 0 0\n0 1 0\n3 0 1 2\n", "error:0x1")
add("ply_ascii_int_colour_as_float.ply",
    ply_header("ascii", 3, 1).replace("property float z\n",
                                      "property float z\nproperty uchar red\n") +
    "0 0 0 1\n1 0 0 0.5\n0 1 0 1\n3 0 1 2\n", "error:0.5")
add("ply_ascii_index_overflow.ply", ply_header("ascii", 3, 1) + PLY_V + "3 0 1 99999999999\n",
    "error:99999999999")
add("ply_duplicate_vertex_element.ply",
    ply_header("ascii", 3, None).replace(
        "end_header", "element vertex 1\nproperty float x\nend_header") + PLY_V + "0\n",
    "error:twice")
add("ply_ascii_list_count_huge.ply", ply_header("ascii", 3, 1) + PLY_V + "4000000000 0 1 2\n",
    "error:truncated")
add("ply_unknown_property_type.ply",
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty quux x\nproperty float y\n"
    "property float z\nend_header\n" + PLY_V, "error:quux")
add("ply_no_xyz.ply",
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float a\nproperty float b\n"
    "property float c\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
    PLY_V + "3 0 1 2\n", "error:x, y and z")
add("ply_faces_without_vertices.ply",
    "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
    "end_header\n3 0 1 2\n", "error:element vertex")
add("ply_index_out_of_range.ply", ply_header("ascii", 3, 2) + PLY_V + "3 0 1 2\n3 0 1 3\n",
    "ok:invalid_index=1")
add("ply_index_negative_binary.ply",
    ply_header("binary_little_endian", 3, 2).encode() + PLY_VB + face_b(0, 1, 2) +
    face_b(0, -1, 2), "ok:invalid_index=1")
add("ply_too_few_vertices.ply", ply_header("ascii", 3, 3) + PLY_V + "3 0 1 2\n2 0 1\n0\n",
    "ok:too_few_vertices=2")
add("ply_degenerate.ply", ply_header("ascii", 3, 2) + PLY_V + "3 0 1 2\n3 0 0 1\n",
    "ok:degenerate=1")
add("ply_nan_vertex_binary.ply",
    ply_header("binary_little_endian", 4, 2).encode() + PLY_VB + f32(float("nan"), 0, 0) +
    face_b(0, 1, 2) + face_b(0, 1, 3), "ok:non_finite=1")
add("ply_nan_ascii.ply", ply_header("ascii", 3, 1) + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n",
    "error:nan")
add("ply_points_all_nan_binary.ply",
    ply_header("binary_little_endian", 2, None).encode() +
    f32(float("nan"), 0, 0, 0, float("inf"), 0), "error:no usable points")
add("ply_points_extent_overflow.ply",
    ply_header("ascii", 2, None) + "-3e38 0 0\n3e38 0 0\n", "error:rescale")
add("ply_list_property_on_vertex.ply",
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nproperty list uchar int extra\nend_header\n0 0 0 0\n1 0 0 0\n0 1 0 0\n",
    "error:list property")

# Face lists beside vertex_indices are skipped, but must still be whole.
add("ply_face_list_truncated.ply",
    ply_header("ascii", 3, 1, "list uchar int vertex_indices\nproperty list uchar float texcoord")
    + PLY_V + "3 0 1 2 6 0 0\n", "error:truncated")
add("ply_binary_face_list_negative.ply",
    ply_header("binary_little_endian", 3, 1,
               "list uchar int vertex_indices\nproperty list int float texcoord").encode() +
    PLY_VB + face_b(0, 1, 2) + struct.pack("<i", -1), "error:-1")

# --- OFF ------------------------------------------------------------------------------------
OFF_V = "0 0 0\n1 0 0\n0 1 0\n"
add("off_empty.off", "", "error:first line")
add("off_garbage.off", garbage(2000), "error:first line")
add("off_negative_counts.off", "OFF\n-1 -1 0\n", "error:-1")
add("off_huge_vertex_count.off", "OFF\n4000000000 1 0\n" + OFF_V + "3 0 1 2\n",
    "error:truncated")
add("off_huge_face_count.off", "OFF\n3 4000000000 0\n" + OFF_V + "3 0 1 2\n", "error:truncated")
add("off_count_overflow.off", "OFF\n99999999999999999999 1 0\n" + OFF_V + "3 0 1 2\n",
    "error:99999999999999999999")
add("off_face_list_huge.off", "OFF\n3 1 0\n" + OFF_V + "4000000000 0 1 2\n", "error:truncated")
add("off_truncated.off", "OFF\n3 2 0\n" + OFF_V + "3 0 1 2\n", "error:truncated")
add("off_missing_keyword.off", "3 1 0\n" + OFF_V + "3 0 1 2\n", "error:first line")
add("off_nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "error:nan")
add("off_index_negative.off", "OFF\n3 2 0\n" + OFF_V + "3 0 -1 2\n3 0 1 2\n",
    "ok:invalid_index=1")
add("off_index_out_of_range.off", "OFF\n3 2 0\n" + OFF_V + "3 0 1 3\n3 0 1 2\n",
    "ok:invalid_index=1")
add("off_zero_faces.off", "OFF\n3 0 0\n" + OFF_V, "error:no faces")
add("off_binary_huge_counts.off",
    b"OFF BINARY\n" + struct.pack("<3I", 4000000000, 4000000000, 0) + PLY_VB,
    "error:4000000000")
add("off_binary_truncated.off",
    b"OFF BINARY\n" + struct.pack("<3I", 3, 1, 0) + PLY_VB + struct.pack("<2I", 3, 0),
    "error:truncated")
add("off_binary_negative_counts.off",
    b"OFF BINARY\n" + struct.pack("<3i", -1, -1, 0) + PLY_VB, "error:4294967295")
add("off_binary_face_list_huge.off",
    b"OFF BINARY\n" + struct.pack("<3I", 3, 1, 0) + PLY_VB +
    struct.pack("<4I", 4000000000, 0, 1, 2), "error:truncated")
add("off_4d.off", "4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n", "error:4OFF")
add("off_index_overflow.off", "OFF\n3 1 0\n" + OFF_V + "3 0 1 99999999999\n",
    "error:99999999999")
# A face line ends in an optional colour (a colour-map index, RGB or RGBA); anything else after
# the indices means the vertex count is wrong.
add("off_face_colour_two_values.off", "OFF\n3 1 0\n" + OFF_V + "3 0 1 2 5 6\n", "error:line 6")
add("off_face_colour_word.off", "OFF\n3 1 0\n" + OFF_V + "3 0 1 2 red\n", "error:red")

# --- STL ------------------------------------------------------------------------------------


def stl_b(facets, count=None, pad=b""):
    out = b"\0" * 80 + struct.pack("<I", len(facets) if count is None else count)
    for f in facets:
        out += f32(0, 0, 1, *[c for v in f for c in v]) + b"\0\0"
    return out + pad


def stl_a(facets):
    s = "solid t\n"
    for f in facets:
        s += " facet normal 0 0 1\n  outer loop\n"
        for v in f:
            s += "   vertex %s %s %s\n" % v
        s += "  endloop\n endfacet\n"
    return s + "endsolid t\n"


T1 = ((0, 0, 0), (1, 0, 0), (0, 1, 0))
T2 = ((0, 0, 0), (1, 0, 0), (0, 0, 1))
add("stl_empty.stl", "", "error:neither")
add("stl_garbage.stl", garbage(3000), "error:neither")
add("stl_binary_zero_facets.stl", stl_b([]), "error:no faces")
add("stl_binary_truncated.stl", stl_b([T1, T2], count=10), "error:truncated")
add("stl_binary_huge_count.stl", stl_b([T1], count=0xFFFFFFFF), "error:truncated")
add("stl_binary_trailing_bytes.stl", stl_b([T1, T2], pad=b"\0" * 7), "error:truncated")
add("stl_binary_nan.stl", stl_b([T1, ((0, 0, 0), (float("nan"), 0, 0), (0, 1, 0))]),
    "error:NaN")
add("stl_binary_inf.stl", stl_b([T1, ((0, 0, 0), (float("inf"), 0, 0), (0, 1, 0))]),
    "ok:non_finite=1")
add("stl_binary_degenerate.stl", stl_b([T1, ((0, 0, 0), (0, 0, 0), (0, 1, 0))]),
    "ok:degenerate=1")
add("stl_binary_all_degenerate.stl", stl_b([((0, 0, 0), (0, 0, 0), (0, 1, 0))]),
    "error:none of its 1 faces is usable")
add("stl_binary_extent_overflow.stl", stl_b([((-3e38, 0, 0), (3e38, 0, 0), (0, 1, 0))]),
    "error:rescale")
add("stl_ascii_truncated.stl", stl_a([T1, T2])[:-60], "error:line")
add("stl_ascii_nan.stl", stl_a([T1, ((0, 0, 0), ("nan", 0, 0), (0, 1, 0))]), "error:line")
add("stl_ascii_garbage_coordinate.stl", stl_a([T1, ((0, 0, 0), ("x1", 0, 0), (0, 1, 0))]),
    "error:line")
add("stl_ascii_no_facets.stl", "solid empty\nendsolid empty\n", "error:no faces")
# A binary STL whose header starts with "solid" (as many CAD programs write it) and whose facet
# count is wrong: the size rule reads it as ASCII, which finds no facet.
add("stl_binary_solid_header_wrong_count.stl",
    b"solid part".ljust(80, b" ") + stl_b([T1, T2], count=5)[80:], "error:declares 5 facets")

# --- XYZ ------------------------------------------------------------------------------------
add("xyz_empty.xyz", "", "error:no usable points")
add("xyz_garbage.xyz", garbage(1000), "error:line")
add("xyz_short_line.xyz", "0 0 0\n1 2\n", "error:line 2")
add("xyz_all_nan.xyz", "nan 0 0\n0 inf 0\n", "error:no usable points")
add("xyz_some_nan.xyz", "0 0 0\nnan 0 0\n1 0 0\n0 1e999 0\n", "ok:non_finite=2")
add("xyz_extent_overflow.xyz", "-3e38 0 0\n3e38 0 0\n", "error:rescale")
add("xyz_nul_bytes.xyz", b"0 0 0\n\0\0\0\n", "error:line 2")

# --- names and kinds --------------------------------------------------------------------------
add("unknown_extension.abc", TRI + "f 1 2 3\n", "error:unknown scene format")
add("no_extension", TRI + "f 1 2 3\n", "error:unknown scene format")
# A directory named like a mesh is created by the tests (git keeps no empty folders).

# --- numeric range (core/geometry/numeric_range.h; docs/ROBUSTNESS.md, "Numeric range") --------
# Kept apart from the format cases above. Beyond the range: refused; at its edges: loaded.
TETRA = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def tetra(s):
    return "v 0 0 0\nv %r 0 0\nv 0 %r 0\nv 0 0 %r\n" % (s, s, s) + TETRA


add("range_coordinates_1e14.obj", tetra(1e14), "error:beyond +-1e+11")
add("range_coordinates_at_bound.obj",
    "v -1e11 -1e11 0\nv 1e11 -1e11 0\nv 0 1e11 1e11\nf 1 2 3\n", "ok:degenerate=0")
add("range_extent_1e-20.obj", tetra(1e-20), "error:extent")
add("range_extent_at_bound.obj", tetra(1e-6), "ok:degenerate=0")
add("range_triangle_area_1e-60.obj", tetra(1.0) + "v 1e-30 0 0\nv 0 1e-30 0\nf 1 5 6\n",
    "error:area below")
# Two points 1e-16 apart beside a third: the default radius (half the median nearest-neighbour
# distance) is 5e-17, below the smallest radius.
add("range_points_radius_tiny.xyz", "0 0 0\n1e-16 0 0\n1 0 0\n", "error:sphere radius")

# --- found by the fuzzer (fuzz/README.md) -----------------------------------------------------
FUZZ_FOUND = [
    # "f /4 -5 -6": a corner without a vertex index; Debian's OpenMesh asserts (SIGABRT).
    ("fuzz/obj_corner_without_vertex.obj", "error:without a vertex index"),
]


def main():
    lines = ["# file expectation  (generated by make_corpus.py; error:TEXT or ok:drop=N,...)"]
    for name, data, expect in cases:
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(data)
        lines.append("%s %s" % (name, expect))
    for name, expect in FUZZ_FOUND:
        assert os.path.exists(os.path.join(HERE, name)), name
        lines.append("%s %s" % (name, expect))
    with open(os.path.join(HERE, "manifest.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
