#!/usr/bin/env python3
"""Print vertex/face statistics for OBJ, PLY (ascii / binary, optionally .gz),
STL (ascii / binary) and OFF files. Standard library only.

Used to produce the counts in meshes/README.md and to sanity-check the meshes:
index validity, polygon arity, degenerate faces (repeated index or zero area),
unused vertices, bounding box.

Usage: mesh_stats.py FILE [FILE ...]
"""
import gzip
import math
import struct
import sys
from collections import Counter


def _open(path):
    return gzip.open(path, "rb") if path.endswith(".gz") else open(path, "rb")


def read_obj(path):
    verts, faces, notes = [], [], Counter()
    with _open(path) as f:
        for raw in f:
            line = raw.decode("utf-8", "replace").strip()
            if not line or line.startswith("#"):
                continue
            tok = line.split()
            if tok[0] == "v":
                verts.append(tuple(float(x) for x in tok[1:4]))
            elif tok[0] == "f":
                idx = []
                for t in tok[1:]:
                    if "/" in t:
                        notes["f with v/vt/vn syntax"] += 1
                    i = int(t.split("/")[0])
                    if i < 0:
                        notes["negative (relative) indices"] += 1
                        i = len(verts) + i  # relative to vertices seen so far
                    else:
                        i -= 1
                    idx.append(i)
                faces.append(idx)
            elif tok[0] in ("vn", "vt", "l", "p", "mtllib", "usemtl", "g", "o", "s"):
                notes["'%s' records" % tok[0]] += 1
            else:
                notes["other '%s' records" % tok[0]] += 1
    return verts, faces, notes


def read_off(path):
    notes = Counter()
    with _open(path) as f:
        words = []
        for raw in f:
            line = raw.decode("utf-8", "replace").split("#")[0]
            words.extend(line.split())
    if not words[0].endswith("OFF"):
        raise ValueError("not an OFF file")
    if words[0] != "OFF":
        notes["header %s" % words[0]] += 1
    nv, nf = int(words[1]), int(words[2])
    p = 4
    verts = []
    for _ in range(nv):
        verts.append(tuple(float(x) for x in words[p:p + 3]))
        p += 3
    faces = []
    for _ in range(nf):
        k = int(words[p])
        faces.append([int(x) for x in words[p + 1:p + 1 + k]])
        p += 1 + k
        # optional per-face colour values are not supported here
    notes["header counts: %d vertices, %d faces" % (nv, nf)] += 1
    return verts, faces, notes


_PLY_TYPES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B",
    "short": "h", "int16": "h", "ushort": "H", "uint16": "H",
    "int": "i", "int32": "i", "uint": "I", "uint32": "I",
    "float": "f", "float32": "f", "double": "d", "float64": "d",
}


