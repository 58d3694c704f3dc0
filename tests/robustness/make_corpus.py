#!/usr/bin/env python3
"""Writes the hostile-input corpus of tests/robustness/corpus/ (issue 9, item 1).

Every file is small: the "huge" ones only claim huge counts in their headers. Run it again after
changing a case; corpus_test.cpp holds the table of what each file must be refused for. Files in
corpus/ that this script does not write (fuzz/ crash inputs) are left alone.
"""
import os
import struct

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")

# A 2 x 2 grid of squares (9 vertices, 8 triangles): a valid disk to corrupt.
GRID_V = [(i, j, 0.0) for j in range(3) for i in range(3)]
GRID_F = []
for j in range(2):
    for i in range(2):
        a = i + 3 * j
        GRID_F += [(a, a + 1, a + 4), (a, a + 4, a + 3)]


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def obj(vertices, faces, extra=""):
    s = "".join("v {} {} {}\n".format(*v) for v in vertices)
    s += "".join("f {} {} {}\n".format(*(i + 1 for i in f)) for f in faces)
    return s + extra


def off(vertices, faces):
    s = "OFF\n{} {} 0\n".format(len(vertices), len(faces))
    s += "".join("{} {} {}\n".format(*v) for v in vertices)
    return s + "".join("3 {} {} {}\n".format(*f) for f in faces)


def ply_ascii(vertices, faces, nv=None, nf=None):
    s = ("ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
         "property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n"
         ).format(len(vertices) if nv is None else nv, len(faces) if nf is None else nf)
    s += "".join("{} {} {}\n".format(*v) for v in vertices)
    return s + "".join("3 {} {} {}\n".format(*f) for f in faces)


def ply_binary(vertices, faces, nv=None, nf=None, endian="<", fmt_name="binary_little_endian"):
    header = ("ply\nformat {} 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
              "property float z\nelement face {}\nproperty list uchar int vertex_indices\n"
              "end_header\n").format(fmt_name, len(vertices) if nv is None else nv,
                                     len(faces) if nf is None else nf).encode()
    body = b"".join(struct.pack(endian + "3f", *v) for v in vertices)
    body += b"".join(struct.pack(endian + "B3i", 3, *f) for f in faces)
    return header + body


def stl_binary(triangles, count=None):
    data = b"flatmorph corpus".ljust(80, b" ")
    data += struct.pack("<I", len(triangles) if count is None else count)
    for t in triangles:
        data += struct.pack("<3f", 0, 0, 1)
        for p in t:
            data += struct.pack("<3f", *p)
        data += b"\0\0"
    return data


def stl_ascii(triangles, end=True):
    s = "solid corpus\n"
    for t in triangles:
        s += " facet normal 0 0 1\n  outer loop\n"
        s += "".join("   vertex {} {} {}\n".format(*p) for p in t)
        s += "  endloop\n endfacet\n"
    return s + ("endsolid corpus\n" if end else "")


GRID_T = [[GRID_V[i] for i in f] for f in GRID_F]
TETRA_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_F = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]


