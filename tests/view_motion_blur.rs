//! `filmsplat view` with an open shutter: the final picture is exactly what `render` makes of
//! the same scene (blurred, not the sharp frame), the one-sample passes of a moving camera
//! stay centred on the frame's position, and bad shutters are refused before serving.

mod cli_support;
mod motion_support;
mod view_support;

use filmsplat::pipeline;
use filmsplat::scene::SceneDesc;
use motion_support::square;
use std::path::{Path, PathBuf};
use view_support::*;

/// The camera of the requests (head-on, 3 units away).
const CAMERA: &str = "pos=0,0,3&look=0,0,0&up=0,1,0&fov=40";

/// A scene of the moving square: `shutter` lines added to `[render]`.
fn scene(ply: &Path, shutter: &str) -> &'static str {
    let toml = format!(
        "[input]\ncloud = \"{}\"\n[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         up = [0.0, 1.0, 0.0]\nfov = 40.0\n[render]\nwidth = 64\nheight = 48\nspp = 16\n{shutter}",
        ply.display()
    );
    Box::leak(toml.into_boxed_str())
}

/// What `filmsplat render` writes for `toml`, decoded.
fn rendered(toml: &str) -> Vec<u8> {
    let mut desc = SceneDesc::from_toml(toml, "oracle.toml").unwrap();
    desc.input.time = Some(0.0);
    let p = pipeline::prepare(&desc, Path::new("."), false).unwrap();
    let path = temp("oracle.png");
    pipeline::write_image(&p.shot, &pipeline::render(&p, &p.shot).unwrap(), &path).unwrap();
    let (_, _, px) = decode(&std::fs::read(&path).unwrap());
    std::fs::remove_file(&path).unwrap();
    px
}

/// The served picture of `pass`, decoded.
fn served(s: &Running, pass: &str) -> Vec<u8> {
    let r = get(
        s.addr,
        &format!("/api/render?{CAMERA}&w=64&h=48&pass={pass}"),
    );
    assert_eq!(r.status, 200, "{}", r.text());
    let (w, h, px) = decode(&r.body);
    assert_eq!((w, h), (64, 48));
    px
}

/// The film's horizontal centre, pixels: in the middle rows (the film's, below the studio's
/// bright top), the columns weighted by how far each pixel differs from its row's left edge
/// (background).
fn centre_x(px: &[u8]) -> f32 {
    let (mut sum, mut total) = (0.0, 0.0);
    for y in 18..30 {
        let row = &px[y * 64 * 3..(y + 1) * 64 * 3];
        for x in 0..64 {
            let d: f32 = (0..3)
                .map(|c| (row[x * 3 + c] as f32 - row[c] as f32).abs())
                .sum();
            sum += x as f32 * d;
            total += d;
        }
    }
    sum / total
}

fn moving_square(name: &str) -> PathBuf {
    let ply = temp(name);
    square(&ply, ["1", "0", "0"]);
    ply
}

#[test]
fn the_final_picture_is_render_s_blur_and_the_quick_passes_stay_centred() {
    let ply = moving_square("view-moving.ply");
    let shutter = "shutter = 1.0\nframe_time = 0.5\nshutter_slices = 8\n";
    let (blur_toml, sharp_toml) = (scene(&ply, shutter), scene(&ply, ""));
    let blurred = start(blur_toml);
    let final_blur = served(&blurred, "final");
    assert!(
        final_blur == rendered(blur_toml),
        "the served blur differs from render's"
    );
    let sharp = start(sharp_toml);
    let final_sharp = served(&sharp, "final");
    assert!(final_blur != final_sharp, "the shutter changed nothing");
    // One sample a pixel: the middle slice, centred where the frame holds the film (the first
    // slice would put it 7/16 of the 0.5 travel, ~3.6 px, to the left).
    let (draft, still) = (served(&blurred, "draft"), served(&sharp, "draft"));
    let (c, c0) = (centre_x(&draft), centre_x(&still));
    eprintln!("draft centre {c:.2}, sharp {c0:.2}");
    assert!((c - c0).abs() < 1.0, "draft centre {c} vs {c0}");
}

#[test]
fn bad_shutters_are_refused_before_serving() {
    let ply = moving_square("view-bad.ply");
    let nan = temp("view-nan.ply");
    square(&nan, ["nan", "0", "0"]);
    let (p, n) = (ply.to_str().unwrap(), nan.to_str().unwrap());
    for (input, flags, needle) in [
        (p, vec!["--shutter", "2", "--frame-time", "0.5"], "0..=1"),
        (p, vec!["--shutter", "0.5"], "--frame-time"),
        (
            p,
            vec!["--shutter", "nan", "--frame-time", "0.5"],
            "--shutter",
        ),
        (
            n,
            vec!["--shutter", "0.5", "--frame-time", "0.5"],
            "particle 0",
        ),
    ] {
        let mut args = vec!["view", input, "--port", "0"];
        args.extend_from_slice(&flags);
        let (code, out, err) = cli_support::filmsplat(&args);
        assert_eq!(code, 2, "{flags:?}: {err}");
        assert!(out.is_empty(), "{flags:?}: {out}");
        assert_eq!(err.trim().lines().count(), 1, "{flags:?}: {err}");
        assert!(err.contains(needle), "{flags:?}: {needle} missing: {err}");
    }
}
