//! Droplets (issue 28 item 3, issue 30 items 4–5): they keep the size the simulator stored in
//! every frame, film or no film; one smaller than a pixel still shows its share of it; they
//! are in every EXR layer; and every droplet file goes through the input checks, naming it.
//! Real frames are copied from tests/data into run layouts made at test time; hostile files
//! are generated here.

mod cli_support;
use cli_support::{data, filmsplat, tmp};

use filmsplat::geometry::{DiskGeometry, Droplets};
use filmsplat::image::read_exr;
use filmsplat::io::{CloudPart, PartKind, ReadOptions};
use filmsplat::pipeline::read_input_parts;
use filmsplat::render::{
    Camera, Environment, FilmShader, RenderOutput, RenderSettings, Scene, ShadingMode, Staging,
    WorldRef, render,
};
use filmsplat::spectrum::WavelengthStrategy;
use glam::Vec3;
use std::path::{Path, PathBuf};

/// A fresh folder for a test.
fn folder(name: &str) -> PathBuf {
    let d = tmp(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Copies the files of folder `from` (recursively) into `to`.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.path().is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// Empties every film file of frame folder `dir` as the simulator writes them once no film is
/// left (count 0), keeping the droplet files (`*_3d`).
fn empty_film(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        if !name.ends_with("_3d") {
            std::fs::write(dir.join(&name), 0u32.to_le_bytes()).unwrap();
        }
    }
}

/// The bursting bubble's frame 100 copied to `run/<name>`.
fn frame_100(run: &Path, name: &str) -> PathBuf {
    let d = run.join(name);
    copy_dir(Path::new(&data("thin-film-sph/bursting_bubble/100")), &d);
    d
}

/// The droplet part of `parts`.
fn droplets(parts: &[CloudPart]) -> &CloudPart {
    parts
        .iter()
        .find(|p| p.kind == PartKind::Droplets)
        .expect("a droplet part")
}

/// The droplets' radii of `dir`, read through the pipeline, and their notes.
fn radii(dir: &Path) -> (Vec<f32>, Vec<String>) {
    let parts = read_input_parts(dir, &ReadOptions::default()).unwrap();
    let d = droplets(&parts);
    (d.cloud.radius.clone().unwrap(), d.notes.clone())
}

/// The bursting bubble's film particle volume: SA·H = 1.0845e-11 m³ (= m.bin / 1000 kg/m³).
const VOLUME_M3: f64 = 1.084_536_152_407_295e-11;

fn sphere_radius(v: f64) -> f32 {
    (3.0 * v / (4.0 * std::f64::consts::PI)).cbrt() as f32
}

#[test]
fn droplets_keep_their_size_when_no_film_is_left() {
    let run = folder("size-run");
    let with_film = frame_100(&run, "100");
    let no_film = frame_100(&run, "110");
    empty_film(&no_film);
    let want = sphere_radius(VOLUME_M3);
    let (a, _) = radii(&with_film);
    let (b, notes) = radii(&no_film);
    assert_eq!(a.len(), 2548);
    assert_eq!(a.len(), b.len());
    for r in a.iter().chain(&b) {
        assert!((r - want).abs() < 1e-3 * want, "{r} vs {want}");
    }
    // Frame 110 holds no film: its size comes from the run's frame 100, and says so.
    assert!(notes.iter().any(|n| n.contains("100")), "{notes:?}");
    // Alone, with nothing stored anywhere, the guess is said to be one.
    let lone = frame_100(&folder("size-lone"), "110");
    empty_film(&lone);
    let (_, notes) = radii(&lone);
    assert!(
        notes.iter().any(|n| n.contains("no droplet volume stored")),
        "{notes:?}"
    );
}

#[test]
fn a_snapshot_gives_each_droplet_its_stored_mass_and_the_run_its_volume() {
    let run = folder("size-snapshot");
    let snap = run.join("snapshot/100");
    copy_dir(
        Path::new(&data("thin-film-sph/bursting_bubble/snapshot/100")),
        &snap,
    );
    let want = sphere_radius(VOLUME_M3);
    let (own, notes) = radii(&snap);
    assert_eq!(own.len(), 2548);
    assert!(
        own.iter().all(|r| (r - want).abs() < 1e-3 * want),
        "{notes:?}"
    );
    assert!(notes.iter().any(|n| n.contains("stored mass")), "{notes:?}");
    // A frame of the same run with no film and no frame 0: the snapshot's film masses.
    let no_film = frame_100(&run, "200");
    empty_film(&no_film);
    let (r, notes) = radii(&no_film);
    assert!(
        r.iter().all(|r| (r - want).abs() < 1e-3 * want),
        "{notes:?}"
    );
    assert!(notes.iter().any(|n| n.contains("snapshot")), "{notes:?}");
}

/// Renders `input` at 64×48 (preview preset) to an EXR; returns its layers.
fn render_exr(input: &Path, name: &str, extra: &[&str]) -> filmsplat::image::ExrLayers {
    let out = folder(name).join("r.exr");
    let mut args = vec![
        "render",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--preset",
        "preview",
    ];
    args.extend(extra);
    let (code, _, err) = filmsplat(&args);
    assert_eq!(code, 0, "{err}");
    read_exr(&out).unwrap()
}

#[test]
fn droplets_are_in_every_exr_layer() {
    let run = folder("exr-run");
    frame_100(&run, "100");
    let no_film = frame_100(&run, "110");
    empty_film(&no_film);
    // Every 3D particle a droplet: this test is about droplets, not bulk liquid.
    let l = render_exr(&no_film, "exr-nofilm", &["--liquid", "droplets"]);
    let drops = l.droplets.as_ref().expect("a droplets layer");
    let depth = l.depth.as_ref().unwrap();
    let normal = l.normal.as_ref().unwrap();
    let mut seen = 0;
    for (k, px) in l.rgba.iter().enumerate() {
        let a = px[3];
        // No film: whatever covers a pixel is droplets, and it has a depth and a normal.
        assert!(
            (a - drops[k]).abs() < 1e-5,
            "pixel {k}: alpha {a}, droplets {}",
            drops[k]
        );
        if a > 0.0 {
            seen += 1;
            assert!(depth[k] > 0.0, "pixel {k}");
            let n = Vec3::from(normal[k]);
            assert!(
                n.length() > 0.0 && n.length() <= 1.0 + 1e-4,
                "pixel {k}: {n}"
            );
        }
    }
    // 2,548 droplets, most far smaller than a pixel: each shows, so many pixels are covered.
    assert!(seen > 300, "{seen} pixels with droplets");
}

/// A scene of droplets of radius `r_px` pixels at the given pixel positions (x right, y down,
/// in pixels of a `w`×`h` image), in the plane z = 0 seen from 10 units away, no film.
fn droplet_scene(w: usize, h: usize, r_px: f32, at: &[(f32, f32)]) -> (Scene, RenderSettings) {
    let fov = 40.0f32;
    let px = 2.0 * (0.5 * fov.to_radians()).tan() * 10.0 / h as f32;
    let centre =
        |(x, y): (f32, f32)| Vec3::new((x - 0.5 * w as f32) * px, (0.5 * h as f32 - y) * px, 0.0);
    let centres: Vec<Vec3> = at.iter().map(|p| centre(*p)).collect();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, fov);
    let drops = Droplets::build(&centres, &vec![r_px * px; centres.len()]).unwrap();
    let scene = Scene {
        geometry: DiskGeometry::build(&[], &[], &[], &[]).unwrap().into(),
        camera,
        environment: Environment::Uniform(Vec3::splat(0.5)),
        layer_skip: 1e-3,
        epsilon: 1e-6,
        staging: Staging {
            droplets: drops,
            ..Staging::default()
        },
    };
    let settings = RenderSettings {
        width: w,
        height: h,
        spp: 1,
        max_depth: 4,
        ..RenderSettings::default()
    };
    (scene, settings)
}