def main():
    os.makedirs(HERE, exist_ok=True)
    # --- OBJ
    write("empty.obj", "")
    write("only_comments.obj", "# exported by nothing\n\n# still nothing\n")
    write("obj_face_missing_vertex.obj", obj(GRID_V, GRID_F) + "f 1 2 42\n")
    write("obj_face_index_zero.obj", obj(GRID_V, GRID_F) + "f 0 1 2\n")
    write("obj_relative_index_before_start.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n")
    write("obj_two_vertex_face.obj", obj(GRID_V, GRID_F) + "f 1 2\n")
    write("obj_truncated_face.obj", obj(GRID_V, GRID_F)[:-4])
    write("obj_bad_number.obj", obj(GRID_V, GRID_F).replace("v 1 0 0.0", "v 1 zero 0.0", 1))
    write("obj_index_overflow.obj", obj(GRID_V, GRID_F) + "f 1 2 99999999999999999999\n")
    write("obj_binary_garbage.obj", bytes((i * 37 + 11) % 256 for i in range(600)))
    write("obj_no_faces.obj", "".join("v {} {} {}\n".format(*v) for v in GRID_V))
    write("obj_nan.obj", obj([(float("nan"), 0, 0)] + GRID_V[1:], GRID_F))
    write("obj_inf.obj", obj(GRID_V[:4] + [(1, 1, float("inf"))] + GRID_V[5:], GRID_F))
    write("obj_1e300.obj", obj([(x * 1e300, y * 1e300, z) for x, y, z in GRID_V], GRID_F))
    write("obj_1e-300.obj", obj([(x * 1e-300, y * 1e-300, z) for x, y, z in GRID_V], GRID_F))
    write("obj_all_one_point.obj", obj([(1, 1, 1)] * 9, GRID_F))
    write("obj_collinear_slivers.obj", obj([(i, 0, 0) for i in range(9)], GRID_F))
    write("obj_closed_tetrahedron.obj", obj(TETRA_V, TETRA_F))
    # three triangles on one edge
    write("obj_nonmanifold_edge.obj",
          obj([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)],
              [(0, 1, 2), (1, 0, 3), (0, 1, 4)]))
    # two grids touching at one corner: a bow tie, the boundary touches itself
    shifted = [(x + 2, y + 2, z) for x, y, z in GRID_V]
    write("obj_bowtie_vertex.obj",
          obj(GRID_V + shifted[1:], GRID_F + [tuple(8 if i == 0 else i + 8 for i in f)
                                              for f in GRID_F]))
    write("obj_two_components.obj",
          obj(GRID_V + [(x + 5, y, z) for x, y, z in GRID_V],
              GRID_F + [tuple(i + 9 for i in f) for f in GRID_F]))
    # a 4 x 4 grid without its centre squares: an annulus (a hole)
    v4 = [(i, j, 0) for j in range(4) for i in range(4)]
    f4 = []
    for j in range(3):
        for i in range(3):
            if (i, j) == (1, 1):
                continue
            a = i + 4 * j
            f4 += [(a, a + 1, a + 5), (a, a + 5, a + 4)]
    write("obj_hole.obj", obj(v4, f4))
    # --- PLY
    write("empty.ply", "")
    write("ply_header_only_magic.ply", "ply\n")
    write("ply_no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n")
    write("ply_unknown_format.ply",
          ply_ascii(GRID_V, GRID_F).replace("format ascii", "format binary_middle_endian"))
    write("ply_negative_count.ply", ply_ascii(GRID_V, GRID_F, nv=-9))
    write("ply_ascii_truncated.ply", ply_ascii(GRID_V, GRID_F)[:-30])
    write("ply_ascii_face_missing_vertex.ply", ply_ascii(GRID_V, GRID_F[:-1] + [(0, 1, 9)]))
    write("ply_binary_too_few_vertices.ply", ply_binary(GRID_V, GRID_F, nv=12))
    write("ply_binary_too_many_faces.ply", ply_binary(GRID_V, GRID_F, nf=9))
    write("ply_binary_truncated.ply", ply_binary(GRID_V, GRID_F)[:-7])
    write("ply_binary_face_missing_vertex.ply", ply_binary(GRID_V, GRID_F[:-1] + [(0, 1, 1000)]))
    write("ply_binary_negative_index.ply", ply_binary(GRID_V, GRID_F[:-1] + [(0, -5, 1)],
                                                     endian=">", fmt_name="binary_big_endian"))
    # 2^28 vertices of 12 bytes and 2^28 faces of 13: a header that claims 6.5 GB
    write("ply_claims_6GB.ply", ply_binary(GRID_V, GRID_F, nv=1 << 28, nf=1 << 28))
    write("ply_claims_2G_vertices.ply", ply_binary(GRID_V, GRID_F, nv=2147483647))
    write("ply_count_overflows_int64.ply", ply_binary(GRID_V, GRID_F, nv=99999999999999999999))
    write("ply_binary_nan.ply", ply_binary([(0, 0, float("nan"))] + GRID_V[1:], GRID_F))
    write("ply_no_vertex_element.ply",
          "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
          "end_header\n3 0 1 2\n")
    write("ply_list_count_255.ply",
          ply_binary(GRID_V, GRID_F)[:-13] + struct.pack("<B3i", 255, 0, 1, 2))
    # --- STL
    write("empty.stl", "")
    write("stl_binary_claims_4G_triangles.stl", stl_binary(GRID_T, count=0xFFFFFFFF))
    write("stl_binary_truncated.stl", stl_binary(GRID_T)[:-20])
    write("stl_binary_short_header.stl", stl_binary(GRID_T)[:60])
    write("stl_binary_inf.stl", stl_binary([[(0, 0, 0), (1, 0, 0), (0, float("inf"), 0)]] +
                                           GRID_T[1:]))
    write("stl_ascii_truncated.stl", stl_ascii(GRID_T)[:-200])
    write("stl_ascii_bad_number.stl", stl_ascii(GRID_T).replace("vertex 1 0 0", "vertex 1 O 0", 1))
    write("stl_ascii_four_vertices.stl",
          stl_ascii(GRID_T).replace("  endloop", "   vertex 5 5 5\n  endloop", 1))
    write("stl_ascii_closed.stl", stl_ascii([[TETRA_V[i] for i in f] for f in TETRA_F]))
    # --- OFF
    write("empty.off", "")
    write("off_binary.off", b"OFF BINARY\n" + struct.pack(">3i", 9, 8, 0) + bytes(20))
    write("off_counts_too_large.off", off(GRID_V, GRID_F).replace("9 8 0", "1000000000 8 0", 1))
    write("off_negative_count.off", off(GRID_V, GRID_F).replace("9 8 0", "9 -8 0", 1))
    write("off_truncated.off", off(GRID_V, GRID_F)[:-12])
    write("off_face_missing_vertex.off", off(GRID_V, GRID_F[:-1] + [(0, 1, 9)]))
    write("off_polygon_of_two.off", off(GRID_V, GRID_F).replace("3 0 1 4", "2 0 1", 1))
    write("off_huge_polygon_count.off", off(GRID_V, GRID_F).replace("3 0 1 4", "4000000000 0 1 4", 1))
    # --- plates (flat.ply) for simulate and toolpaths
    plate = ("ply\nformat ascii 1.0\nelement vertex 9\nproperty double x\nproperty double y\n"
             "property double z\nelement face 8\nproperty list uchar int vertex_indices\n"
             "property double theta1\nend_header\n")
    plate += "".join("{} {} 0\n".format(10 * x, 10 * y) for x, y, _ in GRID_V)
    write("plate_grid.ply", plate + "".join("3 {} {} {} 0.5\n".format(*f) for f in GRID_F))
    write("plate_no_theta1.ply", ply_ascii([(10 * x, 10 * y, 0) for x, y, _ in GRID_V], GRID_F))
    write("plate_nan_theta1.ply", plate + "".join("3 {} {} {} nan\n".format(*f) for f in GRID_F))
    write("plate_not_flat.ply", plate.replace("0\n10 0 0", "0\n10 0 7", 1) +
          "".join("3 {} {} {} 0.5\n".format(*f) for f in GRID_F))
    # --- other mesh inputs
    write("mesh.xyz", "0 0 0\n1 0 0\n0 1 0\n")
    write("no_extension", obj(GRID_V, GRID_F))
    # --- material JSON
    write("material_not_json.json", "lambda1 = 0.58\n")
    write("material_empty.json", "")
    write("material_array.json", "[0.58, 1.08]\n")
    write("material_unknown_key.json", '{"lamda1": 0.58}\n')
    write("material_out_of_range.json", '{"lambda1": 58}\n')
    write("material_wrong_type.json", '{"lambda1": "0.58"}\n')
    write("material_number_overflow.json", '{"lambda1": 1e400}\n')
    write("material_truncated.json", '{"lambda1": 0.58, "lambda2": 1.')
    write("material_unsafe_temperatures.json",
          '{"nozzle_temperature": 260, "max_nozzle_temperature": 230}\n')
    write("material_deep_nesting.json", '{"lambda1": ' + "[" * 5000 + "]" * 5000 + "}\n")
    # --- printer JSON
    write("printer_not_json.json", "<printer name='x'/>\n")
    write("printer_empty_object.json", "{}\n")
    write("printer_number_overflow.json", '{"name": "x", "bed": {"x": 1e999}}\n')
    write("printer_truncated.json", '{"name": "x", "bed": {')
    write("printer_string.json", '"creality-cr10s-pro"\n')
    # --- measurement sheets for `flatmorph calibrate fit` (src/calibration/measurements.h)
    head = ("sample,set,plate,nozzle_temperature,layer_height,layers,length_before,width_before,"
            "thickness_before,length_after,width_after,thickness_after,curvature,rise,chord\n")
    rows = ["{},1,1,190,0.08,10,80,20,0.8,{},{},{},0.032,,\n".format(
        i, 80 * 0.58, 20 * 1.08, 0.8 * 1.52) for i in range(1, 5)]
    good = "# kind = sets\n# samples = 4\n" + head + "".join(rows)
    write("csv_empty.csv", "")
    write("csv_no_header.csv", "".join(rows))
    write("csv_not_a_number.csv", good.replace("46.4", "46,4", 1))
    write("csv_missing_cell.csv", good.replace(",21.6,", ",,", 1))
    write("csv_length_grew.csv", good.replace("46.4", "146.4", 1))
    write("csv_nan.csv", good.replace("46.4", "nan", 1))
    write("csv_wrong_row_count.csv", good.replace("# samples = 4", "# samples = 36"))
    write("csv_repeated_sample.csv", good.replace("\n2,1,1", "\n1,1,1", 1))
    write("csv_binary_garbage.csv", bytes((i * 91 + 7) % 256 for i in range(400)))
    write("csv_bad_material_line.csv", good.replace("# kind = sets", "# kind = sets\n# material = {\"lambda1\": 1e400}"))
    # --- G-code for `flatmorph check` with a bad printer/material (the G-code itself is fine)
    write("safe.gcode", "M140 S55\nM104 S190\nG28\nM190 S55\nM109 S190\nG90\nM83\nG92 E0\n"
          "G1 Z0.2 F600\nG1 X20 Y20 F3000\nG1 X60 Y20 E1.5 F1200\nG1 Z10 F600\nM104 S0\n"
          "M140 S0\nM84\n")


if __name__ == "__main__":
    main()
