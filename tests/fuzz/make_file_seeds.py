#!/usr/bin/python3
"""Writes the seed corpus of the file-reader fuzz targets (tests/fuzz/corpus/read_*): small cuts
of the real data (../shared/data, data/) in the layouts the real files use, plus a few small
files in the variants the readers accept (binary PLY and STL, OBJ with texture and normal
indices, OFF with colours, binary legacy VTK, both VTK cell layouts). Run from the repository root:

    /usr/bin/python3 tests/fuzz/make_file_seeds.py [SHARED_DATA]   (Debian's python3-vtk9)
"""
import os
import struct
import sys

import vtk

root = os.path.dirname(os.path.abspath(__file__))
corpus = os.path.join(root, "corpus")
shared = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "..", "..", "..", "shared", "data")


def put(target, name, data):
    os.makedirs(os.path.join(corpus, target), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(corpus, target, name), mode) as f:
        f.write(data)


def cut_faces(vertices, faces, keep):
    """The first `keep` faces and the vertices they use, renumbered in order of first use."""
    ids, out_v, out_f = {}, [], []
    for f in faces[:keep]:
        for v in f:
            if v not in ids:
                ids[v] = len(ids)
                out_v.append(vertices[v])
        out_f.append([ids[v] for v in f])
    return out_v, out_f


def read_off(path):
    with open(path) as f:
        tokens = f.read().split()
    nv, nf = int(tokens[1]), int(tokens[2])
    at = 4
    vertices = [tokens[at + 3 * i: at + 3 * i + 3] for i in range(nv)]
    at += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(tokens[at])
        faces.append([int(t) for t in tokens[at + 1: at + 1 + n]])
        at += 1 + n
    return vertices, faces


def off_text(vertices, faces, header="OFF"):
    lines = [header, f"{len(vertices)} {len(faces)} 0"]
    lines += [" ".join(v) for v in vertices]
    lines += [f"{len(f)} " + " ".join(map(str, f)) for f in faces]
    return "\n".join(lines) + "\n"


