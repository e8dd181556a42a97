//! Frame folders (`x_bin`, `norm_bin`, `rh_bin`, ...): happy path, units, and every malformed
//! case returning an error naming the file and the format.

use std::fs;
use std::path::{Path, PathBuf};

use filmsplat::io::{CloudFormat, ReadOptions, detect_format, read_cloud};
use glam::Vec3;

fn tmp(test: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("io_frame_folder")
        .join(test);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn bin(n: u32, vals: &[f64]) -> Vec<u8> {
    let mut b = n.to_le_bytes().to_vec();
    vals.iter().for_each(|v| b.extend(v.to_le_bytes()));
    b
}

/// A 3-particle folder: positions, unit normals, rh (m), h, kh and a vector sa.
fn folder(test: &str) -> PathBuf {
    let d = tmp(test);
    let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.5];
    fs::write(d.join("x_bin"), bin(3, &x)).unwrap();
    let nrm = [0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0];
    fs::write(d.join("norm_bin"), bin(3, &nrm)).unwrap();
    fs::write(d.join("rh_bin"), bin(3, &[100e-9, 250e-9, 1e-6])).unwrap();
    fs::write(d.join("h_bin"), bin(3, &[0.1, 0.2, 0.3])).unwrap();
    fs::write(d.join("kh_bin"), bin(3, &[7.0, 8.0, 9.0])).unwrap();
    let sa = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
    fs::write(d.join("sa_bin"), bin(3, &sa)).unwrap();
    fs::write(d.join("notes.txt"), b"ignored").unwrap();
    fs::create_dir_all(d.join("sub_bin")).unwrap();
    d
}

fn err(p: &Path, opts: &ReadOptions) -> String {
    let e = read_cloud(p, opts).expect_err("must fail").to_string();
    assert!(e.contains("frame folder"), "{e}");
    assert!(!e.contains('\n'), "{e}");
    e
}

#[test]
fn reads_positions_normals_thickness_in_metres_and_extras() {
    let d = folder("happy");
    assert_eq!(detect_format(&d).unwrap(), CloudFormat::FrameFolder);
    let c = read_cloud(&d, &ReadOptions::default()).unwrap();
    assert_eq!(c.positions, [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.5)]);
    assert_eq!(c.normals.as_deref().unwrap(), [Vec3::Z, Vec3::Y, Vec3::X]);
    let t = c.thickness_nm.as_deref().unwrap();
    for (got, want) in t.iter().zip([100.0, 250.0, 1000.0]) {
        assert!((got - want).abs() < 1e-3, "{got} vs {want}");
    }
    assert!(c.radius.is_none());
    assert_eq!(c.extra("h").unwrap(), [0.1, 0.2, 0.3]);
    assert_eq!(c.extra("kh").unwrap(), [7.0, 8.0, 9.0]);
    assert_eq!(c.extra("sa_y").unwrap(), [2.0, 5.0, 8.0]);
    assert_eq!(c.extra.len(), 5, "{:?}", c.extra);
}

