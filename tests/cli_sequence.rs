//! One camera per sequence: `render --frames` auto-frames once (on the first frame of the whole
//! list, or on every frame's bounds with --frame-all), so a moving cloud moves in the picture,
//! sharded jobs agree on the camera, and the printed `[camera]` lines reproduce it.

mod cli_support;
use cli_support::{disk_ply_header, filmsplat, tmp};

use filmsplat::scene::SceneDesc;
use glam::Vec3;
use std::path::{Path, PathBuf};

const W: usize = 64;
const H: usize = 48;

/// A flat square film, 1 × 1 in the z = 0 plane centred on `centre`, as an ASCII PLY of 12 × 12
/// particles with normals and radii (so nothing is estimated).
fn square(path: &Path, centre: Vec3) {
    let n = 12;
    let mut s = disk_ply_header(n * n);
    for i in 0..n {
        for j in 0..n {
            let p = centre
                + Vec3::new(
                    i as f32 / (n - 1) as f32 - 0.5,
                    j as f32 / (n - 1) as f32 - 0.5,
                    0.0,
                );
            s += &format!("{} {} {} 0 0 1 0.09 400\n", p.x, p.y, p.z);
        }
    }
    std::fs::write(path, s).unwrap();
}

/// Two frames of a square moving by `step` between them, in a fresh folder.
fn moving(name: &str, step: Vec3) -> PathBuf {
    let dir = tmp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    square(&dir.join("frame_0000.ply"), Vec3::ZERO);
    square(&dir.join("frame_0001.ply"), step);
    dir
}

fn render(dir: &Path, out: &str, extra: &[&str]) -> (i32, String, String) {
    let input = dir.join("frame_{:04}.ply");
    let o = dir.join(out);
    let mut args = vec![
        "render",
        input.to_str().unwrap(),
        "-o",
        o.to_str().unwrap(),
        "--size",
        "64x48",
        "--spp",
        "1",
        "--frames",
        "0..2",
        // The oracle traces the file's disks as they are.
        "--raw-radii",
    ];
    args.extend_from_slice(extra);
    filmsplat(&args)
}

/// The `[camera]` block the sequence printed.
fn printed_camera(out: &str) -> filmsplat::scene::CameraDesc {
    let start = out.find("[camera]").unwrap_or_else(|| panic!("{out}"));
    let block: String = out[start..]
        .lines()
        .take_while(|l| !l.starts_with("frame "))
        .map(|l| format!("{l}\n"))
        .collect();
    SceneDesc::from_toml(&block, "printed").unwrap().camera
}

/// Centroid (pixels, x right, y down) and pixel count of the square film centred on `centre`
/// as the pinhole camera `c` sees it, traced here from the camera's definition (right =
/// forward × up, vertical field of view `fov`): a ray through each pixel centre meets the
/// z = 0 plane inside one of the 12 × 12 disks of radius 0.09.
fn expected(c: &filmsplat::scene::CameraDesc, centre: Vec3) -> (f32, f32, f32) {
    let p = Vec3::from(c.position.unwrap());
    let forward = (Vec3::from(c.look_at.unwrap()) - p).normalize();
    let right = forward.cross(Vec3::from(c.up.unwrap())).normalize();
    let up = right.cross(forward);
    let tan = (0.5 * c.fov.unwrap().to_radians()).tan();
    let aspect = W as f32 / H as f32;
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in 0..H {
        for x in 0..W {
            let u = (2.0 * (x as f32 + 0.5) / W as f32 - 1.0) * tan * aspect;
            let v = (1.0 - 2.0 * (y as f32 + 0.5) / H as f32) * tan;
            let dir = forward + u * right + v * up;
            let hit = p + dir * (-p.z / dir.z) - centre;
            let near = |w: f32| ((w + 0.5) * 11.0).round().clamp(0.0, 11.0) / 11.0 - 0.5;
            let d = hit - Vec3::new(near(hit.x), near(hit.y), 0.0);
            if d.length() < 0.09 {
                sx += x as f32 + 0.5;
                sy += y as f32 + 0.5;
                n += 1.0;
            }
        }
    }
    (sx / n, sy / n, n)
}

/// Centroid of the film's coverage (the EXR's alpha), pixels, and the covered pixel count.
fn centroid(path: &Path) -> (f32, f32, f32) {
    let img = filmsplat::image::read_exr(path).unwrap();
    assert_eq!((img.width, img.height), (W, H));
    let (mut sx, mut sy, mut sa) = (0.0, 0.0, 0.0);
    for (k, px) in img.rgba.iter().enumerate() {
        let a = px[3];
        sx += a * ((k % W) as f32 + 0.5);
        sy += a * ((k / W) as f32 + 0.5);
        sa += a;
    }
    assert!(
        sa > 50.0,
        "{}: the film should be in view ({sa})",
        path.display()
    );
    (sx / sa, sy / sa, sa)
}

/// True if any pixel on the image's border is covered by film.
fn touches_border(path: &Path) -> bool {
    let img = filmsplat::image::read_exr(path).unwrap();
    img.rgba.iter().enumerate().any(|(k, px)| {
        let (x, y) = (k % W, k / W);
        px[3] > 0.0 && (x == 0 || y == 0 || x == W - 1 || y == H - 1)
    })
}