def off_seeds():
    for name, keep in (("fandisk.off", 40), ("armadillo.off", 60)):
        v, f = cut_faces(*read_off(os.path.join(shared, "geometry", name)), keep)
        put("read_off", name.replace(".off", "-cut.off"), off_text(v, f))
        if name == "fandisk.off":
            put("read_obj", "fandisk-cut.obj",
                "".join(f"v {' '.join(p)}\n" for p in v) +
                "".join("f " + " ".join(str(i + 1) for i in t) + "\n" for t in f))
    tetra_v = [["0", "0", "0"], ["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]]
    tetra_f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    coloured = ["COFF", "4 4 0"] + [" ".join(p) + " 255 0 0 255" for p in tetra_v]
    coloured += ["3 " + " ".join(map(str, t)) for t in tetra_f]
    put("read_off", "tetra-colours.off", "\n".join(coloured) + "\n")
    put("read_off", "tetra-comment.off", "OFF\n# a comment\n" + off_text(tetra_v, tetra_f)[4:])


def ply_seeds():
    with open(os.path.join(shared, "geometry", "bunny.ply")) as f:
        text = f.read()
    header, body = text.split("end_header\n", 1)
    lines = body.split("\n")
    nv = int(header.split("element vertex ")[1].split()[0])
    nf = int(header.split("element face ")[1].split()[0])
    vertices = [l.split() for l in lines[:nv]]
    faces = [[int(t) for t in l.split()[1:]] for l in lines[nv: nv + nf]]
    v, f = cut_faces(vertices, faces, 50)
    header = header.replace(f"element vertex {nv}", f"element vertex {len(v)}")
    header = header.replace(f"element face {nf}", f"element face {len(f)}")
    put("read_ply", "bunny-cut.ply", header + "end_header\n" + "".join(
        " ".join(p) + "\n" for p in v) + "".join(f"3 {t[0]} {t[1]} {t[2]}\n" for t in f))
    # Binary little endian with a scalar and a 3-component field (how ddsimp writes them).
    tetra = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
            "property float x\nproperty float y\nproperty float z\nproperty float T\n"
            "property float v[0]\nproperty float v[1]\nproperty float v[2]\n"
            "element face 4\nproperty list uchar int vertex_indices\nend_header\n").encode()
    body = b"".join(struct.pack("<7f", *p, i, i, -i, 2 * i) for i, p in enumerate(tetra))
    body += b"".join(struct.pack("<B3i", 3, *t) for t in faces)
    put("read_ply", "tetra-binary.ply", head + body)
    big = head.replace(b"binary_little_endian", b"binary_big_endian")
    body = b"".join(struct.pack(">7f", *p, i, i, -i, 2 * i) for i, p in enumerate(tetra))
    body += b"".join(struct.pack(">B3i", 3, *t) for t in faces)
    put("read_ply", "tetra-binary-big-endian.ply", big + body)


def obj_and_stl_seeds():
    put("read_obj", "quad-with-texture-and-normals.obj",
        "# two triangles\nmtllib none.mtl\no square\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "g face\nusemtl none\ns off\n"
        "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
    put("read_obj", "negative-indices.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")
    tetra = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    text = "solid tetra\n"
    for t in faces:
        text += "  facet normal 0 0 0\n    outer loop\n"
        text += "".join("      vertex %g %g %g\n" % tetra[i] for i in t)
        text += "    endloop\n  endfacet\n"
    put("read_stl", "tetra-ascii.stl", text + "endsolid tetra\n")
    binary = b"binary tetra".ljust(80, b" ") + struct.pack("<I", len(faces))
    for t in faces:
        binary += struct.pack("<3f", 0, 0, 0)
        binary += b"".join(struct.pack("<3f", *tetra[i]) for i in t) + b"\0\0"
    put("read_stl", "tetra-binary.stl", binary)


def vtk_seeds():
    def write(data, name, binary, version=42):
        writer = vtk.vtkPolyDataWriter() if isinstance(data, vtk.vtkPolyData) \
            else vtk.vtkUnstructuredGridWriter()
        writer.SetInputData(data)
        writer.SetFileVersion(version)  # 42: the layout before VTK 9; 51: OFFSETS/CONNECTIVITY
        writer.SetFileTypeToBinary() if binary else writer.SetFileTypeToASCII()
        writer.SetWriteToOutputString(True)
        writer.Write()
        out = writer.GetOutputStdString()
        put("read_vtk", name, out if isinstance(out, bytes) else out.encode("latin-1"))

    def first_cells(data, keep):
        ids = vtk.vtkIdList()
        for i in range(keep):
            ids.InsertNextId(i)
        extract = vtk.vtkExtractCells()
        extract.SetInputData(data)
        extract.SetCellList(ids)
        extract.Update()
        return extract.GetOutput()

    reader = vtk.vtkUnstructuredGridReader()
    reader.SetFileName(os.path.join(root, "..", "..", "data", "SurfaceVectors.vtk"))
    reader.ReadAllScalarsOn()
    reader.ReadAllVectorsOn()
    reader.ReadAllFieldsOn()
    reader.Update()
    grid = first_cells(reader.GetOutput(), 24)
    write(grid, "surface-vectors-cut.vtk", False)
    # The grid in the OFFSETS/CONNECTIVITY layout too, ASCII and binary.
    write(grid, "surface-vectors-cut-version-5.1.vtk", False, 51)
    write(grid, "surface-vectors-cut-version-5.1-binary.vtk", True, 51)
    geometry = vtk.vtkGeometryFilter()
    geometry.SetInputData(grid)
    geometry.Update()
    write(geometry.GetOutput(), "surface-vectors-cut-polydata-binary.vtk", True)

    reader = vtk.vtkPolyDataReader()
    reader.SetFileName(os.path.join(shared, "surfaces", "motorBike_cuttingPlane_500",
                                    "p_yNormal.vtk"))
    reader.ReadAllScalarsOn()
    reader.ReadAllFieldsOn()
    reader.Update()
    cut = first_cells(reader.GetOutput(), 30)
    geometry = vtk.vtkGeometryFilter()
    geometry.SetInputData(cut)
    geometry.Update()
    write(geometry.GetOutput(), "motorbike-p-cut.vtk", False)
    write(geometry.GetOutput(), "motorbike-p-cut-version-5.1.vtk", False, 51)


off_seeds()
ply_seeds()
obj_and_stl_seeds()
vtk_seeds()
