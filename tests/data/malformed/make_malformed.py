#!/usr/bin/env python3
"""Writes the malformed-input corpus beside this script (run from anywhere; deterministic).

Every file here must make the reader fail with one clean error line: truncated, byte-flipped,
absurd-count, wrong-type, missing-property, garbage, empty files of every format, and frame
folders (subdirectories) with broken *_bin files. tests/malformed_corpus.rs reads them all."""
import base64, gzip, os, shutil, struct, zlib

HERE = os.path.dirname(os.path.abspath(__file__))
os.chdir(HERE)
for f in os.listdir("."):
    if f not in ("make_malformed.py", "README.md"):
        shutil.rmtree(f) if os.path.isdir(f) else os.remove(f)

def put(name, data):
    with open(name, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode("latin-1"))

pts = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 2.0, 0.5), (0.5, 0.5, 1.0)]
flat = [c for p in pts for c in p]

def truncations(stem, ext, data, cuts):
    for k, cut in enumerate(cuts):
        put(f"{stem}_truncated_{k}.{ext}", data[:cut])

# ---------------------------------------------------------------- PLY
hdr = "ply\nformat {fmt} 1.0\nelement vertex {n}\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
ascii_ply = hdr.format(fmt="ascii", n=4) + "".join(f"{p[0]} {p[1]} {p[2]}\n" for p in pts)
bin_ply = hdr.format(fmt="binary_little_endian", n=4).encode() + struct.pack("<12f", *flat)
put("ply_empty.ply", b"")
put("ply_magic_only.ply", "ply\n")
put("ply_no_end_header.ply", hdr.format(fmt="ascii", n=4).replace("end_header\n", ""))
put("ply_absurd_count.ply", hdr.format(fmt="binary_little_endian", n=10**12).encode() + b"\0" * 64)
put("ply_absurd_count_ascii.ply", hdr.format(fmt="ascii", n=10**12) + "0 0 0\n")
put("ply_negative_count.ply", hdr.format(fmt="ascii", n=-4) + "0 0 0\n")
put("ply_count_overflow.ply", hdr.format(fmt="ascii", n=2**70) + "0 0 0\n")
put("ply_unknown_format.ply", hdr.format(fmt="binary_middle_endian", n=4) + "0 0 0\n")
put("ply_bad_type.ply", ascii_ply.replace("property float y", "property floot y"))
put("ply_missing_x.ply", ascii_ply.replace("property float x\n", "property float w\n"))
put("ply_list_as_x.ply", ascii_ply.replace("property float x", "property list uchar float x"))
put("ply_no_vertex.ply", ascii_ply.replace("element vertex", "element point"))
put("ply_garbage_ascii.ply", hdr.format(fmt="ascii", n=4) + "0 0 0\n1 zero 0\n0 0 0\n0 0 0\n")
put("ply_short_line.ply", hdr.format(fmt="ascii", n=4) + "0 0 0\n1 0\n0 0 0\n0 0 0\n")
put("ply_too_few_lines.ply", hdr.format(fmt="ascii", n=4) + "0 0 0\n")
put("ply_binary_short_body.ply", bin_ply[:-5])
put("ply_not_utf8_header.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float \xff\xfe\nend_header\n0\n")
put("ply_nul_in_header.ply", b"ply\nformat ascii\x00 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n")
put("ply_huge_list.ply", "ply\nformat binary_little_endian 1.0\nelement face 1\n"
    "property list uint int vertex_indices\nelement vertex 1\nproperty float x\nproperty float y\n"
    "property float z\nend_header\n".encode()
    + struct.pack("<I", 0xFFFFFFFF) + b"\0" * 8 + struct.pack("<3f", 0, 0, 0))
flipped = bytearray(bin_ply); flipped[bin_ply.index(b"vertex 4") + 7] = ord("9")
put("ply_flipped_count.ply", bytes(flipped))
flipped = bytearray(bin_ply); flipped[bin_ply.index(b"binary")] ^= 0x20
put("ply_flipped_format.ply", bytes(flipped))
truncations("ply_bin", "ply", bin_ply, [len(bin_ply) - 1, len(bin_ply) - 24, len(bin_ply) - 47, 20])

