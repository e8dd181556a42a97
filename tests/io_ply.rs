//! PLY reader: exact values in all three encodings, attribute mapping, skipping of lists and
//! other elements, real files, and a clean error (never a panic) for every malformed input.

use std::fs;
use std::path::{Path, PathBuf};

use filmsplat::Error;
use filmsplat::io::{ReadOptions, read_cloud};
use filmsplat::pointcloud::PointCloud;
use glam::Vec3;

/// A fresh directory for one test.
fn tmp(test: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("io_ply")
        .join(test);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    // Unlink first: truncating an existing file makes ext4 flush it to disk (auto_da_alloc).
    let _ = fs::remove_file(&p);
    fs::write(&p, bytes).unwrap();
    p
}

/// One typed value, written in any encoding.
#[derive(Clone, Copy, Debug)]
enum V {
    I8(i8),
    U8(u8),
    I16(i16),
    U16(u16),
    I32(i32),
    U32(u32),
    F32(f32),
    F64(f64),
}

impl V {
    fn bytes(self, be: bool, out: &mut Vec<u8>) {
        macro_rules! b {
            ($x:expr) => {
                out.extend(if be {
                    $x.to_be_bytes()
                } else {
                    $x.to_le_bytes()
                })
            };
        }
        match self {
            V::I8(x) => b!(x),
            V::U8(x) => b!(x),
            V::I16(x) => b!(x),
            V::U16(x) => b!(x),
            V::I32(x) => b!(x),
            V::U32(x) => b!(x),
            V::F32(x) => b!(x),
            V::F64(x) => b!(x),
        }
    }

    fn text(self) -> String {
        match self {
            V::I8(x) => x.to_string(),
            V::U8(x) => x.to_string(),
            V::I16(x) => x.to_string(),
            V::U16(x) => x.to_string(),
            V::I32(x) => x.to_string(),
            V::U32(x) => x.to_string(),
            V::F32(x) => format!("{x:?}"),
            V::F64(x) => format!("{x:?}"),
        }
    }

    fn f32(self) -> f32 {
        match self {
            V::I8(x) => x as f32,
            V::U8(x) => x as f32,
            V::I16(x) => x as f32,
            V::U16(x) => x as f32,
            V::I32(x) => x as f32,
            V::U32(x) => x as f32,
            V::F32(x) => x,
            V::F64(x) => x as f32,
        }
    }
}

/// `records` in the given encoding after `header` (property lines etc., no format/end_header).
/// Each record is a list of values; in ASCII one line per record.
fn ply(format: &str, header: &str, records: &[Vec<V>]) -> Vec<u8> {
    let mut out =
        format!("ply\nformat {format} 1.0\ncomment test\n{header}end_header\n").into_bytes();
    for r in records {
        match format {
            "ascii" => {
                let line: Vec<String> = r.iter().map(|v| v.text()).collect();
                out.extend(line.join(" ").bytes());
                out.push(b'\n');
            }
            _ => r
                .iter()
                .for_each(|v| v.bytes(format == "binary_big_endian", &mut out)),
        }
    }
    out
}

const FORMATS: [&str; 3] = ["ascii", "binary_little_endian", "binary_big_endian"];

fn read(p: &Path) -> PointCloud {
    read_cloud(p, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn extra<'a>(c: &'a PointCloud, name: &str) -> &'a [f32] {
    &c.extra
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no {name}"))
        .1
}