/// Renders `scene` with its droplets grown to its camera's pixel footprints, as the pipeline
/// renders every shot.
fn render_grown(scene: &Scene, settings: &RenderSettings) -> RenderOutput {
    let (camera, h) = (&scene.camera, settings.height);
    let grown = (scene.staging.droplets)
        .footprints(|c| camera.pixel_footprint(c, h))
        .unwrap();
    let world = WorldRef {
        footprints: grown.as_ref(),
        ..scene.into()
    };
    render(world, &shader(), settings).unwrap()
}

fn shader() -> FilmShader {
    FilmShader::new(1.33, ShadingMode::Lut, 8, WavelengthStrategy::Jittered)
}

#[test]
fn a_droplet_smaller_than_a_pixel_shows_its_share_of_it() {
    let (w, h) = (64, 48);
    let r_px = 0.2;
    // Droplets at pixel corners, where no pixel centre meets them: at 1 spp they used to
    // vanish. Every one must show, in one of the four pixels around it.
    let corners: Vec<(f32, f32)> = (0..10)
        .flat_map(|i| (0..8).map(move |j| (4.0 + 6.0 * i as f32, 4.0 + 5.0 * j as f32)))
        .collect();
    let (scene, settings) = droplet_scene(w, h, r_px, &corners);
    let out = render_grown(&scene, &settings);
    for &(x, y) in &corners {
        let (x, y) = (x as usize, y as usize);
        let around = [(x - 1, y - 1), (x, y - 1), (x - 1, y), (x, y)];
        let a: f32 = around.iter().map(|(i, j)| out.alpha[j * w + i]).sum();
        assert!(a > 0.0, "droplet at corner ({x}, {y}) vanished");
        // ... with its share, not a whole pixel: four centres at 0.71 px see it at (r/g)².
        assert!(a < 4.0 * (r_px / 0.75f32).powi(2) + 1e-4, "{a}");
    }
    // Anywhere in a pixel: the mean alpha is the droplets' cross-section over the image's
    // area (exact in expectation over positions; 1,200 droplets at scattered offsets).
    let mut at = Vec::new();
    let mut s = 0.618_034f32;
    for j in 0..30 {
        for i in 0..40 {
            s = (s + 0.618_034).fract();
            let t = (s * 7.31).fract();
            at.push((1.5 + i as f32 * 1.5 + s, 1.5 + j as f32 * 1.5 + t));
        }
    }
    let (scene, settings) = droplet_scene(w, h, r_px, &at);
    let out = render_grown(&scene, &settings);
    let mean: f32 = out.alpha.iter().sum::<f32>() / (w * h) as f32;
    let want = at.len() as f32 * std::f32::consts::PI * r_px * r_px / (w * h) as f32;
    assert!(
        (mean / want - 1.0).abs() < 0.1,
        "mean alpha {mean} vs {want}"
    );
    let drops: f32 = out.droplets.iter().sum::<f32>() / (w * h) as f32;
    assert!((drops - mean).abs() < 1e-6, "{drops} vs {mean}");
}

