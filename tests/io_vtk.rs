//! VTK legacy reader: ASCII and binary synthetic files, the real SPlisHSPlasH files, and
//! malformed files returning one-line errors naming the file and the format.

mod io_support;

use std::path::Path;

use filmsplat::io::{CloudFormat, ReadOptions, detect_format, read_cloud};
use glam::Vec3;
use io_support::{read, tmp, write};

/// A 3-point ASCII file with every kind of point-data array, cells and cell data.
const ASCII: &str = "# vtk DataFile Version 3.0
test cloud
ASCII
FIELD FieldData 1
TIME 1 1 double
0.5
DATASET POLYDATA
POINTS 3 double
0 0 0  1 0 0
0 2 0.5
METADATA
INFORMATION 0

VERTICES 3 6
1 0 1 1 1 2
POINT_DATA 3
SCALARS rh float
LOOKUP_TABLE default
100 200 300
SCALARS id int 1
LOOKUP_TABLE default
7 8 9
VECTORS velocity float
1 2 3 4 5 6 7 8 9
NORMALS normals float
0 0 1 0 1 0 1 0 0
FIELD FieldData 2
density 1 3 double
1000 1001 1002
q 2 3 float
1 2 3 4 5 6
CELL_DATA 3
SCALARS cellid int
LOOKUP_TABLE default
0 1 2
";

fn check_ascii_cloud(c: &filmsplat::pointcloud::PointCloud) {
    assert_eq!(c.positions, [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.5)]);
    assert_eq!(c.normals.as_deref().unwrap(), [Vec3::Z, Vec3::Y, Vec3::X]);
    assert_eq!(c.thickness_nm.as_deref().unwrap(), [100.0, 200.0, 300.0]);
    assert_eq!(c.extra("id").unwrap(), [7.0, 8.0, 9.0]);
    assert_eq!(c.extra("velocity_y").unwrap(), [2.0, 5.0, 8.0]);
    assert_eq!(c.extra("density").unwrap(), [1000.0, 1001.0, 1002.0]);
    assert_eq!(c.extra("q_1").unwrap(), [2.0, 4.0, 6.0]);
    let names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "id",
            "velocity_x",
            "velocity_y",
            "velocity_z",
            "density",
            "q_0",
            "q_1"
        ]
    );
}

/// The same cloud in BINARY (big-endian), unstructured grid with 4.x cells.
fn binary_file() -> Vec<u8> {
    let mut b = b"# vtk DataFile Version 4.1\nbin\nBINARY\nDATASET UNSTRUCTURED_GRID\n".to_vec();
    b.extend(b"POINTS 3 float\n");
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.5] {
        b.extend(v.to_be_bytes());
    }
    b.extend(b"\nCELLS 3 6\n");
    for v in [1i32, 0, 1, 1, 1, 2] {
        b.extend(v.to_be_bytes());
    }
    b.extend(b"\nCELL_TYPES 3\n");
    for _ in 0..3 {
        b.extend(1i32.to_be_bytes());
    }
    b.extend(b"\nPOINT_DATA 3\nSCALARS rh double 1\nLOOKUP_TABLE default\n");
    for v in [100.0f64, 200.0, 300.0] {
        b.extend(v.to_be_bytes());
    }
    b.extend(b"\nSCALARS id unsigned_int 1\nLOOKUP_TABLE id_table\n");
    for v in [7u32, 8, 9] {
        b.extend(v.to_be_bytes());
    }
    b.extend(b"\nNORMALS normals float\n");
    for v in [0.0f32, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0] {
        b.extend(v.to_be_bytes());
    }
    b.extend(b"\nFIELD FieldData 1\nvelocity 3 3 float\n");
    for v in 1..=9 {
        b.extend((v as f32).to_be_bytes());
    }
    b.extend(b"\n");
    b
}

#[test]
fn ascii_polydata_with_every_array_kind() {
    let d = tmp("vtk_ascii");
    let p = write(&d, "c.vtk", ASCII.as_bytes());
    assert_eq!(detect_format(&p).unwrap(), CloudFormat::VtkLegacy);
    check_ascii_cloud(&read(&p));
}

#[test]
fn binary_unstructured_grid() {
    let d = tmp("vtk_binary");
    let p = write(&d, "c.dat", &binary_file()); // magic wins over the extension
    let c = read(&p);
    assert_eq!(c.positions, [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.5)]);
    assert_eq!(c.normals.as_deref().unwrap(), [Vec3::Z, Vec3::Y, Vec3::X]);
    assert_eq!(c.thickness_nm.as_deref().unwrap(), [100.0, 200.0, 300.0]);
    assert_eq!(c.extra("id").unwrap(), [7.0, 8.0, 9.0]);
    assert_eq!(c.extra("velocity_z").unwrap(), [3.0, 6.0, 9.0]);
    // Explicit options apply as for PLY.
    let o = ReadOptions {
        thickness_attr: Some("id".into()),
        radius_attr: Some("rh".into()),
        ..ReadOptions::with_thickness_scale(1e3)
    };
    let c = read_cloud(&p, &o).unwrap();
    assert_eq!(c.thickness_nm.as_deref().unwrap(), [7000.0, 8000.0, 9000.0]);
    assert_eq!(c.radius.as_deref().unwrap(), [100.0, 200.0, 300.0]);
}

