//! BGEO V5 reader: files written here (plain and gzip), the real SPlisHSPlasH files, and
//! malformed files.

mod io_support;

use std::io::Write;
use std::path::Path;

use filmsplat::io::{CloudFormat, ReadOptions, detect_format, read_cloud};
use glam::Vec3;
use io_support::{read, tmp, write};

/// (name, type, words per point, values per point as f32 bits or i32).
type AttrDef<'a> = (&'a str, i32, u16);

/// Writes a classic BGEO V5: `attrs` definitions, then per point P (w = 1) and `words[i]`.
fn bgeo(attrs: &[AttrDef], points: &[[f32; 3]], words: &[Vec<u32>]) -> Vec<u8> {
    let mut b = b"BgeoV".to_vec();
    let n = points.len() as i32;
    for v in [5, n, 1, 0, 0, attrs.len() as i32, 0, 0, 0] {
        b.extend(v.to_be_bytes());
    }
    for (name, ty, size) in attrs {
        b.extend((name.len() as u16).to_be_bytes());
        b.extend(name.bytes());
        b.extend(size.to_be_bytes());
        b.extend(ty.to_be_bytes());
        if *ty == 4 {
            b.extend(2i32.to_be_bytes());
            for s in ["a", "bc"] {
                b.extend((s.len() as u16).to_be_bytes());
                b.extend(s.bytes());
            }
        } else {
            b.extend(vec![0u8; 4 * *size as usize]);
        }
    }
    for (p, w) in points.iter().zip(words) {
        for x in [p[0], p[1], p[2], 1.0] {
            b.extend(x.to_be_bytes());
        }
        for x in w {
            b.extend(x.to_be_bytes());
        }
    }
    b.extend([0u8; 12]); // a stand-in for primitives etc. (ignored)
    b
}

fn gz(b: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(b).unwrap();
    e.finish().unwrap()
}

const ATTRS: &[AttrDef] = &[
    ("pscale", 0, 1),
    ("id", 1, 1),
    ("N", 5, 3),
    ("name", 4, 1),
    ("v", 0, 3),
];

fn sample() -> Vec<u8> {
    let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.5]];
    let words: Vec<Vec<u32>> = (0..3)
        .map(|i| {
            let f = |x: f32| x.to_bits();
            let nrm = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]][i];
            vec![
                f(0.025 * (i + 1) as f32),
                (7 + i) as u32,
                f(nrm[0]),
                f(nrm[1]),
                f(nrm[2]),
                (i % 2) as u32,
                f(i as f32),
                f(10.0 + i as f32),
                f(-(i as f32)),
            ]
        })
        .collect();
    bgeo(ATTRS, &pts, &words)
}

fn check(c: &filmsplat::pointcloud::PointCloud) {
    assert_eq!(c.positions, [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.5)]);
    assert_eq!(c.normals.as_deref().unwrap(), [Vec3::Z, Vec3::Y, Vec3::X]);
    assert_eq!(c.radius.as_deref().unwrap(), [0.025, 0.05, 0.075]);
    assert_eq!(c.extra("id").unwrap(), [7.0, 8.0, 9.0]);
    assert_eq!(c.extra("v_y").unwrap(), [10.0, 11.0, 12.0]);
    let names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["id", "v_x", "v_y", "v_z"],
        "indexed strings are skipped"
    );
    assert!(c.thickness_nm.is_none());
}

#[test]
fn plain_and_gzip_files() {
    let d = tmp("bgeo_ok");
    let plain = write(&d, "a.bgeo", &sample());
    let zipped = write(&d, "a.bgeo.gz", &gz(&sample()));
    let odd = write(&d, "cloud.bin", &gz(&sample())); // gzip magic, then Bgeo inside
    for p in [&plain, &zipped, &odd] {
        assert_eq!(detect_format(p).unwrap(), CloudFormat::Bgeo);
        check(&read(p));
    }
    let o = ReadOptions {
        thickness_attr: Some("pscale".into()),
        radius_attr: Some("v_z".into()),
        ..ReadOptions::with_thickness_scale(1e3)
    };
    let c = read_cloud(&zipped, &o).unwrap();
    assert_eq!(c.thickness_nm.as_deref().unwrap(), [25.0, 50.0, 75.0]);
    assert_eq!(c.radius.as_deref().unwrap(), [0.0, -1.0, -2.0]);
}

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