def read_ply(path):
    notes = Counter()
    with _open(path) as f:
        data = f.read()
    end = data.index(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = None
    elements = []  # (name, count, [(propname, type | ("list", ctype, itype))])
    for line in header:
        tok = line.split()
        if not tok:
            continue
        if tok[0] == "format":
            fmt = tok[1]
        elif tok[0] == "element":
            elements.append((tok[1], int(tok[2]), []))
        elif tok[0] == "property":
            if tok[1] == "list":
                elements[-1][2].append((tok[4], ("list", tok[2], tok[3])))
            else:
                elements[-1][2].append((tok[2], tok[1]))
    notes["format %s" % fmt] += 1
    for name, count, props in elements:
        notes["header: element %s %d (%s)" % (name, count, " ".join(p[0] for p in props))] += 1
    verts, faces = [], []
    body = data[end:]
    if fmt == "ascii":
        words = body.split()
        p = 0
        for name, count, props in elements:
            for _ in range(count):
                rec = {}
                for pname, ptype in props:
                    if isinstance(ptype, tuple):
                        k = int(words[p]); p += 1
                        rec[pname] = [int(w) for w in words[p:p + k]]; p += k
                    else:
                        rec[pname] = float(words[p]); p += 1
                _store(name, rec, verts, faces)
    else:
        endian = "<" if fmt == "binary_little_endian" else ">"
        p = 0
        for name, count, props in elements:
            simple = all(not isinstance(t, tuple) for _, t in props)
            if simple:
                st = struct.Struct(endian + "".join(_PLY_TYPES[t] for _, t in props))
                names = [n for n, _ in props]
                for _ in range(count):
                    rec = dict(zip(names, st.unpack_from(body, p)))
                    p += st.size
                    _store(name, rec, verts, faces)
                continue
            for _ in range(count):
                rec = {}
                for pname, ptype in props:
                    if isinstance(ptype, tuple):
                        cst = struct.Struct(endian + _PLY_TYPES[ptype[1]])
                        (k,) = cst.unpack_from(body, p); p += cst.size
                        ist = struct.Struct(endian + _PLY_TYPES[ptype[2]] * k)
                        rec[pname] = list(ist.unpack_from(body, p)); p += ist.size
                    else:
                        st = struct.Struct(endian + _PLY_TYPES[ptype])
                        (rec[pname],) = st.unpack_from(body, p); p += st.size
                _store(name, rec, verts, faces)
        if p != len(body):
            notes["%d trailing bytes after last element" % (len(body) - p)] += 1
    return verts, faces, notes


def _store(name, rec, verts, faces):
    if name == "vertex":
        verts.append((rec["x"], rec["y"], rec["z"]))
    elif name == "face":
        faces.append(rec.get("vertex_indices", rec.get("vertex_index")))


def read_stl(path):
    notes = Counter()
    with _open(path) as f:
        data = f.read()
    binary = True
    if len(data) >= 84:
        (n,) = struct.unpack_from("<I", data, 80)
        binary = 84 + 50 * n == len(data)
    else:
        binary = False
    verts, faces = [], []
    if binary:
        notes["binary STL, header count %d" % n] += 1
        for t in range(n):
            vals = struct.unpack_from("<12f", data, 84 + 50 * t)
            base = len(verts)
            verts.extend([vals[3:6], vals[6:9], vals[9:12]])
            faces.append([base, base + 1, base + 2])
    else:
        notes["ascii STL"] += 1
        cur = []
        for line in data.decode("utf-8", "replace").splitlines():
            tok = line.split()
            if tok and tok[0] == "vertex":
                cur.append(tuple(float(x) for x in tok[1:4]))
            elif tok and tok[0] == "endfacet":
                base = len(verts)
                verts.extend(cur)
                faces.append(list(range(base, base + len(cur))))
                cur = []
            elif tok and tok[0] == "solid":
                notes["solid records"] += 1
    notes["STL has no shared vertices (3 per triangle)"] += 1
    return verts, faces, notes


def stats(path):
    base = path[:-3] if path.endswith(".gz") else path
    ext = base.rsplit(".", 1)[-1].lower()
    reader = {"obj": read_obj, "off": read_off, "ply": read_ply, "stl": read_stl}[ext]
    verts, faces, notes = reader(path)
    nv = len(verts)
    arity = Counter(len(f) for f in faces)
    bad = sum(1 for f in faces if any(i < 0 or i >= nv for i in f))
    repeated = sum(1 for f in faces if len(set(f)) < len(f))
    tris = sum(max(0, len(f) - 2) for f in faces)
    zero_area = 0
    used = set()
    for f in faces:
        used.update(f)
        if any(i < 0 or i >= nv for i in f):
            continue
        # fan triangulation; count a triangle as zero-area on exact zero cross product
        a = verts[f[0]]
        for k in range(1, len(f) - 1):
            b, c = verts[f[k]], verts[f[k + 1]]
            u = [b[j] - a[j] for j in range(3)]
            v = [c[j] - a[j] for j in range(3)]
            cx = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
            if math.sqrt(sum(x * x for x in cx)) == 0.0:
                zero_area += 1
    unused = nv - len(used & set(range(nv)))
    if verts:
        lo = [min(v[j] for v in verts) for j in range(3)]
        hi = [max(v[j] for v in verts) for j in range(3)]
    else:
        lo = hi = [0, 0, 0]
    print(path)
    print("  vertices %d, faces %d, triangles after fan split %d" % (nv, len(faces), tris))
    print("  face arity " + ", ".join("%d-gon: %d" % (k, c) for k, c in sorted(arity.items())))
    print("  out-of-range faces %d, repeated-index faces %d, zero-area triangles %d, unused vertices %d"
          % (bad, repeated, zero_area, unused))
    print("  bbox min (%g, %g, %g) max (%g, %g, %g)" % (*lo, *hi))
    for k, c in sorted(notes.items()):
        print("  note: %s%s" % (k, "" if c == 1 else " x%d" % c))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__.strip())
        sys.exit(2)
    for p in sys.argv[1:]:
        stats(p)
