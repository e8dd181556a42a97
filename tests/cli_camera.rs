//! Per-frame cameras of `render --frames`: a turntable (`--orbit`) of one still cloud renders
//! N views prepared once, and a cloud symmetric about the up axis looks the same from every
//! view; camera keys and orbits refuse bad values before any frame renders.

mod cli_support;
use cli_support::{filmsplat, tmp};

use filmsplat::image::read_png;
use std::f32::consts::PI;
use std::path::{Path, PathBuf};

/// A spherical shell of radius 1 about the origin as an ASCII PLY (normals, radii, thickness
/// growing with height): rings of latitude of 8·k particles each, all starting at azimuth 0,
/// so a quarter turn about +y maps the cloud exactly onto itself.
fn symmetric_shell(path: &Path) {
    let mut rows = Vec::new();
    let rings = 20;
    for j in 0..=rings {
        let theta = PI * j as f32 / rings as f32;
        let around = (2.0 * PI * theta.sin() / 0.16 / 8.0).ceil().max(1.0) as usize * 8;
        let around = if j == 0 || j == rings { 1 } else { around };
        for i in 0..around {
            let phi = 2.0 * PI * i as f32 / around as f32;
            let n = [
                theta.sin() * phi.sin(),
                theta.cos(),
                theta.sin() * phi.cos(),
            ];
            let h = 450.0 + 150.0 * n[1];
            rows.push(format!(
                "{} {} {} {} {} {} 0.13 {h}",
                n[0], n[1], n[2], n[0], n[1], n[2]
            ));
        }
    }
    write_ply(path, &rows);
}

/// A flat film in the plane z = 0 (not symmetric about +y): seen edge-on after a quarter turn.
fn flat_film(path: &Path) {
    let mut rows = Vec::new();
    for i in 0..16 {
        for j in 0..12 {
            let (x, y) = (i as f32 / 15.0 * 1.6 - 0.8, j as f32 / 11.0 * 1.2 - 0.6);
            rows.push(format!("{x} {y} 0 0 0 1 0.08 400"));
        }
    }
    write_ply(path, &rows);
}

fn write_ply(path: &Path, rows: &[String]) {
    let head = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
         property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float radius\nproperty float thickness\nend_header\n",
        rows.len()
    );
    std::fs::write(path, head + &rows.join("\n") + "\n").unwrap();
}

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let dir = tmp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Renders a 4-frame 360° turntable of `cloud` into `dir`; returns stderr.
fn turntable(cloud: &Path, dir: &Path) -> String {
    let out = dir.join("{:02}.png");
    let (code, _, err) = filmsplat(&[
        "render",
        cloud.to_str().unwrap(),
        "--frames",
        "0..4",
        "--orbit",
        "360",
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--spp",
        "8",
    ]);
    assert_eq!(code, 0, "{err}");
    err
}

/// Mean absolute difference of two frames' linear RGB, relative to the first's mean.
fn difference(dir: &Path, a: u32, b: u32) -> f32 {
    let img = |f: u32| read_png(&dir.join(format!("{f:02}.png"))).unwrap().data;
    let (x, y) = (img(a), img(b));
    let diff: f32 = x
        .iter()
        .zip(&y)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).sum::<f32>())
        .sum();
    let mean: f32 = x.iter().map(|p| p.iter().sum::<f32>()).sum();
    diff / mean
}

#[test]
fn a_turntable_of_a_symmetric_cloud_looks_the_same_from_every_view_and_is_prepared_once() {
    let dir = folder("turntable-shell");
    let cloud = dir.join("shell.ply");
    symmetric_shell(&cloud);
    let err = turntable(&cloud, &dir);
    // Prepared once: one report of the load, three re-aimed frames.
    assert_eq!(err.matches(": load ").count(), 1, "{err}");
    assert_eq!(
        err.matches("prepared once, camera re-aimed").count(),
        3,
        "{err}"
    );
    // The printed path is the start camera and the orbit.
    assert!(
        err.contains("camera path, auto-framed") && err.contains("orbit = 360.0"),
        "{err}"
    );
    let same: Vec<f32> = (1..4).map(|f| difference(&dir, 0, f)).collect();
    // A flat film turned a quarter is seen edge-on: the check tells views apart.
    let control = folder("turntable-flat");
    let flat = control.join("flat.ply");
    flat_film(&flat);
    turntable(&flat, &control);
    let other = difference(&control, 0, 1);
    for (f, d) in same.iter().enumerate() {
        assert!(
            *d < 0.02,
            "view {} differs by {d} (flat film's quarter turn: {other})",
            f + 1
        );
    }
    eprintln!("turntable differences: shell {same:?}, flat film {other}");
    assert!(
        other > 0.3,
        "the flat film's quarter turn differs by only {other}"
    );
}