#[test]
fn thickness_falls_back_to_h_and_explicit_units_and_names_apply() {
    let d = folder("fallback");
    fs::remove_file(d.join("rh_bin")).unwrap();
    let c = read_cloud(&d, &ReadOptions::default()).unwrap();
    let t = c.thickness_nm.unwrap();
    assert!((t[1] - 0.2e9).abs() < 1e2, "{t:?}");
    // Explicit unit (nm) and explicit name.
    let o = ReadOptions {
        thickness_attr: Some("kh".into()),
        ..ReadOptions::with_thickness_scale(1.0)
    };
    let c = read_cloud(&d, &o).unwrap();
    assert_eq!(c.thickness_nm.as_deref().unwrap(), [7.0, 8.0, 9.0]);
    assert_eq!(c.extra("h").unwrap(), [0.1, 0.2, 0.3]);
    let o = ReadOptions {
        thickness_attr: Some("rh".into()),
        ..ReadOptions::default()
    };
    let e = err(&d, &o);
    assert!(e.contains("'rh' not found"), "{e}");
    let o = ReadOptions {
        normal_attr: Some("sa".into()),
        ..ReadOptions::default()
    };
    let c = read_cloud(&d, &o).unwrap();
    assert_eq!(c.normals.as_deref().unwrap()[0], Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(c.extra("norm_x").unwrap(), [0.0, 0.0, 1.0]);
}

#[test]
fn empty_folder_frame_reads_as_empty_cloud() {
    let d = tmp("empty_frame");
    fs::write(d.join("x_bin"), bin(0, &[])).unwrap();
    fs::write(d.join("rh_bin"), bin(0, &[])).unwrap();
    let c = read_cloud(&d, &ReadOptions::default()).unwrap();
    assert!(c.is_empty());
}

#[test]
fn malformed_folders_name_the_file() {
    // Directory without x_bin: not a frame folder at all.
    let d = tmp("no_x");
    fs::write(d.join("rh_bin"), bin(1, &[1.0])).unwrap();
    let e = read_cloud(&d, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("x_bin"), "{e}");
    assert!(filmsplat::io::frame_folder::read(&d, &ReadOptions::default()).is_err());

    // Count mismatch.
    let d = folder("mismatch");
    fs::write(d.join("kh_bin"), bin(2, &[1.0, 2.0])).unwrap();
    let e = err(&d, &ReadOptions::default());
    assert!(
        e.contains("kh_bin") && e.contains("count 2 disagrees"),
        "{e}"
    );

    // Truncated vector file.
    let d = folder("truncated");
    let full = bin(3, &[0.0; 9]);
    fs::write(d.join("norm_bin"), &full[..full.len() - 5]).unwrap();
    let e = err(&d, &ReadOptions::default());
    assert!(e.contains("norm_bin") && e.contains("runs out"), "{e}");

    // A normal file holding scalars (e.g. a vector file cut to 4 + 8n bytes).
    let d = folder("scalar_norm");
    fs::write(d.join("norm_bin"), bin(3, &[0.0; 3])).unwrap();
    let e = err(&d, &ReadOptions::default());
    assert!(e.contains("norm_bin") && e.contains("names normals"), "{e}");

    // Size fits neither layout.
    let d = folder("neither");
    fs::write(d.join("sa_bin"), bin(3, &[0.0; 10])).unwrap();
    let e = err(&d, &ReadOptions::default());
    assert!(e.contains("sa_bin") && e.contains("neither"), "{e}");

    // Positions as scalars, empty x_bin file, absurd count.
    let d = folder("scalar_x");
    fs::write(d.join("x_bin"), bin(3, &[0.0; 3])).unwrap();
    let e = err(&d, &ReadOptions::default());
    assert!(e.contains("x_bin") && e.contains("scalars"), "{e}");
    fs::write(d.join("x_bin"), b"").unwrap();
    let e = err(&d, &ReadOptions::default());
    assert!(e.contains("x_bin") && e.contains("4-byte count"), "{e}");
    fs::write(d.join("x_bin"), bin(u32::MAX, &[1.0; 3])).unwrap();
    let e = err(&d, &ReadOptions::default());
    assert!(e.contains("x_bin") && e.contains("truncated"), "{e}");
}

#[test]
fn every_truncation_of_every_file_is_an_error() {
    let d = folder("every_truncation");
    for name in ["x_bin", "norm_bin", "rh_bin", "sa_bin"] {
        let full = fs::read(d.join(name)).unwrap();
        for len in 0..full.len() {
            fs::write(d.join(name), &full[..len]).unwrap();
            if len == 28 && name == "sa_bin" {
                // A vector file cut to 4 + 8n bytes is a valid scalar file: the format cannot
                // tell; it reads as the scalar attribute.
                let c = read_cloud(&d, &ReadOptions::default()).unwrap();
                let stem = name.trim_end_matches("_bin");
                assert_eq!(c.extra(stem).map(<[f32]>::len), Some(3), "{stem}");
                continue;
            }
            let e = err(&d, &ReadOptions::default());
            assert!(e.contains(name), "len {len}: {e}");
        }
        fs::write(d.join(name), &full).unwrap();
    }
    assert!(read_cloud(&d, &ReadOptions::default()).is_ok());
}
