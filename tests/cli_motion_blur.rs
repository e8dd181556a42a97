//! Motion blur (`render --shutter`) on a known motion: a flat square film moving at a known
//! velocity is smeared along the motion by the distance it covers while the shutter is open
//! (projected to pixels), centred on the frame's position, and not across it; a closed shutter
//! gives exactly the unblurred image; bad values are refused in one line before any render.

mod cli_support;
mod motion_support;
use cli_support::{filmsplat, tmp};
use motion_support::{smear, square};

use std::path::{Path, PathBuf};

const W: usize = 64;
const H: usize = 48;
/// Camera distance and vertical field of view: pixels per scene unit at the film's plane.
const DISTANCE: f32 = 3.0;
const FOV_DEG: f32 = 40.0;
/// The film's speed (scene units per second), the frame time (s) and the shutter.
const SPEED: f32 = 1.0;
const FRAME_TIME: f32 = 0.5;
const SHUTTER: f32 = 1.0;
const SLICES: u32 = 8;

/// The head-on camera of every render here: size, samples, camera, look-at, field of view.
fn camera_args() -> Vec<String> {
    let mut a: Vec<String> = ["--size", &format!("{W}x{H}"), "--spp", "16", "--camera"]
        .map(String::from)
        .to_vec();
    a.push(format!("0,0,{DISTANCE}"));
    a.extend(["--look-at", "0,0,0", "--fov"].map(String::from));
    a.push(FOV_DEG.to_string());
    a
}

/// Runs `filmsplat` with `head` (before the camera's arguments) and `tail` (after), and
/// expects success.
fn run(head: &[&str], tail: &[&str]) {
    let camera = camera_args();
    let mut args = head.to_vec();
    args.extend(camera.iter().map(String::as_str));
    args.extend_from_slice(tail);
    let (code, _, err) = filmsplat(&args);
    assert_eq!(code, 0, "{err}");
}

/// Renders `ply` head-on with `extra` flags; returns the PNG's bytes and the EXR's alpha
/// (coverage), row-major.
fn render(ply: &Path, name: &str, extra: &[&str]) -> (Vec<u8>, Vec<f32>) {
    let png = tmp(&format!("{name}.png"));
    let exr = tmp(&format!("{name}.exr"));
    let (png_s, exr_s) = (png.to_str().unwrap(), exr.to_str().unwrap());
    let head = ["render", ply.to_str().unwrap(), "-o", png_s, "--exr", exr_s];
    let mut tail = vec!["--quiet"];
    tail.extend_from_slice(extra);
    run(&head, &tail);
    let layers = filmsplat::image::read_exr(&exr).unwrap();
    assert_eq!((layers.width, layers.height), (W, H));
    let alpha = layers.rgba.iter().map(|p| p[3]).collect();
    (std::fs::read(png).unwrap(), alpha)
}

/// The alpha of row `y` (a horizontal line) or column `x`.
fn row(alpha: &[f32], y: usize) -> Vec<f32> {
    alpha[y * W..(y + 1) * W].to_vec()
}
fn column(alpha: &[f32], x: usize) -> Vec<f32> {
    (0..H).map(|y| alpha[y * W + x]).collect()
}

/// Pixels the open shutter smears each edge over: the distance covered between the first and
/// the last slice's middles, projected at the film's plane.
fn expected_smear_px() -> f32 {
    let px_per_unit = H as f32 / (2.0 * DISTANCE * (FOV_DEG.to_radians() / 2.0).tan());
    let travel = SPEED * SHUTTER * FRAME_TIME * (1.0 - 1.0 / SLICES as f32);
    travel * px_per_unit
}

fn blur_flags() -> Vec<String> {
    vec![
        "--shutter".into(),
        SHUTTER.to_string(),
        "--frame-time".into(),
        FRAME_TIME.to_string(),
        "--shutter-slices".into(),
        SLICES.to_string(),
    ]
}

fn ply(name: &str, velocity: [&str; 3]) -> PathBuf {
    let path = tmp(name);
    square(&path, velocity);
    path
}