#[test]
fn real_splishsplash_files() {
    let c = read(&data("splishsplash_sphere.bgeo"));
    assert_eq!(c.len(), 12_394);
    assert!(c.radius.as_deref().unwrap().iter().all(|&r| r == 0.025));
    let r: Vec<f32> = c.positions.iter().map(|p| p.length()).collect();
    assert!(
        r.iter().all(|&r| (r - 0.99).abs() < 0.03),
        "a shell of radius ≈ 0.99"
    );
    // The PLY conversion holds the same positions, pscale and ids.
    let ply = read(&data("splishsplash_sphere_shell.ply"));
    assert_eq!(ply.positions, c.positions);
    assert_eq!(ply.radius, c.radius);
    assert_eq!(ply.extra("id").unwrap(), c.extra("id").unwrap());
    assert_eq!(c.extra.len(), 1);

    let c = read(&data("dam_break_frame_9_6859_particles.bgeo"));
    assert_eq!(c.len(), 6859);
    let names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["id", "density", "velocity_x", "velocity_y", "velocity_z"]
    );
    let dens = c.extra("density").unwrap();
    let lo = dens.iter().fold(f32::MAX, |a, &b| a.min(b));
    let hi = dens.iter().fold(f32::MIN, |a, &b| a.max(b));
    // Water: at most a few per cent above the rest density 1000 (weakly compressible SPH),
    // lower at the free surface; never near zero.
    assert!(
        lo > 100.0 && (hi - 1000.0).abs() < 60.0,
        "density {lo}..{hi}"
    );
    let mut ids: Vec<u32> = c.extra("id").unwrap().iter().map(|&v| v as u32).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), 6859, "ids are distinct");
}

fn err(p: &Path) -> String {
    let e = read_cloud(p, &ReadOptions::default())
        .expect_err("must fail")
        .to_string();
    let name = p.file_name().unwrap().to_string_lossy();
    assert!(
        e.contains(&*name) && !e.contains('\n') && e.contains("BGEO"),
        "{e}"
    );
    e
}

#[test]
fn malformed_files() {
    let d = tmp("bgeo_bad");
    let good = sample();
    let mut cases: Vec<(Vec<u8>, &str)> = Vec::new();
    let mut v = good.clone();
    v[8] = 6;
    cases.push((v, "version 6"));
    let mut v = good.clone();
    v[9..13].copy_from_slice(&i32::MAX.to_be_bytes());
    cases.push((v, "data runs out"));
    let mut v = good.clone();
    v[9..13].copy_from_slice(&(-3i32).to_be_bytes());
    cases.push((v, "negative point count"));
    let mut v = good.clone();
    v[25..29].copy_from_slice(&1_000_000i32.to_be_bytes());
    cases.push((v, "cannot fit"));
    cases.push((bgeo(&[("s", 2, 1)], &[[0.0; 3]], &[vec![0]]), "type string"));
    cases.push((
        bgeo(&[("s", 9, 1)], &[[0.0; 3]], &[vec![0]]),
        "unknown type 9",
    ));
    cases.push((bgeo(&[("s", 0, 0)], &[[0.0; 3]], &[vec![]]), "size 0"));
    cases.push((b"\x7fNSJb...".to_vec(), "JSON"));
    cases.push((b"BgeoX".to_vec(), "magic"));
    let mut z = gz(&good);
    let l = z.len();
    z.truncate(l - 30);
    cases.push((z, "gzip"));
    let mut z = gz(&good);
    z[20] ^= 0xff;
    cases.push((z, "gzip"));
    for (i, (bytes, want)) in cases.iter().enumerate() {
        let p = write(&d, &format!("bad{i}.bgeo"), bytes);
        let e = err(&p);
        assert!(e.contains(want), "case {i}: {e}");
    }
    assert!(err(&write(&d, "empty.bgeo", b"")).contains("empty"));
    // Gzip holding something else than BGEO.
    let e = read_cloud(
        &write(&d, "c.ply.gz", &gz(b"ply\nformat ascii 1.0\n")),
        &ReadOptions::default(),
    );
    let e = e.unwrap_err().to_string();
    assert!(
        e.contains("gzip-compressed PLY") && e.contains("c.ply.gz"),
        "{e}"
    );
    let p = write(&d, "ok.bgeo", &good);
    let o = ReadOptions {
        thickness_attr: Some("rh".into()),
        ..ReadOptions::default()
    };
    let e = read_cloud(&p, &o).unwrap_err().to_string();
    assert!(e.contains("'rh' not found") && e.contains("pscale"), "{e}");
}

#[test]
fn every_truncation_is_an_error() {
    let d = tmp("bgeo_trunc");
    let full = sample();
    let points_end = full.len() - 12;
    for len in 0..points_end {
        let e = err(&write(&d, "t.bgeo", &full[..len]));
        assert!(
            e.contains("runs out") || e.contains("empty") || e.contains("cannot fit"),
            "{len}: {e}"
        );
    }
    for i in 0..full.len() {
        for x in [0x01, 0x80, 0xff] {
            let mut b = full.clone();
            b[i] ^= x;
            if let Err(e) = read_cloud(&write(&d, "f.bgeo", &b), &ReadOptions::default()) {
                assert!(e.to_string().contains("f.bgeo"));
            }
        }
    }
    let z = gz(&full);
    for len in 0..z.len() {
        let _ = err(&write(&d, "t.bgeo.gz", &z[..len]));
    }
}
