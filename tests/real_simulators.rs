//! The two thin-film simulators' own output (`tests/data/thin-film-sph`, `tests/data/melp`; see
//! ATTRIBUTION.md) read as their writers meant it — checked against values decoded here, from
//! the raw bytes, by the layouts of the writers' source — and rendered.

mod cli_support;

use cli_support::{filmsplat, tmp};
use filmsplat::io::{PartKind, ReadOptions, read_parts};
use glam::Vec3;
use std::path::{Path, PathBuf};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// `BinaryDataIO::Write_Array`: u32 count, then f64 values.
fn f64s(path: &Path) -> Vec<f64> {
    let b = std::fs::read(path).unwrap();
    b[4..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// `Write_To_File_3d_Fast` / `Write_Points_Float`: i32 count of floats, then f32 x y z 0.
fn points(path: &Path) -> Vec<Vec3> {
    let b = std::fs::read(path).unwrap();
    let n = i32::from_le_bytes(b[..4].try_into().unwrap()) as usize;
    assert_eq!(b.len(), 4 + 4 * n, "{}", path.display());
    b[4..]
        .chunks_exact(16)
        .map(|c| {
            let f = |k: usize| f32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap());
            Vec3::new(f(0), f(1), f(2))
        })
        .collect()
}

fn sphere_radius(volume: f64) -> f64 {
    (3.0 * volume / (4.0 * std::f64::consts::PI)).cbrt()
}

#[test]
fn a_bursting_bubble_frame_is_its_film_and_its_droplets() {
    let dir = data("thin-film-sph/bursting_bubble/100");
    // The reader gives the droplets as stored; the pipeline sizes them.
    let parts = read_parts(&dir, &ReadOptions::default()).unwrap();
    assert!(parts[1].cloud.radius.is_none());
    let parts = filmsplat::pipeline::read_input_parts(&dir, &ReadOptions::default()).unwrap();
    assert_eq!(parts.len(), 2);
    let (film, drops) = (&parts[0], &parts[1]);
    assert_eq!(
        (film.kind, drops.kind),
        (PartKind::Film, PartKind::Droplets)
    );
    assert_eq!(film.cloud.len(), 14);
    // Thickness is rh_bin, in metres.
    let rh = f64s(&dir.join("rh_bin"));
    for (t, r) in film.cloud.thickness_nm.as_ref().unwrap().iter().zip(&rh) {
        assert!(
            (f64::from(*t) - r * 1e9).abs() < 1e-3 * r * 1e9,
            "{t} vs {r} m"
        );
    }
    // Droplets: the float32 positions of tracker_points_3d, radius of a sphere of a film
    // particle's volume SA·H (the simulator turns a film particle into a droplet of its mass).
    let want = points(&dir.join("tracker_points_3d"));
    assert_eq!(drops.cloud.positions, want);
    let mut vol: Vec<f64> = f64s(&dir.join("sa_bin"))
        .iter()
        .zip(f64s(&dir.join("h_bin")))
        .map(|(a, h)| a * h)
        .filter(|v| *v > 0.0)
        .collect();
    vol.sort_by(f64::total_cmp);
    let r = sphere_radius(vol[vol.len() / 2]);
    for got in drops.cloud.radius.as_ref().unwrap() {
        assert!((f64::from(*got) - r).abs() < 1e-3 * r, "{got} vs {r}");
    }
    // ... which is the mass the snapshot stores over water's density: the same droplets.
    let m = f64s(&data("thin-film-sph/bursting_bubble/snapshot/100/3d/m.bin"));
    assert!((sphere_radius(m[0] / 1000.0) - r).abs() < 1e-3 * r);
}

#[test]
fn snapshot_normals_are_column_2_of_the_column_major_frame() {
    let snap = data("thin-film-sph/bursting_bubble/snapshot/100");
    let parts = read_parts(&snap, &ReadOptions::default()).unwrap();
    assert_eq!(parts.len(), 2);
    let film = &parts[0].cloud;
    // The frame folder of the same frame writes Normal(i) = E(i).col(2) as norm_bin.
    let norm = f64s(&data("thin-film-sph/bursting_bubble/100/norm_bin"));
    for (n, want) in film
        .normals
        .as_ref()
        .unwrap()
        .iter()
        .zip(norm.chunks_exact(3))
    {
        let want = Vec3::new(want[0] as f32, want[1] as f32, want[2] as f32);
        assert!((*n - want).length() < 1e-6, "{n} vs {want}");
    }
    // int32 and f64 attributes, vectors and 2×2 matrices all read; the droplets from 3d/.
    for name in [
        "b", "idx", "phase", "vrt", "conc", "gamma", "v_x", "g_3", "dh_1",
    ] {
        assert!(film.extra(name).is_some(), "{name}");
    }
    let v = f64s(&snap.join("v.bin"));
    assert!((f64::from(film.extra("v_y").unwrap()[3]) - v[3 * 3 + 1]).abs() < 1e-6);
    assert_eq!(parts[1].kind, PartKind::Droplets);
    assert_eq!(parts[1].cloud.len(), 2548);
}

#[test]
fn melp_vtp_thickness_is_h_in_metres_and_radius_the_disk_of_sa() {
    let p = data("melp/bubble/l_particles_0100.vtp");
    let parts = read_parts(&p, &ReadOptions::default()).unwrap();
    let c = &parts[0].cloud;
    assert_eq!(c.len(), 19_995);
    let t = c.thickness_nm.as_ref().unwrap();
    // H is 2e-7 .. 5e-7 m: 200 .. 500 nm, not 1e-7 nm.
    assert!(
        t.iter().all(|v| (150.0..600.0).contains(v)),
        "{:?}",
        &t[..4]
    );
    let sa = c.extra("SA").unwrap();
    for (r, a) in c.radius.as_ref().unwrap().iter().zip(sa) {
        assert!((r - (a / std::f32::consts::PI).sqrt()).abs() < 1e-7);
    }
    // Naming the unit wrongly is told, in one line, with the fix.
    let out = folder("melp-unit").join("u.png");
    // Named explicitly, the unit is the user's: a warning on stderr, even with -q.
    let (code, said, err) = filmsplat(&[
        "render",
        p.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--preset",
        "preview",
        "--thickness-unit",
        "nm",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(said.is_empty(), "stdout is for data: {said}");
    assert!(
        err.lines().any(|l| l.starts_with("filmsplat: warning:")
            && l.contains("below 0.001 nm")
            && l.contains("--thickness-unit m")),
        "{err}"
    );
}

#[test]
fn a_melp_foam_frame_is_one_film_per_bubble() {
    let dir = data("melp/foam3/50");
    let parts = read_parts(&dir, &ReadOptions::default()).unwrap();
    let counts: Vec<usize> = parts.iter().map(|p| p.cloud.len()).collect();
    assert_eq!(counts, [4445, 5428, 5124]);
    for (r, p) in parts.iter().enumerate() {
        assert_eq!(p.kind, PartKind::Film);
        assert_eq!(
            p.cloud.positions,
            points(&dir.join(format!("l_tracker_points_{r}")))
        );
        let h = f64s(&dir.join(format!("l_h_bin_{r}")));
        let t = p.cloud.thickness_nm.as_ref().unwrap();
        assert!((f64::from(t[7]) - h[7] * 1e9).abs() < 1e-3);
        let n = p.cloud.normals.as_ref().unwrap();
        assert!(n.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    }
}

/// A fresh folder for a test.
fn folder(name: &str) -> PathBuf {
    let d = tmp(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Renders `inputs` (preview preset, `size`) to an EXR and returns (stdout, the EXR's alpha).
fn render_at(name: &str, inputs: &[&Path], size: &str, extra: &[&str]) -> (String, Vec<f32>) {
    let out = folder(name).join("r.exr");
    let mut args = vec!["render".to_string()];
    args.extend(inputs.iter().map(|p| p.to_str().unwrap().to_string()));
    args.extend(
        [
            "-o",
            out.to_str().unwrap(),
            "--size",
            size,
            "--preset",
            "preview",
        ]
        .map(String::from),
    );
    args.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, out_text, said) = filmsplat(&refs);
    assert_eq!(code, 0, "{said}");
    assert!(out_text.is_empty(), "stdout is for data: {out_text}");
    let img = filmsplat::image::read_exr(&out).unwrap();
    (said, img.rgba.iter().map(|p| p[3]).collect())
}

/// [`render_at`] 64×48.
fn render(name: &str, inputs: &[&Path], extra: &[&str]) -> (String, Vec<f32>) {
    render_at(name, inputs, "64x48", extra)
}

#[test]
fn frames_render_as_written_droplets_included() {
    // Frame 100: 14 film particles and 2,548 droplets; the picture holds both. (By default
    // the 3D particles packed into bodies are drawn as a water surface, see
    // tests/render_liquid.rs; here every one is counted as a droplet.)
    let as_droplets: &[&str] = &["--liquid", "droplets"];
    let (said, _) = render(
        "sph-100",
        &[&data("thin-film-sph/bursting_bubble/100")],
        as_droplets,
    );
    assert!(
        said.contains("14 particles") && said.contains("2548 droplets"),
        "{said}"
    );
    // A frame whose film has ruptured completely still renders its droplets.
    let dir = folder("sph-droplets-only");
    let src = data("thin-film-sph/bursting_bubble/100");
    for f in std::fs::read_dir(&src).unwrap() {
        let f = f.unwrap();
        std::fs::copy(f.path(), dir.join(f.file_name())).unwrap();
    }
    for film in ["x_bin", "norm_bin", "h_bin", "rh_bin", "kh_bin", "sa_bin"] {
        std::fs::write(dir.join(film), 0u32.to_le_bytes()).unwrap();
    }
    let (said, _) = render("sph-empty-film", &[&dir], as_droplets);
    assert!(
        said.contains("0 particles") && said.contains("2548 droplets"),
        "{said}"
    );
}

#[test]
fn several_inputs_are_one_scene() {
    // The shell, and the shell with a copy moved along x: both are in the picture.
    let shell = data("splishsplash_sphere_shell.ply");
    let far = folder("two-inputs").join("far.ply");
    // The same shell moved 3 units along x.
    let (code, _, err) = filmsplat(&[
        "convert",
        shell.to_str().unwrap(),
        "-o",
        far.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let c = filmsplat::io::read_cloud(&far, &ReadOptions::default()).unwrap();
    let moved = filmsplat::pointcloud::PointCloud {
        positions: c
            .positions
            .iter()
            .map(|p| *p + Vec3::new(3.0, 0.0, 0.0))
            .collect(),
        ..c
    };
    filmsplat::io::write_ply(&far, &moved).unwrap();
    let camera = ["--camera", "1.5,0,9", "--look-at", "1.5,0,0"];
    let (_, one) = render("one-input", &[&shell], &camera);
    let (said, two) = render("two-inputs-r", &[&shell, &far], &camera);
    let covered = |a: &[f32], left: bool| {
        a.iter()
            .enumerate()
            .filter(|(k, v)| **v > 0.5 && ((k % 64) < 32) == left)
            .count()
    };
    assert!(
        covered(&one, true) > 100 && covered(&one, false) < 10,
        "one shell, on the left"
    );
    assert!(
        covered(&two, true) > 100 && covered(&two, false) > 100,
        "{said}"
    );
}

#[test]
fn fitted_radii_leave_no_pinholes_in_closed_real_films() {
    // The pinhole share the render prints (the front layer missing where the particles hold
    // film), at 1 spp, on real closed films.
    let share = |said: &str| -> f64 {
        let at = said.find("pinholes at ").expect(said) + "pinholes at ".len();
        said[at..].split(' ').next().unwrap().parse().unwrap()
    };
    for (name, input) in [
        ("fit-melp", data("melp/bubble/l_particles_0100.vtp")),
        ("fit-shell", data("splishsplash_sphere_shell.ply")),
    ] {
        let (said, _) = render_at(name, &[&input], "320x240", &[]);
        assert!(share(&said) <= 0.02, "{name}: {said}");
        let (raw, _) = render_at(name, &[&input], "320x240", &["--raw-radii"]);
        assert!(
            share(&raw) > 0.05,
            "{name} without fitting has pinholes: {raw}"
        );
    }
}