#[test]
fn a_moving_cloud_moves_in_the_picture_from_the_first_frames_camera() {
    let step = Vec3::new(0.3, 0.1, 0.0);
    let dir = moving("seq-move", step);
    let (code, out, err) = render(&dir, "all_{:04}.exr", &[]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "stdout is for data: {out}");
    let out = err;
    assert!(out.contains("auto-framed on frame 0"), "{out}");
    assert_eq!(out.matches("[camera]").count(), 1, "printed once: {out}");
    let cam = printed_camera(&out);
    let centre = Vec3::from(cam.look_at.unwrap());
    assert!(centre.length() < 1e-5, "frame 0's centre: {centre}");
    let c0 = centroid(&dir.join("all_0000.exr"));
    let c1 = centroid(&dir.join("all_0001.exr"));
    for (c, centre) in [(c0, Vec3::ZERO), (c1, step)] {
        let e = expected(&cam, centre);
        assert!(
            (c.0 - e.0).abs() < 0.3 && (c.1 - e.1).abs() < 0.3 && (c.2 - e.2).abs() < 0.05 * e.2,
            "film centroid and area {c:?} should be what the printed camera sees: {e:?}"
        );
    }
    assert!(c1.0 - c0.0 > 5.0, "moved right: {c0:?} -> {c1:?}");
    assert!(c0.1 - c1.1 > 1.0, "moved up: {c0:?} -> {c1:?}");

    // Shards agree without talking: the job that renders only frame 1 frames on frame 0 too.
    for k in ["0/2", "1/2"] {
        let (code, out, err) = render(&dir, "shard_{:04}.exr", &["--shard", k, "-q"]);
        assert_eq!(code, 0, "{err}");
        assert!(
            out.is_empty() && err.is_empty(),
            "-q prints nothing: {out} {err}"
        );
    }
    for f in 0..2 {
        let a = std::fs::read(dir.join(format!("all_{f:04}.exr"))).unwrap();
        let b = std::fs::read(dir.join(format!("shard_{f:04}.exr"))).unwrap();
        assert!(a == b, "frame {f}: sharded and unsharded cameras differ");
    }

    // The printed lines, pasted into a scene file, render the same pictures.
    let block = &out[out.find("[camera]").unwrap()..];
    let block: String = block
        .lines()
        .take_while(|l| !l.starts_with("frame "))
        .map(|l| format!("{l}\n"))
        .collect();
    for f in 0..2u64 {
        let scene = dir.join(format!("pasted_{f}.toml"));
        std::fs::write(
            &scene,
            format!("[input]\ncloud = \"frame_{f:04}.ply\"\n\n{block}"),
        )
        .unwrap();
        let o = dir.join(format!("pasted_{f}.exr"));
        let (code, _, err) = filmsplat(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            o.to_str().unwrap(),
            "--size",
            "64x48",
            "--spp",
            "1",
            "--seed",
            &f.to_string(),
            "--raw-radii",
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(
            std::fs::read(&o).unwrap()
                == std::fs::read(dir.join(format!("all_{f:04}.exr"))).unwrap(),
            "frame {f}: the pasted camera is the sequence's"
        );
    }
}

#[test]
fn frame_all_frames_the_union_and_a_named_camera_wins() {
    // Far enough apart that frame 0's camera would lose frame 1.
    let step = Vec3::new(2.0, 0.0, 0.0);
    let dir = moving("seq-all", step);
    let (code, out, err) = render(&dir, "u_{:04}.exr", &["--frame-all"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "stdout is for data: {out}");
    assert!(err.contains("all 2 frames"), "{err}");
    let cam = printed_camera(&err);
    let centre = Vec3::from(cam.look_at.unwrap());
    assert!(
        (centre - 0.5 * step).length() < 1e-5,
        "the union's centre: {centre}"
    );
    let c0 = centroid(&dir.join("u_0000.exr"));
    let c1 = centroid(&dir.join("u_0001.exr"));
    for (c, centre) in [(c0, Vec3::ZERO), (c1, step)] {
        let e = expected(&cam, centre);
        assert!(
            (c.0 - e.0).abs() < 0.3 && (c.1 - e.1).abs() < 0.3 && (c.2 - e.2).abs() < 0.05 * e.2,
            "{c:?} vs {e:?}"
        );
    }
    for f in 0..2 {
        assert!(
            !touches_border(&dir.join(format!("u_{f:04}.exr"))),
            "frame {f} whole in view"
        );
    }
    // Sharded --frame-all jobs agree too.
    let (code, _, err) = render(&dir, "us_{:04}.exr", &["--frame-all", "--shard", "1/2"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        std::fs::read(dir.join("us_0001.exr")).unwrap()
            == std::fs::read(dir.join("u_0001.exr")).unwrap(),
        "--frame-all shards agree"
    );
    // An explicit camera wins: nothing is auto-framed or printed, the square moves as seen.
    let (code, out, err) = render(
        &dir,
        "e_{:04}.exr",
        &["--camera", "1,0,6", "--look-at", "1,0,0"],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        !out.contains("[camera]") && !err.contains("[camera]"),
        "{out} {err}"
    );
    let (e0, e1) = (
        centroid(&dir.join("e_0000.exr")),
        centroid(&dir.join("e_0001.exr")),
    );
    assert!(e1.0 - e0.0 > 10.0, "{e0:?} {e1:?}");
    // --frame-all without --frames is refused.
    let (code, _, err) = filmsplat(&[
        "render",
        dir.join("frame_0000.ply").to_str().unwrap(),
        "--frame-all",
        "-o",
        dir.join("x.png").to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--frame-all") && err.lines().count() == 1,
        "{err}"
    );
    // A missing first frame is named: the camera cannot be framed without it.
    std::fs::remove_file(dir.join("frame_0000.ply")).unwrap();
    let (code, _, err) = render(&dir, "m_{:04}.exr", &["--shard", "1/2", "--keep-going"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("frame 0") && err.contains("frame_0000.ply") && err.contains("camera"),
        "{err}"
    );
    assert!(!dir.join("m_0001.exr").exists());
}