# ---------------------------------------------------------------- VTK legacy
vtk_head = "# vtk DataFile Version 3.0\nmalformed\n{enc}\nDATASET POLYDATA\nPOINTS {n} float\n"
ascii_vtk = vtk_head.format(enc="ASCII", n=4) + " ".join(map(str, flat)) + "\n"
bin_vtk = vtk_head.format(enc="BINARY", n=4).encode() + struct.pack(">12f", *flat) + b"\n"
put("vtk_empty.vtk", b"")
put("vtk_header_only.vtk", "# vtk DataFile Version 3.0\n")
put("vtk_absurd_points.vtk", vtk_head.format(enc="BINARY", n=10**12).encode() + b"\0" * 48)
put("vtk_negative_points.vtk", vtk_head.format(enc="ASCII", n=-3) + "0 0 0\n")
put("vtk_unknown_encoding.vtk", vtk_head.format(enc="EBCDIC", n=4) + "0\n")
put("vtk_unknown_dataset.vtk", ascii_vtk.replace("POLYDATA", "HYPERCUBE"))
put("vtk_unknown_type.vtk", ascii_vtk.replace("POINTS 4 float", "POINTS 4 quaternion"))
put("vtk_no_points.vtk", "# vtk DataFile Version 3.0\nmalformed\nASCII\nDATASET POLYDATA\n")
put("vtk_garbage_number.vtk", ascii_vtk.replace("0.5 0.5 1.0", "0.5 zebra 1.0"))
put("vtk_too_few_values.vtk", vtk_head.format(enc="ASCII", n=4) + "0 0 0 1 0 0\n")
put("vtk_absurd_scalars.vtk", ascii_vtk + "POINT_DATA 4\nSCALARS rh float 1000000000\nLOOKUP_TABLE default\n1 2 3 4\n")
put("vtk_point_data_mismatch.vtk", ascii_vtk + "POINT_DATA 7\nSCALARS rh float 1\nLOOKUP_TABLE default\n1 2 3 4\n")
put("vtk_truncated_scalars.vtk", ascii_vtk + "POINT_DATA 4\nSCALARS rh float 1\nLOOKUP_TABLE default\n1 2\n")
truncations("vtk_bin", "vtk", bin_vtk, [len(bin_vtk) - 2, len(bin_vtk) - 30, len(bin_vtk) - 49])

# ---------------------------------------------------------------- VTK XML
def vtu(n, points, data="", extra="", attrs=""):
    return (f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
            f'byte_order="LittleEndian"{attrs}>\n<UnstructuredGrid>\n<Piece NumberOfPoints="{n}" '
            f'NumberOfCells="0">\n<PointData>{data}</PointData>\n<Points>\n{points}</Points>\n</Piece>\n'
            f'</UnstructuredGrid>\n{extra}</VTKFile>\n')
def arr(vals, fmt="ascii", name="Points", comps=3, ty="Float32", more=""):
    return f'<DataArray type="{ty}" Name="{name}" NumberOfComponents="{comps}" format="{fmt}"{more}>{vals}</DataArray>\n'
ascii_vtu = vtu(4, arr(" ".join(map(str, flat))))
raw = struct.pack("<12f", *flat)
b64 = base64.b64encode(struct.pack("<I", len(raw)) + raw).decode()
put("vtu_empty.vtu", b"")
put("vtu_not_xml.vtu", "<?xml version=\"1.0\"?>\nthis is not a VTK file\n")
put("vtu_unclosed.vtu", ascii_vtu[: ascii_vtu.index("</Points>")])
put("vtu_absurd_points.vtu", vtu(10**12, arr(" ".join(map(str, flat)))))
put("vtu_count_mismatch.vtu", vtu(9, arr(" ".join(map(str, flat)))))
put("vtu_garbage_ascii.vtu", vtu(4, arr(" ".join(map(str, flat[:-1])) + " banana")))
put("vtu_bad_base64.vtu", vtu(4, arr("!!!!not*base64!!!!", "binary")))
put("vtu_short_base64.vtu", vtu(4, arr(b64[:12], "binary")))
put("vtu_wrong_type.vtu", vtu(4, arr(" ".join(map(str, flat)), ty="Float128")))
put("vtu_two_components.vtu", vtu(4, arr(" ".join(map(str, flat)), comps=2)))
put("vtu_no_points.vtu", vtu(4, "").replace("<Points>\n</Points>\n", ""))
put("vtu_unknown_compressor.vtu", vtu(4, arr(b64, "binary"), attrs=' compressor="vtkLZMAFancy"'))
put("vtu_big_endian_unsupported_header.vtu", vtu(4, arr(b64, "binary"), attrs=' header_type="UInt16"'))
put("vtu_appended_truncated.vtu",
    vtu(4, arr("", "appended", more=' offset="0"').replace("></DataArray>", "/>").replace("</DataArray>", ""),
        extra='<AppendedData encoding="raw">\n_' + (struct.pack("<I", 48) + raw[:20]).decode("latin-1") + "\n</AppendedData>\n"))
put("vtu_appended_bad_offset.vtu",
    vtu(4, arr("", "appended", more=' offset="99999"').replace("></DataArray>", "/>").replace("</DataArray>", ""),
        extra='<AppendedData encoding="raw">\n_' + (struct.pack("<I", 48) + raw).decode("latin-1") + "\n</AppendedData>\n"))