#[test]
fn all_types_all_encodings_exact() {
    let dir = tmp("all_types");
    let header = "element vertex 3\nproperty float x\nproperty double y\nproperty short z\n\
        property char a\nproperty uchar b\nproperty ushort c\nproperty int d\nproperty uint e\n\
        property float nx\nproperty float ny\nproperty float nz\nproperty float32 rh\n\
        property float64 radius\n";
    let recs: Vec<Vec<V>> = (0..3)
        .map(|i| {
            let k = i as f32;
            vec![
                V::F32(0.1 + k),
                V::F64(-2.7e-3 * f64::from(k + 1.0)),
                V::I16(-300 + i),
                V::I8(-128 + i as i8),
                V::U8(255 - i as u8),
                V::U16(65535),
                V::I32(-2_000_000 + i as i32),
                V::U32(16_777_216 + 2 * i as u32),
                V::F32(1.0 / 3.0),
                V::F32(-k),
                V::F32(f32::MIN_POSITIVE),
                V::F32(250.5 + k),
                V::F64(0.025),
            ]
        })
        .collect();
    for f in FORMATS {
        let p = write(&dir, &format!("{f}.ply"), &ply(f, header, &recs));
        let c = read(&p);
        assert_eq!(c.len(), 3, "{f}");
        for (i, r) in recs.iter().enumerate() {
            assert_eq!(
                c.positions[i],
                Vec3::new(r[0].f32(), r[1].f32(), r[2].f32()),
                "{f}"
            );
            assert_eq!(
                c.normals.as_ref().unwrap()[i],
                Vec3::new(r[8].f32(), r[9].f32(), r[10].f32())
            );
            assert_eq!(c.thickness_nm.as_ref().unwrap()[i], r[11].f32());
            assert_eq!(c.radius.as_ref().unwrap()[i], r[12].f32());
            for (k, name) in ["a", "b", "c", "d", "e"].iter().enumerate() {
                assert_eq!(extra(&c, name)[i], r[3 + k].f32(), "{f} {name}");
            }
        }
        let names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            ["a", "b", "c", "d", "e"],
            "file order, used attributes excluded"
        );
    }
}

#[test]
fn double_positions_and_thickness_scale() {
    let dir = tmp("double");
    let header = "element vertex 2\nproperty double x\nproperty double y\nproperty double z\n\
        property double thickness\n";
    let recs = vec![
        vec![
            V::F64(0.1),
            V::F64(1e-7),
            V::F64(-123456.789),
            V::F64(3.5e-7),
        ],
        vec![
            V::F64(f64::MAX),
            V::F64(-0.0),
            V::F64(1.0 / 7.0),
            V::F64(1e-6),
        ],
    ];
    for f in FORMATS {
        let p = write(&dir, &format!("{f}.ply"), &ply(f, header, &recs));
        let opts = ReadOptions {
            thickness_scale_to_nm: 1e9,
            ..Default::default()
        };
        let c = read_cloud(&p, &opts).unwrap();
        assert_eq!(
            c.positions[0],
            Vec3::new(0.1f64 as f32, 1e-7f64 as f32, -123456.789f64 as f32)
        );
        assert_eq!(
            c.positions[1].x,
            f32::INFINITY,
            "f64::MAX narrows to inf (not validated)"
        );
        assert_eq!(c.positions[1].z, (1.0f64 / 7.0) as f32);
        let t = c.thickness_nm.unwrap();
        assert!(
            (t[0] - 350.0).abs() < 1e-4 && (t[1] - 1000.0).abs() < 1e-3,
            "{t:?}"
        );
    }
}

