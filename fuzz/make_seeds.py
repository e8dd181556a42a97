#!/usr/bin/env python3
"""Writes the small seed corpora in fuzz/corpus/<target>/ (run from fuzz/). Deterministic."""
import base64, gzip, os, shutil, struct, zlib

C = "corpus"
def put(target, name, data):
    os.makedirs(f"{C}/{target}", exist_ok=True)
    with open(f"{C}/{target}/{name}", "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())

pts = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 2.0, 0.5), (0.5, 0.5, 1.0)]
nrm = [(0, 0, 1), (0, 1, 0), (1, 0, 0), (0, 0, 1)]
rh = [100.0, 250.0, 400.0, 800.0]

# PLY: ASCII, binary LE and BE, with a face element and a list property.
hdr = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n" \
      "property float nx\nproperty float ny\nproperty float nz\nproperty float rh\n"
body = "".join(f"{p[0]} {p[1]} {p[2]} {n[0]} {n[1]} {n[2]} {h}\n" for p, n, h in zip(pts, nrm, rh))
put("ply", "ascii.ply", "ply\nformat ascii 1.0\ncomment seed\n" + hdr +
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + body + "3 0 1 2\n")
for fmt, e in [("binary_little_endian", "<"), ("binary_big_endian", ">")]:
    b = ("ply\nformat %s 1.0\n" % fmt + hdr + "property double radius\nproperty uchar id\nend_header\n").encode()
    for i, (p, n, h) in enumerate(zip(pts, nrm, rh)):
        b += struct.pack(e + "7fdB", *p, *n, h, 0.1, i)
    put("ply", fmt + ".ply", b)
put("ply", "xyz_only.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\n"
    "property double y\nproperty double z\nend_header\n0 0 0\n1e30 -1 nan\n")

# VTK legacy: ASCII polydata with point data, binary unstructured grid, and a real file.
put("vtk", "ascii.vtk", "# vtk DataFile Version 3.0\nseed\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n" +
    " ".join(f"{p[0]} {p[1]} {p[2]}" for p in pts) + "\nVERTICES 1 5\n4 0 1 2 3\n"
    "POINT_DATA 4\nSCALARS rh float 1\nLOOKUP_TABLE default\n" + " ".join(map(str, rh)) +
    "\nNORMALS normals float\n" + " ".join(f"{n[0]} {n[1]} {n[2]}" for n in nrm) +
    "\nFIELD FieldData 1\nid 1 4 int\n0 1 2 3\n")
b = b"# vtk DataFile Version 3.0\nseed\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
b += b"".join(struct.pack(">3d", *p) for p in pts) + b"\nCELLS 0 0\nCELL_TYPES 0\nPOINT_DATA 4\n"
b += b"SCALARS thickness float 1\nLOOKUP_TABLE default\n" + struct.pack(">4f", *rh) + b"\n"
put("vtk", "binary.vtk", b)
shutil.copy("../tests/data/free_particles_125_particles.vtk", f"{C}/vtk/free_particles_125.vtk")

# VTK XML: ascii, inline base64 (with zlib), appended raw; and a real file.
def arr(name, comps, vals, fmt="ascii", ty="Float32"):
    nc = f' NumberOfComponents="{comps}"' if comps > 1 else ""
    return f'<DataArray type="{ty}" Name="{name}"{nc} format="{fmt}">{vals}</DataArray>\n'
flat = [c for p in pts for c in p]
def vtu(arrays_points, arrays_data, extra="", header=""):
    return (f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
            f'byte_order="LittleEndian"{header}>\n<UnstructuredGrid>\n<Piece NumberOfPoints="4" '
            f'NumberOfCells="0">\n<PointData>\n{arrays_data}</PointData>\n<Points>\n{arrays_points}'
            f'</Points>\n</Piece>\n</UnstructuredGrid>\n{extra}</VTKFile>\n')
put("vtu", "ascii.vtu", vtu(arr("Points", 3, " ".join(map(str, flat))),
                           arr("rh", 1, " ".join(map(str, rh)))))
raw = struct.pack("<12f", *flat)
enc = base64.b64encode(struct.pack("<I", len(raw)) + raw).decode()
put("vtu", "base64.vtu", vtu(arr("Points", 3, enc, "binary"), arr("rh", 1,
    base64.b64encode(struct.pack("<I", 16) + struct.pack("<4f", *rh)).decode(), "binary")))