zblock = zlib.compress(raw)
zhead = struct.pack("<4I", 1, len(raw), len(raw), len(zblock))
put("vtu_zlib_corrupt.vtu", vtu(4, arr(base64.b64encode(zhead).decode() + base64.b64encode(b"\x78\x9c garbage").decode(), "binary"),
                                attrs=' compressor="vtkZLibDataCompressor"'))
truncations("vtu_ascii", "vtu", ascii_vtu.encode(), [len(ascii_vtu) // 2, len(ascii_vtu) - 30, 40])

# ---------------------------------------------------------------- BGEO
def bgeo(n=4, version=5, attr=("pscale", 1, 0), points=None):
    b = b"BgeoV" + struct.pack(">i", version) + b"".join(struct.pack(">i", v) for v in [n, 0, 0, 0, 1, 0, 0, 0])
    name, size, ty = attr
    b += struct.pack(">H", len(name)) + name.encode() + struct.pack(">Hi", size, ty) + b"\0" * (4 * size)
    for p in (pts if points is None else points):
        b += struct.pack(">5f", *p, 1.0, 0.05)
    return b + b"\0" * 12
good = bgeo()
put("bgeo_empty.bgeo", b"")
put("bgeo_bad_magic.bgeo", b"BgeoX" + good[5:])
put("bgeo_version_4.bgeo", bgeo(version=4))
put("bgeo_absurd_count.bgeo", bgeo(n=2**31 - 1))
put("bgeo_negative_count.bgeo", bgeo(n=-5))
put("bgeo_string_attribute.bgeo", bgeo(attr=("label", 1, 2)))
put("bgeo_unknown_attribute_type.bgeo", bgeo(attr=("weird", 1, 77)))
put("bgeo_absurd_attribute_size.bgeo", bgeo(attr=("big", 65535, 0)))
put("bgeo_json.bgeo", b'\x7fNSJ[{"fileversion":"19.5"}]')
put("bgeo_corrupt_gzip.bgeo", gzip.compress(good, mtime=0)[:10] + b"\xde\xad\xbe\xef" * 8)
put("bgeo_truncated_gzip.bgeo", gzip.compress(good, mtime=0)[:-20])
put("bgeo_gzip_of_garbage.bgeo.gz", gzip.compress(b"Bgeo but nothing after", mtime=0))
truncations("bgeo", "bgeo", good, [4, 9, 20, 45, len(good) - 20, len(good) - 13])

# ---------------------------------------------------------------- CSV / XYZ
put("csv_empty.csv", b"")
put("csv_blank_lines.csv", "\n\n   \n")
put("csv_no_x_column.csv", "a,b,c\n1,2,3\n")
put("csv_not_a_number.csv", "x,y,z\n1,2,3\n4,five,6\n")
put("csv_too_few_fields.csv", "x,y,z,rh\n1,2,3,100\n4,5,6\n")
put("csv_too_many_fields.csv", "x,y,z\n1,2,3\n4,5,6,7\n")
put("csv_not_utf8.csv", b"x,y,z\n1,2,3\n\xff\xfe,0,0\n")
put("csv_binary_garbage.xyz", bytes(range(256)) * 4)
put("csv_duplicate_column.csv", "x,y,z,x\n1,2,3,4\n")
put("csv_empty_field.tsv", "x\ty\tz\n1\t\t3\n")

# ---------------------------------------------------------------- frame folders (directories)
def frame(name, files):
    os.makedirs(name)
    for f, data in files.items():
        with open(os.path.join(name, f), "wb") as fh:
            fh.write(data)
xb = struct.pack("<I", 4) + struct.pack("<12d", *flat)
rb = struct.pack("<I", 4) + struct.pack("<4d", 1e-7, 2e-7, 3e-7, 4e-7)
frame("frame_no_x_bin", {"rh_bin": rb})
frame("frame_x_bin_truncated", {"x_bin": xb[:-9]})
frame("frame_x_bin_short", {"x_bin": b"\x04\x00"})
frame("frame_x_bin_absurd_count", {"x_bin": struct.pack("<I", 0xFFFFFFFF) + xb[4:]})
frame("frame_x_bin_scalar", {"x_bin": rb})
frame("frame_count_mismatch", {"x_bin": xb, "rh_bin": struct.pack("<I", 3) + struct.pack("<3d", 1, 2, 3)})
frame("frame_rh_bin_truncated", {"x_bin": xb, "rh_bin": rb[:-3]})
frame("frame_norm_bin_scalar", {"x_bin": xb, "norm_bin": rb})
frame("frame_x_bin_empty", {"x_bin": b""})