#[test]
fn streaks_follow_the_velocity_centred_on_the_frame() {
    let flags = blur_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let want = expected_smear_px();
    for (axis, velocity) in [("x", ["1", "0", "0"]), ("y", ["0", "1", "0"])] {
        let cloud = ply(&format!("moving-{axis}.ply"), velocity);
        let (_, sharp) = render(&cloud, &format!("sharp-{axis}"), &[]);
        let (_, blurred) = render(&cloud, &format!("blurred-{axis}"), &flags);
        type Line = fn(&[f32], usize) -> Vec<f32>;
        let (along, across): (Line, Line) = match axis {
            "x" => (row, column),
            _ => (column, row),
        };
        let (mid_along, mid_across) = if axis == "x" {
            (H / 2, W / 2)
        } else {
            (W / 2, H / 2)
        };
        let (sharp_partial, sharp_centre) = smear(&along(&sharp, mid_along));
        let (partial, centre) = smear(&along(&blurred, mid_along));
        assert!(
            sharp_partial <= 4,
            "{axis}: the still film's edges are sharp"
        );
        // Two edges, each smeared over the distance travelled.
        let smeared = partial as f32 / 2.0;
        assert!(
            (smeared - want).abs() <= 2.0,
            "{axis}: each edge smeared over {smeared} px along the motion, expected {want:.1}"
        );
        // A centred shutter: the streak is centred where the frame holds the film.
        assert!(
            (centre - sharp_centre).abs() <= 0.75,
            "{axis}: the streak's centre moved from {sharp_centre} to {centre}"
        );
        // Across the motion: as sharp as the still film.
        let (across_partial, _) = smear(&across(&blurred, mid_across));
        let (sharp_across, _) = smear(&across(&sharp, mid_across));
        eprintln!(
            "{axis}: edges smeared {smeared} px (expected {want:.1}, still {sharp_partial}), \
             centre {centre:.2} (still {sharp_centre:.2}), across {across_partial} (still {sharp_across})"
        );
        assert!(
            across_partial <= sharp_across + 1,
            "{axis}: smeared across the motion ({across_partial} px, still {sharp_across})"
        );
    }
}

#[test]
fn a_closed_shutter_is_the_unblurred_image() {
    let cloud = ply("closed.ply", ["1", "0", "0"]);
    let (sharp, _) = render(&cloud, "closed-none", &[]);
    let (closed, _) = render(&cloud, "closed-zero", &["--shutter", "0"]);
    assert!(sharp == closed, "--shutter 0 changed the image");
}

/// Runs a render expecting a refusal: exit 2, one line containing every one of `needles`, no
/// output written.
fn refused(cloud: &Path, flags: &[&str], needles: &[&str]) {
    let png = tmp("refused.png");
    let _ = std::fs::remove_file(&png);
    let mut args = vec![
        "render",
        cloud.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
    ];
    args.extend_from_slice(&["--size", "64x48", "--spp", "1"]);
    args.extend_from_slice(flags);
    let (code, out, err) = filmsplat(&args);
    assert_eq!(code, 2, "{flags:?}: {err}");
    assert!(out.is_empty());
    assert_eq!(err.trim().lines().count(), 1, "{flags:?}: one line: {err}");
    for n in needles {
        assert!(err.contains(n), "{flags:?}: {n} missing from {err}");
    }
    assert!(!png.exists(), "{flags:?}: an image was written");
}