/// Runs `render` on `args` after the input and output of a one-cloud sequence in a fresh
/// folder; returns (exit code, stderr, how many images were written).
fn refused(name: &str, scene: Option<&str>, args: &[&str]) -> (i32, String, usize) {
    let dir = folder(name);
    let cloud = dir.join("flat.ply");
    flat_film(&cloud);
    let input = match scene {
        Some(text) => {
            let s = dir.join("scene.toml");
            std::fs::write(&s, format!("[input]\ncloud = \"flat.ply\"\n\n{text}")).unwrap();
            s
        }
        None => cloud,
    };
    let out = dir.join("out").join("{:02}.png");
    let mut all = vec![
        "render",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "16x12",
        "--spp",
        "1",
    ];
    all.extend_from_slice(args);
    let (code, _, err) = filmsplat(&all);
    let written = std::fs::read_dir(dir.join("out")).map_or(0, |d| d.count());
    (code, err, written)
}

#[test]
fn bad_orbits_and_keys_are_one_line_exit_2_before_any_frame() {
    let key =
        |frame: i32, pos: &str| format!("[[camera.key]]\nframe = {frame}\nposition = {pos}\n");
    let cases: Vec<(&str, Option<String>, Vec<&str>, &str)> = vec![
        (
            "orbit-nan",
            None,
            vec!["--frames", "0..3", "--orbit", "nan"],
            "--orbit",
        ),
        (
            "orbit-inf",
            None,
            vec!["--frames", "0..3", "--orbit", "inf"],
            "--orbit",
        ),
        ("orbit-alone", None, vec!["--orbit", "90"], "needs --frames"),
        (
            "orbit-scene-nan",
            Some("[camera]\norbit = nan\n".into()),
            vec!["--frames", "0..3"],
            "line 5: camera.orbit = NaN",
        ),
        (
            "keys-order",
            Some(key(5, "[0, 0, 5]") + &key(2, "[1, 0, 5]")),
            vec!["--frames", "0..3"],
            "line 7: camera.key: frame 2 comes after frame 5",
        ),
        (
            "keys-twice",
            Some(key(2, "[0, 0, 5]") + &key(2, "[1, 0, 5]")),
            vec!["--frames", "0..3"],
            "frame 2 is keyed twice",
        ),
        (
            "keys-nan",
            Some(key(0, "[0, 0, 5]") + &key(2, "[1, nan, 5]")),
            vec!["--frames", "0..3"],
            "camera.key.1.position.1 = NaN",
        ),
        (
            "keys-no-position",
            Some("[[camera.key]]\nframe = 1\nlook_at = [0, 0, 0]\n".into()),
            vec!["--frames", "0..3"],
            "missing field `position`",
        ),
        (
            "keys-and-orbit",
            Some(key(0, "[0, 0, 5]")),
            vec!["--frames", "0..3", "--orbit", "90"],
            "choose one",
        ),
    ];
    for (name, scene, args, says) in cases {
        let (code, err, written) = refused(name, scene.as_deref(), &args);
        assert_eq!(code, 2, "{name}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        if scene.is_some() && name != "keys-and-orbit" {
            assert!(err.contains("scene.toml"), "{name}: {err}");
        }
        assert_eq!(written, 0, "{name}: frames were written");
    }
}

#[test]
fn a_single_image_of_a_moving_camera_says_it_uses_the_start() {
    let dir = folder("single-keyed");
    flat_film(&dir.join("flat.ply"));
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[input]\ncloud = \"flat.ply\"\n\n[camera]\norbit = 90\n",
    )
    .unwrap();
    let out = dir.join("one.png");
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "16x12",
        "--spp",
        "1",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("this single image is rendered from [camera] alone"),
        "{err}"
    );
    assert!(out.exists());
}