#[test]
fn vtk_5_cells_layout_is_skipped() {
    let f = "# vtk DataFile Version 5.1\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n\
             0 0 0 1 1 1\nVERTICES 3 2\nOFFSETS vtktypeint64\n0 1 2\n\
             CONNECTIVITY vtktypeint64\n0 1\nPOINT_DATA 2\nSCALARS s float\n5 6\n";
    let d = tmp("vtk5");
    let c = read(&write(&d, "c.vtk", f.as_bytes()));
    assert_eq!(c.positions[1], Vec3::ONE);
    assert_eq!(c.extra("s").unwrap(), [5.0, 6.0]);
}

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

#[test]
fn real_splishsplash_files() {
    let c = read(&data("double_dam_break_frame_26_4732_particles.vtk"));
    assert_eq!(c.len(), 4732);
    let names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["id", "velocity_x", "velocity_y", "velocity_z"]);
    let mut ids: Vec<u32> = c.extra("id").unwrap().iter().map(|&v| v as u32).collect();
    ids.sort_unstable();
    assert!(ids.windows(2).all(|w| w[0] < w[1]), "ids are distinct");
    // The PLY conversion holds the same positions and velocities.
    let ply = read(&data("double_dam_break_frame_26.ply"));
    assert_eq!(ply.positions, c.positions);
    for a in ["velocity_x", "velocity_y", "velocity_z"] {
        assert_eq!(ply.extra(a).unwrap(), c.extra(a).unwrap(), "{a}");
    }
    let c = read(&data("free_particles_125_particles.vtk"));
    assert_eq!(c.len(), 125);
    assert!(c.extra.is_empty());
    assert!(c.positions.iter().all(|p| p.is_finite()));
}

fn err(p: &Path) -> String {
    let e = read_cloud(p, &ReadOptions::default())
        .expect_err("must fail")
        .to_string();
    assert!(
        e.contains(&*p.file_name().unwrap().to_string_lossy()) && !e.contains('\n'),
        "{e}"
    );
    e
}

#[test]
fn malformed_files() {
    let d = tmp("vtk_bad");
    let cases: &[(&str, &str)] = &[
        ("# vtk DataFile Version 3.0\n", "no title"),
        ("# vtk DataFile Version 3.0\nt\nUTF9\n", "ASCII or BINARY"),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n",
            "not supported",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n",
            "no POINTS",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nPOINTS 1 float\n0 0 0\n",
            "expected DATASET",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 x 1\n",
            "line 6: expected a number",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 99999999999 float\n0\n",
            "cannot fit",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n\
             POINT_DATA 2\n",
            "POINT_DATA 2 but POINTS has 1",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 int\n0 0 0\n",
            "float or double",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n\
             POINT_DATA 1\nSCALARS a bit\n1\n",
            "unsupported data type 'bit'",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n\
             POINT_DATA 1\nFIELD f 1\nv 1 5 float\n1 2 3 4 5\n",
            "5 tuples for 1 points",
        ),
        (
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\nBOGUS 1\n",
            "unknown keyword 'BOGUS'",
        ),
        ("hello\n", "not a VTK legacy file"),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let p = write(&d, &format!("bad{i}.vtk"), text.as_bytes());
        let e = err(&p);
        assert!(e.contains(want), "case {i}: {e}");
        if !want.is_empty() {
            assert!(e.contains("VTK legacy"), "case {i}: {e}");
        }
    }
    // Ends right after a header line without a newline.
    let t = "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 0 float";
    assert!(read(&write(&d, "nonl.vtk", t.as_bytes())).is_empty());
    let p = write(&d, "empty.vtk", b"");
    assert!(err(&p).contains("empty"));
    // Missing explicit attribute.
    let p = write(&d, "ok.vtk", ASCII.as_bytes());
    let o = ReadOptions {
        radius_attr: Some("pscale".into()),
        ..ReadOptions::default()
    };
    let e = read_cloud(&p, &o).unwrap_err().to_string();
    assert!(
        e.contains("'pscale' not found") && e.contains("VTK legacy"),
        "{e}"
    );
}

#[test]
fn every_truncation_is_an_error_or_a_prefix() {
    let d = tmp("vtk_trunc");
    for (name, full) in [
        ("a.vtk", ASCII.as_bytes().to_vec()),
        ("b.vtk", binary_file()),
    ] {
        for len in 0..full.len() {
            let p = write(&d, name, &full[..len]);
            match read_cloud(&p, &ReadOptions::default()) {
                Err(e) => {
                    let m = e.to_string();
                    assert!(m.contains(name) && !m.contains('\n'), "{len}: {m}");
                }
                // Cutting at a section boundary leaves a valid, shorter file.
                Ok(c) => assert!(c.len() == 3 || c.is_empty(), "{len}"),
            }
        }
    }
    // Byte flips anywhere: an error or a cloud, never a panic.
    let full = binary_file();
    for i in 0..full.len() {
        for x in [0x01, 0x20, 0xff] {
            let mut b = full.clone();
            b[i] ^= x;
            if let Err(e) = read_cloud(&write(&d, "f.vtk", &b), &ReadOptions::default()) {
                assert!(e.to_string().contains("f.vtk"));
            }
        }
    }
    // The real binary file, cut in the middle of each section.
    let full = std::fs::read(data("free_particles_125_particles.vtk")).unwrap();
    for len in (0..full.len()).step_by(7) {
        let p = write(&d, "real.vtk", &full[..len]);
        if let Err(e) = read_cloud(&p, &ReadOptions::default()) {
            assert!(e.to_string().contains("real.vtk"));
        }
    }
}
