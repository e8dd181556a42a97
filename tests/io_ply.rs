//! PLY reader: exact values in all three encodings, attribute mapping, skipping of lists and
//! other elements, format dispatch, and real files.

mod io_support;

use std::fs;
use std::path::Path;

use filmsplat::io::{ReadOptions, read_cloud};
use glam::Vec3;
use io_support::{FORMATS, V, extra, ply, read, tmp, write};

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
            thickness_unit_explicit: true,
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
        thickness_unit_explicit: true,
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
        &write(&dir, "cloud.dat2", b"1 2 3\n"),
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("cloud.dat2") && e.to_string().contains("unrecognised"),
        "{e}"
    );
    let e = read_cloud(
        &write(&dir, "cloud.PLY", b"1 2 3\n"),
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("not a PLY file"), "{e}");
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

#[test]
fn ascii_crlf_tabs_blank_lines_and_special_numbers() {
    let dir = tmp("crlf");
    let text = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n\
        property float y\r\nproperty double z\r\nend_header\r\n\
        1\t2 \t3\r\n\r\n  -4.5e1 +.5 1e-3  \r\nnan inf -infinity";
    let c = read(&write(&dir, "crlf.ply", text.as_bytes()));
    assert_eq!(c.positions[0], Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(c.positions[1], Vec3::new(-45.0, 0.5, 1e-3));
    let p = c.positions[2];
    assert!(
        p.x.is_nan() && p.y == f32::INFINITY && p.z == f32::NEG_INFINITY,
        "not validated"
    );
}
