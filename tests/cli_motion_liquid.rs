//! Motion blur moves the liquid surface: a block of 3D SPH particles (a snapshot folder's
//! `3d/`, drawn with `--liquid surface`) moving at a known velocity is smeared along the motion
//! by the distance it covers while the shutter is open, centred where the frame holds it, and
//! not across the motion.

mod cli_support;
mod motion_support;
use cli_support::{filmsplat, tmp};
use motion_support::smear;

use std::path::{Path, PathBuf};

const W: usize = 64;
const H: usize = 48;
/// Liquid spacing, m, and particles along each side of the block.
const SPACING: f64 = 0.01;
const SIDE: usize = 10;
/// Camera distance from the block's centre (m) and vertical field of view (degrees).
const DISTANCE: f32 = 0.5;
const FOV_DEG: f32 = 40.0;
/// The block's speed (m/s), the frame time (s), the shutter and its slices.
const SPEED: f32 = 0.2;
const FRAME_TIME: f32 = 0.5;
const SLICES: u32 = 8;

/// An element-layout array (`u32` n, then the values as f64).
fn f64_array(n: usize, vals: &[f64]) -> Vec<u8> {
    let mut b = (n as u32).to_le_bytes().to_vec();
    vals.iter().for_each(|v| b.extend(v.to_le_bytes()));
    b
}

/// A snapshot folder: four still film particles behind the camera (out of view) and a cubic
/// block of SIDE³ 3D particles centred on the origin, all moving at `velocity` (m/s).
fn snapshot(name: &str, velocity: [f64; 3]) -> PathBuf {
    let d = tmp(name).join("snapshot/3");
    std::fs::create_dir_all(d.join("3d")).unwrap();
    let film = [
        0.0, 0.0, 5.0, 0.01, 0.0, 5.0, 0.0, 0.01, 5.0, 0.01, 0.01, 5.0,
    ];
    std::fs::write(d.join("x.bin"), f64_array(4, &film)).unwrap();
    std::fs::write(d.join("rh.bin"), f64_array(4, &[5e-7; 4])).unwrap();
    std::fs::write(d.join("v.bin"), f64_array(4, &[0.0; 12])).unwrap();
    let n = SIDE * SIDE * SIDE;
    let half = (SIDE - 1) as f64 / 2.0;
    let x: Vec<f64> = (0..n)
        .flat_map(|i| [i % SIDE, (i / SIDE) % SIDE, i / (SIDE * SIDE)])
        .map(|k| (k as f64 - half) * SPACING)
        .collect();
    let v: Vec<f64> = (0..n).flat_map(|_| velocity).collect();
    std::fs::write(d.join("3d/x.bin"), f64_array(n, &x)).unwrap();
    std::fs::write(d.join("3d/v.bin"), f64_array(n, &v)).unwrap();
    // Each particle the water of its cell: spacing³ × 1000 kg/m³.
    let m = vec![SPACING.powi(3) * 1000.0; n];
    std::fs::write(d.join("3d/m.bin"), f64_array(n, &m)).unwrap();
    d
}

/// Renders `input` head-on (camera on +z) with `extra` flags; returns the EXR's alpha
/// (coverage), row-major, and stderr.
fn render(input: &Path, name: &str, extra: &[&str]) -> (Vec<f32>, String) {
    let png = tmp(&format!("{name}.png"));
    let exr = tmp(&format!("{name}.exr"));
    let (size, fov, camera) = (
        format!("{W}x{H}"),
        FOV_DEG.to_string(),
        format!("0,0,{DISTANCE}"),
    );
    let mut args = vec![
        "render",
        input.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
    ];
    args.extend_from_slice(&[
        "--exr",
        exr.to_str().unwrap(),
        "--size",
        &size,
        "--spp",
        "16",
    ]);
    args.extend_from_slice(&["--camera", &camera, "--look-at", "0,0,0", "--fov", &fov]);
    args.extend_from_slice(&["--liquid", "surface"]);
    args.extend_from_slice(extra);
    let (code, _, err) = filmsplat(&args);
    assert_eq!(code, 0, "{err}");
    let layers = filmsplat::image::read_exr(&exr).unwrap();
    assert_eq!((layers.width, layers.height), (W, H));
    (layers.rgba.iter().map(|p| p[3]).collect(), err)
}

#[test]
fn the_liquid_surface_streaks_along_its_velocity() {
    let input = snapshot("liquid-moving", [SPEED as f64, 0.0, 0.0]);
    let (sharp, _) = render(&input, "liquid-sharp", &[]);
    let (slices, frame_time) = (SLICES.to_string(), FRAME_TIME.to_string());
    let flags = [
        "--shutter",
        "1",
        "--frame-time",
        &frame_time,
        "--shutter-slices",
        &slices,
    ];
    let (blurred, err) = render(&input, "liquid-blurred", &flags);
    // The note that the liquid stays is gone.
    assert!(!err.contains("liquid surface is drawn where"), "{err}");
    let row = |a: &[f32]| a[(H / 2) * W..(H / 2 + 1) * W].to_vec();
    let column = |a: &[f32]| (0..H).map(|y| a[y * W + W / 2]).collect::<Vec<_>>();
    let (sharp_partial, sharp_centre) = smear(&row(&sharp));
    let (partial, centre) = smear(&row(&blurred));
    // Pixels per metre at the block's front face (SIDE/2 spacings nearer than its centre).
    let front = DISTANCE - (SIDE as f32 / 2.0) * SPACING as f32;
    let px_per_m = H as f32 / (2.0 * front * (FOV_DEG.to_radians() / 2.0).tan());
    let want = SPEED * FRAME_TIME * (1.0 - 1.0 / SLICES as f32) * px_per_m;
    let smeared = partial as f32 / 2.0;
    let (across, _) = smear(&column(&blurred));
    let (sharp_across, _) = smear(&column(&sharp));
    eprintln!(
        "edges smeared {smeared} px (expected {want:.1}, still {sharp_partial}), centre \
         {centre:.2} (still {sharp_centre:.2}), across {across} (still {sharp_across})"
    );
    assert!(sharp_partial <= 4, "the still block's edges are sharp");
    assert!(
        (smeared - want).abs() <= 2.0,
        "each edge smeared over {smeared} px along the motion, expected {want:.1}"
    );
    assert!(
        (centre - sharp_centre).abs() <= 0.75,
        "the streak's centre moved from {sharp_centre} to {centre}"
    );
    assert!(across <= sharp_across + 1, "smeared across the motion");
}