#[test]
fn other_elements_and_lists_are_skipped() {
    let dir = tmp("lists");
    // face before vertex (binary skipping must read the list counts), a list on vertex, an
    // element with no properties, and faces after vertex.
    let h = "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\n\
        element empty 1000000000000\n\
        element vertex 3\nproperty float x\nproperty list ushort double nbrs\nproperty float y\n\
        property float z\nproperty int id\n\
        element edge 1\nproperty list int int pair\n";
    let recs = vec![
        vec![V::U8(3), V::I32(0), V::I32(1), V::I32(2), V::U8(7)],
        vec![V::U8(0), V::U8(9)],
        vec![
            V::F32(1.0),
            V::U16(2),
            V::F64(9.0),
            V::F64(9.5),
            V::F32(2.0),
            V::F32(3.0),
            V::I32(10),
        ],
        vec![V::F32(4.0), V::U16(0), V::F32(5.0), V::F32(6.0), V::I32(11)],
        vec![
            V::F32(7.0),
            V::U16(1),
            V::F64(-1.0),
            V::F32(8.0),
            V::F32(9.0),
            V::I32(12),
        ],
        vec![V::I32(2), V::I32(0), V::I32(1)],
    ];
    for f in FORMATS {
        let p = write(&dir, &format!("{f}.ply"), &ply(f, h, &recs));
        let c = read(&p);
        let want = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]].map(Vec3::from_array);
        assert_eq!(c.positions, want, "{f}");
        assert_eq!(extra(&c, "id"), [10.0, 11.0, 12.0]);
        assert_eq!(c.extra.len(), 1, "lists are not extras");
        assert!(c.normals.is_none() && c.thickness_nm.is_none() && c.radius.is_none());
    }
    // Faces after vertices may even be truncated: they are not read.
    let mut bytes = ply(
        "binary_little_endian",
        "element vertex 1\nproperty float x\n\
        property float y\nproperty float z\nelement face 5\nproperty list uchar int v\n",
        &[vec![V::F32(1.0), V::F32(2.0), V::F32(3.0)]],
    );
    bytes.push(3);
    let c = read(&write(&dir, "trailing.ply", &bytes));
    assert_eq!(c.positions, [Vec3::new(1.0, 2.0, 3.0)]);
}

#[test]
fn attribute_names_aliases_and_overrides() {
    let dir = tmp("attrs");
    let h = "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
        property float normal_x\nproperty float normal_y\nproperty float normal_z\n\
        property float h\nproperty float rh\nproperty float pscale\nproperty float my_t\n";
    let rec = vec![
        [1.0, 2.0, 3.0, 0.0, 0.0, 1.0, 0.5, 300.0, 0.02, 0.4]
            .map(V::F32)
            .to_vec(),
    ];
    let p = write(&dir, "a.ply", &ply("binary_little_endian", h, &rec));
    let c = read(&p);
    assert_eq!(c.normals.as_ref().unwrap()[0], Vec3::Z);
    assert_eq!(c.thickness_nm.as_ref().unwrap()[0], 300.0, "rh wins over h");
    assert_eq!(c.radius.as_ref().unwrap()[0], 0.02);
    assert_eq!(extra(&c, "h"), [0.5]);
    assert_eq!(c.extra.len(), 2);

    let opts = ReadOptions {
        thickness_attr: Some("my_t".into()),
        thickness_scale_to_nm: 1e3,
        normal_attr: Some("normal".into()),
        radius_attr: Some("h".into()),
    };
    let c = read_cloud(&p, &opts).unwrap();
    assert_eq!(c.thickness_nm.as_ref().unwrap()[0], 400.0);
    assert_eq!(c.radius.as_ref().unwrap()[0], 0.5);
    assert_eq!(extra(&c, "rh"), [300.0]);
    assert_eq!(extra(&c, "pscale"), [0.02]);

    for (opts, want) in [
        (
            ReadOptions {
                thickness_attr: Some("nope".into()),
                ..Default::default()
            },
            "thickness attribute 'nope' not found",
        ),
        (
            ReadOptions {
                normal_attr: Some("n".into()),
                ..Default::default()
            },
            "normal attribute 'n' not found",
        ),
        (
            ReadOptions {
                radius_attr: Some("rad".into()),
                ..Default::default()
            },
            "radius attribute 'rad' not found",
        ),
        (
            ReadOptions {
                radius_attr: Some("x".into()),
                ..Default::default()
            },
            "used twice",
        ),
        (
            ReadOptions {
                thickness_scale_to_nm: 0.0,
                ..Default::default()
            },
            "thickness scale",
        ),
        (
            ReadOptions {
                thickness_scale_to_nm: f64::NAN,
                ..Default::default()
            },
            "thickness scale",
        ),
    ] {
        let e = read_cloud(&p, &opts).unwrap_err().to_string();
        assert!(e.contains(want), "{e}");
    }
}

