#!/usr/bin/env python3
"""Writes the odd-but-valid scene corpus of tests/data/odd/ and its manifest.txt.

Each case is a file that its format allows but that a reader can easily get wrong: a UTF-8
byte-order mark, OFF counts on the keyword line, comments and face colours in OFF, OBJ line
continuations, PLY faces with more than their vertex_indices. Every one holds the same scene as
a plain file of plain/, and tests/core/odd_input_test.cpp loads both and requires the same
primitives, in the same order, with nothing dropped.

manifest.txt, one line per file: FILE PRIMITIVES REFERENCE WHY (WHY to the end of the line).
Run this script again after changing the cases:
    python3 tests/data/odd/make_corpus.py
The output is deterministic.
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
BOM = b"\xef\xbb\xbf"

# The scene: a unit quad in z = 0 and a triangle standing on it. Fanned, the quad is the
# triangles (A, B, C) and (A, C, D); with the triangle (E, B, D) the scene has 3 triangles.
V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1)]
QUAD = [0, 1, 2, 3]
TRI = [4, 1, 3]
TRIANGLES = [(0, 1, 2), (0, 2, 3), (4, 1, 3)]


def fmt(v):
    return " ".join("%g" % c for c in v)


def obj_text():
    return "".join("v %s\n" % fmt(v) for v in V) + \
        "f %s\n" % " ".join(str(i + 1) for i in QUAD) + \
        "f %s\n" % " ".join(str(i + 1) for i in TRI)


def off_vertices():
    return "".join("%s\n" % fmt(v) for v in V)


def off_text():
    return "OFF\n5 2 0\n" + off_vertices() + "4 0 1 2 3\n3 4 1 3\n"


def ply_header(fmt_name, face_props):
    return ("ply\nformat %s 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
            "property float z\nelement face 2\n%send_header\n") % (fmt_name, face_props)


def ply_text():
    return ply_header("ascii", "property list uchar int vertex_indices\n") + off_vertices() + \
        "4 0 1 2 3\n3 4 1 3\n"


def stl_ascii():
    s = "solid plain\n"
    for t in TRIANGLES:
        s += " facet normal 0 0 0\n  outer loop\n"
        for i in t:
            s += "   vertex %s\n" % fmt(V[i])
        s += "  endloop\n endfacet\n"
    return s + "endsolid plain\n"


def stl_binary(header):
    out = header.ljust(80, b" ")[:80] + struct.pack("<I", len(TRIANGLES))
    for t in TRIANGLES:
        out += struct.pack("<3f", 0, 0, 0)
        for i in t:
            out += struct.pack("<3f", *V[i])
        out += b"\0\0"
    return out


def xyz_text():
    return "".join("%s\n" % fmt(v) for v in V)


PLAIN = {
    "plain/plain.obj": obj_text(),
    "plain/plain.off": off_text(),
    "plain/plain.ply": ply_text(),
    "plain/plain.stl": stl_ascii(),
    "plain/plain.xyz": xyz_text(),
}

cases = []  # (name, bytes, primitives, reference, why)


def add(name, data, reference, why):
    if isinstance(data, str):
        data = data.encode("latin-1")
    prims = len(V) if reference.endswith(".xyz") else len(TRIANGLES)
    cases.append((name, data, prims, reference, why))


# --- UTF-8 byte-order marks (Windows editors write one) in every text format -----------------
add("obj_bom.obj", BOM + obj_text().encode(), "plain/plain.obj",
    "UTF-8 byte-order mark before the first line; it is not part of the first 'v' keyword")
add("off_bom.off", BOM + off_text().encode(), "plain/plain.off",
    "UTF-8 byte-order mark before the OFF keyword")
add("ply_bom.ply", BOM + ply_text().encode(), "plain/plain.ply",
    "UTF-8 byte-order mark before the 'ply' magic line of an ASCII PLY")
add("stl_bom.stl", BOM + stl_ascii().encode(), "plain/plain.stl",
    "UTF-8 byte-order mark before 'solid' in an ASCII STL")
add("xyz_bom.xyz", BOM + xyz_text().encode(), "plain/plain.xyz",
    "UTF-8 byte-order mark before the first point")

# --- OFF (Geomview's OOGL OFF format) ---------------------------------------------------------
add("off_counts_on_keyword_line.off", "OFF 5 2 0\n" + off_vertices() + "4 0 1 2 3\n3 4 1 3\n",
    "plain/plain.off", "the vertex, face and edge counts on the OFF keyword's line")
add("off_comments.off",
    "OFF\n# written by hand\n\n5 2 0\n# the vertices\n" +
    "".join("%s  # vertex %d\n" % (fmt(v), i) for i, v in enumerate(V)) +
    "# the faces\n4 0 1 2 3 # the quad\n\n# and a triangle\n3 4 1 3\n# end\n",
    "plain/plain.off", "'#' comments before the counts, between and after vertices and faces")
add("off_face_colours.off",
    "OFF\n5 2 0\n" + off_vertices() + "4 0 1 2 3 255 0 0\n3 4 1 3 0.5 0.5 0.5 1\n",
    "plain/plain.off", "faces followed by an RGB and an RGBA colour, without the C prefix")
add("off_face_colour_index.off",
    "OFF\n5 2 0\n" + off_vertices() + "4 0 1 2 3 7\n3 4 1 3 2\n",
    "plain/plain.off", "faces followed by a colour-map index")

# --- OBJ (Wavefront) --------------------------------------------------------------------------
add("obj_line_continuation.obj",
    "# a comment ending in a backslash is still one line: C:\\models\\\n"
    "v 0 0 0\nv 1 \\\n  0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
    "f 1 2 \\\r\n3 4\nf 5 \\\n2 \\\n4\n",
    "plain/plain.obj", "statements continued over several lines with a final backslash")

# --- PLY faces with more than vertex_indices (MeshLab and Blender write texture lists) -------
FACE_EXTRAS = ("property list uchar float texcoord\nproperty list uchar int vertex_indices\n"
               "property int texnumber\nproperty list uchar float texcoord2\n")


def ply_extras_ascii():
    faces = "6 0 0 1 0 1 1 4 0 1 2 3 0 0\n6 0 0 1 0 0 1 3 4 1 3 1 2 0.5 0.5\n"
    return ply_header("ascii", FACE_EXTRAS) + off_vertices() + faces


def ply_extras_binary(order):
    out = ply_header("binary_%s_endian" % ("little" if order == "<" else "big"),
                     FACE_EXTRAS).encode()
    for v in V:
        out += struct.pack(order + "3f", *v)
    for face, tex, num in ((QUAD, [0, 0, 1, 0, 1, 1], 0), (TRI, [0, 0, 1, 0, 0, 1], 1)):
        out += struct.pack(order + "B%df" % len(tex), len(tex), *tex)
        out += struct.pack(order + "B%di" % len(face), len(face), *face)
        out += struct.pack(order + "i", num)
        out += struct.pack(order + "B2f", 2, 0.5, 0.5)
    return out


add("ply_face_lists_ascii.ply", ply_extras_ascii(), "plain/plain.ply",
    "face lists of texture coordinates before and after vertex_indices, and a face scalar")
add("ply_face_lists_binary.ply", ply_extras_binary("<"), "plain/plain.ply",
    "the same in binary_little_endian")
add("ply_face_lists_big_endian.ply", ply_extras_binary(">"), "plain/plain.ply",
    "the same in binary_big_endian")
add("ply_face_property_before_indices.ply",
    ply_header("ascii", "property uchar flags\nproperty list uchar int vertex_indices\n") +
    off_vertices() + "3 4 0 1 2 3\n3 3 4 1 3\n", "plain/plain.ply",
    "a face scalar before vertex_indices (OpenMesh drops its declaration and reads it as the "
    "list length)")

# --- STL --------------------------------------------------------------------------------------
add("stl_binary_solid_header.stl", stl_binary(b"solid exported by a CAD program"),
    "plain/plain.stl", "a binary STL whose 80-byte header starts with 'solid' (size decides)")


def main():
    os.makedirs(os.path.join(HERE, "plain"), exist_ok=True)
    for name, text in PLAIN.items():
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(text.encode())
    lines = ["# file primitives reference why  (generated by make_corpus.py)"]
    for name, data, prims, reference, why in cases:
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(data)
        lines.append("%s %d %s %s" % (name, prims, reference, why))
    with open(os.path.join(HERE, "manifest.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
