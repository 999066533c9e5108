"""Writes the fuzz targets' seed corpus (corpus/<target>/) and the inputs that crashed, hung or
over-allocated froth's readers before issue 25 (regressions/<target>/). Run once; its output is
committed, so ctest and CI need neither this script nor VTK. Usage, from the repository:
    /usr/bin/python3 tests/fuzz/make_corpus.py build/froth
"""
import os
import struct
import subprocess
import sys
import tempfile

import vtk

FROTH = os.path.abspath(sys.argv[1])
HERE = os.path.dirname(os.path.abspath(__file__))
tmp = tempfile.mkdtemp()


def put(kind, target, name, data):
    folder = os.path.join(HERE, kind, target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# A unit cube and a tetrahedron in every surface format.
V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
Q = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]
T = [(a, b, c) for q in Q for (a, b, c) in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
TV = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TT = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def off(v, f, head="OFF"):
    return f"{head}\n{len(v)} {len(f)} 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in v) + \
        "".join(f"{len(p)} {' '.join(map(str, p))}\n" for p in f)


def obj(v, f, group=None):
    return (f"g {group}\n" if group else "") + "".join(f"v {x} {y} {z}\n" for x, y, z in v) + \
        "".join(f"f {' '.join(str(i + 1) for i in p)}\n" for p in f)


def ply_ascii(v, f, vtype="float"):
    head = (f"ply\nformat ascii 1.0\nelement vertex {len(v)}\nproperty {vtype} x\nproperty {vtype} y\n"
            f"property {vtype} z\nelement face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
    return head + "".join(f"{x} {y} {z}\n" for x, y, z in v) + \
        "".join(f"{len(p)} {' '.join(map(str, p))}\n" for p in f)


def ply_binary(v, f, big=False):
    e = ">" if big else "<"
    head = (f"ply\nformat binary_{'big' if big else 'little'}_endian 1.0\nelement vertex {len(v)}\n"
            "property float x\nproperty float y\nproperty float z\n"
            f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n").encode()
    body = b"".join(struct.pack(e + "3f", *p) for p in v)
    body += b"".join(struct.pack(e + "B", len(p)) + struct.pack(e + f"{len(p)}i", *p) for p in f)
    return head + body


def stl_ascii(v, t, name="part"):
    def facet(a, b, c):
        return "facet normal 0 0 0\n outer loop\n" + "".join(
            f"  vertex {x} {y} {z}\n" for x, y, z in (v[a], v[b], v[c])) + " endloop\nendfacet\n"
    return f"solid {name}\n" + "".join(facet(*p) for p in t) + f"endsolid {name}\n"


def stl_binary(v, t):
    out = b"\0" * 80 + struct.pack("<I", len(t))
    for a, b, c in t:
        out += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v[i]) for i in (a, b, c)) + b"\0\0"
    return out


surfaces = {
    "stl": {"cube_ascii.stl": stl_ascii(V, T), "cube_binary.stl": stl_binary(V, T),
            "tetra_ascii.stl": stl_ascii(TV, TT, "tetra"),
            "two_solids.stl": stl_ascii(V, T[:6], "a") + stl_ascii(V, T[6:], "b")},
    "off": {"cube.off": off(V, Q), "tetra.off": off(TV, TT),
            "cube_coff.off": "COFF\n8 6 0\n" + "".join(f"{x} {y} {z} 1 0 0 1\n" for x, y, z in V) +
            "".join(f"4 {' '.join(map(str, q))}\n" for q in Q)},
    "obj": {"cube.obj": obj(V, Q, "body"), "tetra.obj": obj(TV, TT),
            "cube_slashes.obj": "".join(f"v {x} {y} {z}\n" for x, y, z in V) + "vn 0 0 1\n" +
            "".join(f"f {' '.join(f'{i + 1}//1' for i in q)}\n" for q in Q)},
    "ply": {"cube_ascii.ply": ply_ascii(V, Q), "cube_le.ply": ply_binary(V, Q),
            "cube_be.ply": ply_binary(V, Q, big=True), "tetra_double.ply": ply_ascii(TV, TT, "double")},
}
prefix = {".stl": 0, ".off": 1, ".obj": 2, ".ply": 3}  # fuzz_domain's first byte picks the format
for target, files in surfaces.items():
    for name, data in files.items():
        put("corpus", target, name, data)
        raw = data if isinstance(data, bytes) else data.encode()
        put("corpus", "domain", name, bytes([prefix[os.path.splitext(name)[1]]]) + raw)

# VTUs: froth's own (base64 binary) and VTK's encodings of it.
small = os.path.join(tmp, "small.vtu")
subprocess.run([FROTH, "mesh", "box:0,0,0,1,1,1", "-r", "0.6", "-o", small, "--quiet"], check=True)
put("corpus", "vtu", "froth_box.vtu", open(small, "rb").read())
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(small)
reader.Update()


def vtk_written(name, mode, encode=True, zlib=False):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputData(reader.GetOutput())
    path = os.path.join(tmp, name)
    w.SetFileName(path)
    {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary, "appended": w.SetDataModeToAppended}[mode]()
    if mode == "appended":
        w.SetEncodeAppendedData(encode)
    if zlib:
        w.SetCompressorTypeToZLib()
    else:
        w.SetCompressorTypeToNone()
    w.SetHeaderTypeToUInt64()
    w.Write()
    return open(path, "rb").read()


vtus = {"vtk_ascii.vtu": vtk_written("a.vtu", "ascii"), "vtk_base64.vtu": vtk_written("b.vtu", "binary"),
        "vtk_appended_raw.vtu": vtk_written("c.vtu", "appended", encode=False),
        "vtk_appended_base64.vtu": vtk_written("d.vtu", "appended", encode=True),
        "vtk_zlib_raw.vtu": vtk_written("e.vtu", "appended", encode=False, zlib=True),
        "vtk_zlib_base64.vtu": vtk_written("f.vtu", "binary", zlib=True)}
for name, data in vtus.items():
    put("corpus", "vtu", name, data)

# Regressions: issue 25's crashers, hangs and over-allocations, and their neighbours.
put("regressions", "ply", "property_before_element.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n")
put("regressions", "ply", "integer_coordinates.ply", ply_ascii(TV, TT, "int"))
put("regressions", "ply", "vertex_count_minus_one.ply", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n")
put("regressions", "ply", "face_count_past_file.ply",
    ply_ascii(TV, TT).replace("element face 4", "element face 4000000000"))
put("regressions", "ply", "list_past_file.ply", ply_binary(TV, TT)[:-9] + b"\xff")
put("regressions", "off", "coff_word_for_a_number.off", "COFF\n4 4 0\n0 0 0 1 1 1 1\nx y z 1 1 1 1\n"
    "0 1 0 1 1 1 1\n0 0 1 1 1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
put("regressions", "off", "faces_69900000.off", "OFF\n3 69900000 0\n0 0 0\n1 0 0\n0 1 0\n")
put("regressions", "off", "index_out_of_range.off", off(TV, [(0, 2, 1), (0, 1, 9), (0, 3, 2), (1, 2, 3)]))
put("regressions", "off", "face_of_one_billion.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n")
put("regressions", "obj", "index_zero_and_negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 -1 -7\n")
put("regressions", "obj", "huge_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n")
put("regressions", "stl", "binary_count_lies.stl", stl_binary(TV, TT)[:80] + struct.pack("<I", 1 << 31) +
    stl_binary(TV, TT)[84:])
put("regressions", "stl", "ascii_vertex_missing.stl", "solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\n"
    "vertex 1 0 0\nendloop\nendfacet\nendsolid x\n")
put("regressions", "stl", "ascii_nan.stl", stl_ascii(TV, TT).replace("vertex 1 0 0", "vertex nan 0 0", 1))

zlib = vtus["vtk_zlib_raw.vtu"]
start = zlib.index(b"_", zlib.index(b"<AppendedData")) + 1  # first array: blocks, block size, last size, sizes
blocks, block, last = struct.unpack_from("<QQQ", zlib, start)


def patched(data, at, patch):
    out = bytearray(data)
    out[at:at + len(patch)] = patch
    return bytes(out)


put("regressions", "vtu", "zlib_block_count_past_file.vtu", patched(zlib, start, struct.pack("<Q", 1 << 40)))
put("regressions", "vtu", "zlib_bomb_header.vtu", patched(zlib, start, struct.pack("<QQQ", blocks, 1 << 31, 1 << 31)))
put("regressions", "vtu", "zlib_lying_sizes.vtu", patched(zlib, start + 24, struct.pack("<Q", 1 << 50)))
b64 = vtus["vtk_appended_base64.vtu"]
put("regressions", "vtu", "appended_offset_past_end.vtu", b64.replace(b'offset="0"', b'offset="99999999"', 1))
raw = vtus["vtk_appended_raw.vtu"]
put("regressions", "vtu", "appended_raw_truncated.vtu", raw[:len(raw) * 2 // 3])
asc = vtus["vtk_ascii.vtu"].decode()
i = asc.index('Name="faces"')
j = asc.index(">", i) + 1
put("regressions", "vtu", "face_stream_count_lies.vtu", asc[:j] + "\n999 " + asc[j:])
k = asc.index('Name="faceoffsets"')
m = asc.index(">", k) + 1
put("regressions", "vtu", "faceoffsets_past_end.vtu", asc[:m] + "\n99999999 " + asc[m:])

for target in ("ply", "off", "obj", "stl"):
    folder = os.path.join(HERE, "regressions", target)
    for name in sorted(os.listdir(folder)):
        put("regressions", "domain", name, bytes([prefix["." + target]]) + open(os.path.join(folder, name), "rb").read())
print("corpus and regressions written under", HERE)