#[test]
fn dispatch_by_magic_then_extension() {
    let dir = tmp("dispatch");
    let bytes = ply(
        "ascii",
        "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n",
        &[vec![V::F32(1.0), V::F32(2.0), V::F32(3.0)]],
    );
    assert_eq!(
        read(&write(&dir, "cloud.dat", &bytes)).len(),
        1,
        "magic wins"
    );
    let e = read_cloud(
        &write(&dir, "cloud.xyz", b"1 2 3\n"),
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("cloud.xyz") && e.to_string().contains("unrecognised"),
        "{e}"
    );
    let e = read_cloud(
        &write(&dir, "cloud.PLY", b"1 2 3\n"),
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("not a PLY file"), "{e}");
}

/// Reads `bytes` as `name` and returns the error message, checking its form.
fn fail(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let p = write(dir, name, bytes);
    let e = read_cloud(&p, &ReadOptions::default()).expect_err(name);
    let m = e.to_string();
    assert!(m.contains(name), "message must name the file: {m}");
    assert!(!m.contains('\n'), "one line: {m}");
    assert!(matches!(e, Error::Format { format: "PLY", .. }), "{m}");
    assert!(m.contains("PLY"), "{m}");
    m
}

const XYZ: &str = "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n";

fn xyz_records(n: usize) -> Vec<Vec<V>> {
    (0..n)
        .map(|i| vec![V::F32(i as f32), V::F32(0.5), V::F32(-1.0)])
        .collect()
}