#[test]
fn bad_shutters_and_velocities_are_refused_before_rendering() {
    let cloud = ply("bad.ply", ["1", "0", "0"]);
    let t = ["--frame-time", "0.02"];
    refused(
        &cloud,
        &["--shutter", "1.5", t[0], t[1]],
        &["shutter", "1.5"],
    );
    refused(&cloud, &["--shutter", "-0.1", t[0], t[1]], &["shutter"]);
    refused(
        &cloud,
        &["--shutter", "nan", t[0], t[1]],
        &["--shutter", "not a finite number"],
    );
    refused(&cloud, &["--shutter", "0.5"], &["--frame-time"]);
    refused(&cloud, &["--shutter", "0.5", t[0], "0"], &["frame_time"]);
    refused(
        &cloud,
        &["--shutter", "0.5", t[0], t[1], "--shutter-slices", "0"],
        &["--shutter-slices", "1..=256"],
    );
    let flags = ["--shutter", "0.5", t[0], t[1]];
    let mut thickness_view = flags.to_vec();
    thickness_view.extend_from_slice(&["--view", "thickness"]);
    refused(&cloud, &thickness_view, &["shaded"]);
    let nan = ply("nan-velocity.ply", ["1", "nan", "0"]);
    refused(
        &nan,
        &flags,
        &["nan-velocity.ply", "particle 0", "velocity"],
    );
    // A cloud without a velocity: the file and what it holds are named.
    let still = tmp("still.ply");
    std::fs::write(
        &still,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nproperty float pressure\nend_header\n0 0 0 1\n1 0 0 1\n0 1 0 1\n",
    )
    .unwrap();
    refused(&still, &flags, &["still.ply", "velocity", "pressure"]);
}

#[test]
fn the_scene_file_and_any_thread_count_give_the_same_blur() {
    let cloud = ply("scene-moving.ply", ["0.6", "0.3", "0"]);
    let flags = blur_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let (by_flags, _) = render(&cloud, "by-flags", &flags);
    let (sharp, _) = render(&cloud, "scene-sharp", &[]);
    assert!(by_flags != sharp, "the shutter changed nothing");
    // The same shutter from [render] in a scene file.
    let scene = tmp("blur.toml");
    std::fs::write(
        &scene,
        format!(
            "[input]\ncloud = \"{}\"\n[render]\nshutter = {SHUTTER}\nframe_time = {FRAME_TIME}\n\
             shutter_slices = {SLICES}\n",
            cloud.display()
        ),
    )
    .unwrap();
    let (by_scene, _) = render(&scene, "by-scene", &[]);
    assert!(
        by_scene == by_flags,
        "[render] shutter differs from --shutter"
    );
    // One thread or two: the same picture (each slice's seed is fixed).
    let png = tmp("one-thread.png");
    let head = ["--threads", "1", "render", cloud.to_str().unwrap()];
    let mut tail = vec!["-o", png.to_str().unwrap(), "-q"];
    tail.extend_from_slice(&flags);
    run(&head, &tail);
    assert!(
        std::fs::read(&png).unwrap() == by_flags,
        "one thread differs"
    );
}

/// A 3-frame sequence whose frame 2 holds a NaN velocity is refused before frame 0 renders,
/// naming frame 2's file and the particle; no image and no movie is written.
#[test]
fn a_nan_velocity_in_a_later_frame_is_refused_before_any_frame_renders() {
    let dir = tmp("nan-sequence");
    std::fs::create_dir_all(&dir).unwrap();
    for f in 0..3 {
        let vy = if f == 2 { "nan" } else { "0" };
        square(&dir.join(format!("f{f}.ply")), ["1", vy, "0"]);
    }
    let input = dir.join("f{}.ply");
    for (name, output) in [
        ("images", dir.join("out/{}.png")),
        ("movie", dir.join("m.mp4")),
    ] {
        let args = [
            "render",
            input.to_str().unwrap(),
            "--frames",
            "0..3",
            "-o",
            output.to_str().unwrap(),
            "--size",
            "64x48",
            "--spp",
            "1",
            "--shutter",
            "0.5",
            "--frame-time",
            "0.02",
        ];
        let (code, out, err) = filmsplat(&args);
        assert_eq!(code, 2, "{name}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{name}: one line: {err}");
        for n in ["frame 2", "f2.ply", "particle 0", "velocity"] {
            assert!(err.contains(n), "{name}: {n} missing from {err}");
        }
        assert!(!out.contains("frame 0"), "{name}: frame 0 rendered: {out}");
        let written: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| !n.ends_with(".ply"))
            .collect();
        let images = std::fs::read_dir(dir.join("out")).map_or(0, |d| d.count());
        assert!(
            written.iter().all(|n| n == "out") && images == 0,
            "{name}: written: {written:?}, {images} images"
        );
    }
}