app = struct.pack("<I", len(raw)) + raw
put("vtu", "appended.vtu", vtu('<DataArray type="Float32" Name="Points" NumberOfComponents="3" '
    'format="appended" offset="0"/>\n', "", extra="<AppendedData encoding=\"raw\">\n_" +
    app.decode("latin-1") + "\n</AppendedData>\n").encode("latin-1"))
shutil.copy("../tests/data/fluid_250_particles.vtu", f"{C}/vtu/fluid_250.vtu")

# BGEO V5: float, int, vector and indexed-string attributes; plain and gzip.
def bgeo():
    attrs = [("pscale", 0, 1), ("id", 1, 1), ("N", 5, 3), ("name", 4, 1)]
    b = b"BgeoV" + b"".join(struct.pack(">i", v) for v in [5, 4, 1, 0, 0, len(attrs), 0, 0, 0])
    for name, ty, size in attrs:
        b += struct.pack(">H", len(name)) + name.encode() + struct.pack(">Hi", size, ty)
        if ty == 4:
            b += struct.pack(">i", 2) + b"".join(struct.pack(">H", len(s)) + s.encode() for s in ["a", "bc"])
        else:
            b += b"\0" * (4 * size)
    for i, (p, n) in enumerate(zip(pts, nrm)):
        b += struct.pack(">4f", *p, 1.0) + struct.pack(">f", 0.05) + struct.pack(">i", i)
        b += struct.pack(">3f", *n) + struct.pack(">i", i % 2)
    return b + b"\0" * 12
put("bgeo", "plain.bgeo", bgeo())
put("bgeo", "gzip.bgeo", gzip.compress(bgeo(), mtime=0))


def raw_deflate(b):
    c = zlib.compressobj(1, zlib.DEFLATED, -15)
    return c.compress(b) + c.flush()


# bgeo_gzip: raw deflate streams (the target adds the gzip framing): a file, and a bomb whose
# header declares its points and then pads with 4 MiB of zeros.
put("bgeo_gzip", "file.deflate", raw_deflate(bgeo()))
put("bgeo_gzip", "bomb.deflate", raw_deflate(bgeo() + bytes(4 << 20)))
# vtu_zlib: 8 bytes (points, last block size), then a zlib block: 3 points, and a bomb.
three = struct.pack("<9f", *range(9))
put("vtu_zlib", "three.bin", struct.pack("<II", 3, 36) + zlib.compress(three))
put("vtu_zlib", "bomb.bin", struct.pack("<II", 3, 36) + zlib.compress(three + bytes(4 << 20)))

# CSV / XYZ / TSV text.
put("csv", "comma.csv", "x,y,z,nx,ny,nz,rh\n" + "".join(
    f"{p[0]},{p[1]},{p[2]},{n[0]},{n[1]},{n[2]},{h}\n" for p, n, h in zip(pts, nrm, rh)))
put("csv", "space.xyz", "# x y z thickness\n" + "".join(f"{p[0]} {p[1]} {p[2]} {h}\n" for p, h in zip(pts, rh)))
put("csv", "tab.tsv", "x\ty\tz\r\n" + "".join(f"{p[0]}\t{p[1]}\t{p[2]}\r\n" for p in pts))

# Frame folder *_bin: u32 count then f64 values (vector and scalar).
put("frame_bin", "x_bin", struct.pack("<I", 4) + struct.pack("<12d", *flat))
put("frame_bin", "rh_bin", struct.pack("<I", 4) + struct.pack("<4d", *[h * 1e-9 for h in rh]))
put("frame_bin", "empty_bin", struct.pack("<I", 0))

# Scene files.
os.makedirs(f"{C}/scene_toml", exist_ok=True)
shutil.copy("../samples/bubble.toml", f"{C}/scene_toml/bubble.toml")
put("scene_toml", "full.toml", """[input]
cloud = "frame.ply"
thickness_attr = "rh"
repair = true
[film]
primitive = "disk"
ior = 1.33
thickness_unit = "nm"
[render]
width = 64
height = 48
spp = 2
shading = "rgb"
wavelengths = 8
[camera]
position = [0.0, 0.5, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 40.0
[environment]
kind = "uniform"
colour = [1.0, 1.0, 1.0]
[output]
path = "out.png"
exposure = 0.5
""")
put("scene_toml", "sample.toml", "[input]\nsample = \"bubble\"\nparticles = 1000\ntime = 0.5\n")