#[test]
fn malformed_files_give_clear_errors() {
    let dir = tmp("malformed");
    let le = "binary_little_endian";
    let full = ply(le, XYZ, &xyz_records(5));
    // Truncated in the middle of vertex 3 (each vertex is 12 bytes).
    let m = fail(&dir, "trunc.ply", &full[..full.len() - 12 - 6]);
    assert!(m.contains("vertex 3 of 5"), "{m}");
    let m = fail(&dir, "trunc_ascii.ply", &ply("ascii", XYZ, &xyz_records(4)));
    assert!(
        m.contains("line 13") && m.contains("vertex 4 of 5") && m.contains("ends"),
        "{m}"
    );
    let m = fail(
        &dir,
        "garbage.ply",
        format!(
            "ply\nformat ascii 1.0\n{XYZ}end_header\n\
        1 2 3\n\n4 5 6\n7 zz 9\n"
        )
        .as_bytes(),
    );
    assert!(
        m.contains("line 11") && m.contains("vertex 2 of 5") && m.contains("'zz'"),
        "{m}"
    );
    let one = XYZ.replace("vertex 5", "vertex 1");
    let m = fail(
        &dir,
        "few.ply",
        format!("ply\nformat ascii 1.0\n{one}end_header\n1 2\n").as_bytes(),
    );
    assert!(m.contains("line 8") && m.contains("too few values"), "{m}");
    let m = fail(
        &dir,
        "many.ply",
        format!("ply\nformat ascii 1.0\n{one}end_header\n1 2 3 4\n").as_bytes(),
    );
    assert!(m.contains("line 8") && m.contains("more values"), "{m}");
    let mut b = format!("ply\nformat ascii 1.0\n{one}end_header\n1 ").into_bytes();
    b.extend(b"\xff 3\n");
    let m = fail(&dir, "bin_in_ascii.ply", &b);
    assert!(m.contains("line 8") && m.contains("not text"), "{m}");
    let m = fail(
        &dir,
        "fmt.ply",
        format!("ply\nformat binary_middle_endian 1.0\n{XYZ}end_header\n").as_bytes(),
    );
    assert!(m.contains("line 2") && m.contains("unknown format"), "{m}");
    let m = fail(
        &dir,
        "noend.ply",
        format!("ply\nformat ascii 1.0\n{XYZ}").as_bytes(),
    );
    assert!(m.contains("no end_header"), "{m}");
    let renamed = String::from_utf8_lossy(&full).replace("end_header", "end_headr");
    let m = fail(&dir, "noend_bin.ply", renamed.as_bytes());
    assert!(m.contains("end_header"), "{m}");
    let m = fail(
        &dir,
        "noz.ply",
        &ply(
            le,
            "element vertex 1\nproperty float x\nproperty float y\n\
        property float w\n",
            &[vec![V::F32(0.0); 3]],
        ),
    );
    assert!(
        m.contains("no 'z' property") && m.contains("x, y, w"),
        "{m}"
    );
    let m = fail(
        &dir,
        "listx.ply",
        &ply(
            le,
            "element vertex 1\nproperty list uchar float x\n\
        property float y\nproperty float z\n",
            &[vec![V::U8(0), V::F32(0.0), V::F32(0.0)]],
        ),
    );
    assert!(m.contains("'x'") && m.contains("is a list"), "{m}");
    let m = fail(
        &dir,
        "listrh.ply",
        &ply(le, &format!("{XYZ}property list uchar float rh\n"), &[]),
    );
    assert!(m.contains("'rh'") && m.contains("is a list"), "{m}");
    let m = fail(
        &dir,
        "partial_n.ply",
        &ply(
            le,
            &format!("{XYZ}property float nx\nproperty float ny\n"),
            &[],
        ),
    );
    assert!(m.contains("incomplete normal"), "{m}");
    let m = fail(
        &dir,
        "novertex.ply",
        &ply(
            le,
            "element point 1\nproperty float x\n",
            &[vec![V::F32(0.0)]],
        ),
    );
    assert!(m.contains("no 'vertex' element"), "{m}");
    let m = fail(&dir, "empty.ply", b"");
    assert!(m.contains("empty file"), "{m}");
    let m = fail(&dir, "notply.ply", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR");
    assert!(m.contains("not a PLY file"), "{m}");
    let h = format!("element face 2\nproperty list char int v\n{XYZ}");
    let m = fail(
        &dir,
        "neglist.ply",
        &ply(
            le,
            &h,
            &[&[vec![V::I8(-1)], vec![V::I8(0)]][..], &xyz_records(5)].concat(),
        ),
    );
    assert!(
        m.contains("negative list length") && m.contains("face 0 of 2"),
        "{m}"
    );
    // The list count claims more items than the file holds.
    let mut b = ply(le, &h, &[vec![V::I8(0)], vec![V::I8(100), V::I32(1)]]);
    b.extend([0u8; 60]);
    let m = fail(&dir, "longlist.ply", &b);
    assert!(m.contains("face 1 of 2") && m.contains("truncated"), "{m}");
}

#[test]
fn absurd_counts_fail_before_allocating() {
    let dir = tmp("absurd");
    for f in FORMATS {
        let h =
            "element vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\n";
        let name = format!("absurd_{f}.ply");
        let m = fail(&dir, &name, &ply(f, h, &xyz_records(2)));
        assert!(
            m.contains("too short") && m.contains("1000000000000"),
            "{m}"
        );
        if f != "ascii" {
            assert!(m.contains("in vertex 2 of 1000000000000"), "{m}");
        }
    }
    // 2^64 - 1 vertices of 2^16 list items before them: the products must not overflow.
    let h = "element face 18446744073709551615\nproperty list uint double v\n\
        element vertex 18446744073709551615\nproperty double x\nproperty double y\nproperty double z\n";
    let m = fail(&dir, "overflow.ply", &ply("binary_big_endian", h, &[]));
    assert!(
        m.contains("too short") && m.contains("at or before face 0"),
        "{m}"
    );
}

#[test]
fn missing_files_and_directories() {
    let dir = tmp("paths");
    for (p, want) in [
        (dir.join("missing.ply"), "missing.ply"),
        (dir.clone(), "paths"),
    ] {
        let e = read_cloud(&p, &ReadOptions::default()).unwrap_err();
        assert!(matches!(e, Error::Io { .. }), "{e:?}");
        let m = e.to_string();
        assert!(m.contains(want) && !m.contains('\n'), "{m}");
        let e = filmsplat::io::ply::read(&p, &ReadOptions::default()).unwrap_err();
        assert!(e.to_string().contains(want), "{e}");
    }
}

/// Every prefix of a valid file is an error (not a panic) unless it holds all vertices; random
/// byte corruptions never panic.
#[test]
fn truncations_and_corruptions_never_panic() {
    let dir = tmp("fuzz");
    for f in FORMATS {
        let h = format!("element face 1\nproperty list uchar int v\n{XYZ}property float rh\n");
        let mut recs = vec![vec![V::U8(2), V::I32(1), V::I32(2)]];
        recs.extend(xyz_records(5).into_iter().map(|mut r| {
            r.push(V::F32(100.0));
            r
        }));
        let full = ply(f, &h, &recs);
        let name = format!("t_{f}.ply");
        let p = dir.join(&name);
        let opts = ReadOptions::default();
        for len in 0..full.len() {
            // ASCII: the last value "100.0\n" may lose up to 5 bytes and still be a number.
            let end_ok = f == "ascii" && len >= full.len() - 5;
            write(&dir, &name, &full[..len]);
            let r = read_cloud(&p, &opts);
            assert_eq!(r.is_ok(), end_ok, "{f} len {len}: {:?}", r.err());
        }
        write(&dir, &name, &full);
        assert_eq!(read_cloud(&p, &opts).unwrap().len(), 5);
        let mut state = 0x2545f4914f6cdd1du64;
        for _ in 0..300 {
            let mut b = full.clone();
            for _ in 0..3 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let i = (state % b.len() as u64) as usize;
                b[i] = (state >> 32) as u8;
            }
            write(&dir, &name, &b);
            if let Err(e) = read_cloud(&p, &opts) {
                assert!(e.to_string().contains("t_"), "{e}");
            }
        }
    }
}