/// A frame folder holding an empty film and droplets at `points` (f32 x y z each).
fn droplet_frame(name: &str, points: &[[f32; 3]]) -> PathBuf {
    let d = folder(name).join("7");
    std::fs::create_dir_all(&d).unwrap();
    for f in ["x_bin", "norm_bin", "rh_bin", "h_bin", "sa_bin"] {
        std::fs::write(d.join(f), 0u32.to_le_bytes()).unwrap();
    }
    let mut b = ((4 * points.len()) as i32).to_le_bytes().to_vec();
    for p in points {
        for v in p.iter().chain(&[0.0]) {
            b.extend(v.to_le_bytes());
        }
    }
    std::fs::write(d.join("tracker_points_3d"), b).unwrap();
    d
}

/// Renders `input` (64×48 preview) expecting a refusal: exit 2 and one line naming `file`.
fn refused(input: &Path, file: &str, what: &str) {
    let out = tmp(&format!("refused-{file}.png"));
    let (code, _, err) = filmsplat(&[
        "render",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--preset",
        "preview",
    ]);
    assert_eq!(code, 2, "{err}");
    let line = err
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("");
    assert!(
        line.contains(file) && line.contains(what),
        "the error should name {file} and say {what}: {err}"
    );
}

#[test]
fn bad_droplet_positions_are_refused_naming_their_file() {
    let nan = droplet_frame("nan-drops", &[[f32::NAN, 0.0, 0.0], [0.0, 0.0, 0.0]]);
    refused(&nan, "tracker_points_3d", "non-finite");
    let far = droplet_frame("far-drops", &[[3e38, 0.0, 0.0], [-3e38, 0.0, 0.0]]);
    refused(&far, "tracker_points_3d", "beyond");
}

/// An element-layout array (`u32` n, then the values as f64).
fn f64_array(n: usize, vals: &[f64]) -> Vec<u8> {
    let mut b = (n as u32).to_le_bytes().to_vec();
    vals.iter().for_each(|v| b.extend(v.to_le_bytes()));
    b
}

/// A snapshot folder `run/snapshot/3` of four film particles (a square in z = 0) whose
/// `rh.bin` is `rh`, and two droplets of masses `m` (kg).
fn snapshot(name: &str, m: &[f64], rh: Vec<u8>) -> PathBuf {
    let d = folder(name).join("snapshot/3");
    std::fs::create_dir_all(d.join("3d")).unwrap();
    let square = [
        0.0, 0.0, 0.0, 0.01, 0.0, 0.0, 0.0, 0.01, 0.0, 0.01, 0.01, 0.0,
    ];
    std::fs::write(d.join("x.bin"), f64_array(4, &square)).unwrap();
    std::fs::write(d.join("rh.bin"), rh).unwrap();
    let drops = [0.0, 0.0, 0.01, 0.0, 0.0, 0.02];
    std::fs::write(d.join("3d/x.bin"), f64_array(2, &drops)).unwrap();
    std::fs::write(d.join("3d/m.bin"), f64_array(2, m)).unwrap();
    d
}

#[test]
fn bad_snapshot_masses_and_types_are_refused_naming_their_file() {
    let ok = f64_array(4, &[5e-7; 4]);
    let mut rh = 4u32.to_le_bytes().to_vec();
    (0..4).for_each(|_| rh.extend(500i32.to_le_bytes()));
    for (name, m) in [
        ("neg-mass", [-1e-8, 1e-8]),
        ("inf-mass", [f64::INFINITY, 1e-8]),
    ] {
        let d = snapshot(name, &m, ok.clone());
        refused(&d, "m.bin", "mass");
    }
    // rh stored as int32 (4 bytes a particle) instead of float64.
    let d = snapshot("int-rh", &[1e-8, 1e-8], rh);
    refused(&d, "rh.bin", "int32");
    // The good one renders.
    let d = snapshot("good-snapshot", &[1e-8, 1e-8], ok);
    let out = tmp("good-snapshot.png");
    let (code, _, err) = filmsplat(&[
        "render",
        d.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--preset",
        "preview",
    ]);
    assert_eq!(code, 0, "{err}");
}