/// Decodes record `i` (5 little-endian 4-byte fields) straight from the file, as an oracle.
fn raw_record(bytes: &[u8], stride: usize, i: usize) -> Vec<[u8; 4]> {
    let body = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let rec = &bytes[body + i * stride..body + (i + 1) * stride];
    rec.chunks(4).map(|c| c.try_into().unwrap()).collect()
}

#[test]
fn real_sphere_shell() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/splishsplash_sphere_shell.ply");
    let c = read(&p);
    assert_eq!(c.len(), 12394);
    let r: Vec<f32> = c.positions.iter().map(|p| p.length()).collect();
    assert!(
        r.iter().all(|&r| (0.98..=1.0).contains(&r)),
        "a one-layer shell of radius ~0.99"
    );
    let mean = r.iter().sum::<f32>() / r.len() as f32;
    assert!((mean - 0.99).abs() < 0.005, "{mean}");
    assert!(
        c.radius.as_ref().unwrap().iter().all(|&s| s == 0.025),
        "pscale is the radius"
    );
    let ids = extra(&c, "id");
    assert!(ids.iter().enumerate().all(|(i, &id)| id == i as f32));
    assert!(c.normals.is_none() && c.thickness_nm.is_none());
    let bytes = fs::read(&p).unwrap();
    for i in [0, 6000, 12393] {
        let raw = raw_record(&bytes, 20, i);
        let f = |k: usize| f32::from_le_bytes(raw[k]);
        assert_eq!(c.positions[i], Vec3::new(f(0), f(1), f(2)));
    }
}

#[test]
fn real_double_dam_break() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/double_dam_break_frame_26.ply");
    let c = read(&p);
    assert_eq!(c.len(), 4732);
    let names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["velocity_x", "velocity_y", "velocity_z"]);
    let bytes = fs::read(&p).unwrap();
    for i in [0, 4731] {
        let raw = raw_record(&bytes, 24, i);
        let f = |k: usize| f32::from_le_bytes(raw[k]);
        assert_eq!(c.positions[i], Vec3::new(f(0), f(1), f(2)));
        assert_eq!(extra(&c, "velocity_y")[i], f(4));
    }
    assert!((extra(&c, "velocity_y")[0] - -1.556548).abs() < 1e-6);
}
