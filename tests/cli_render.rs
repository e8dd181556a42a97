//! The render, info, sample and chart subcommands end to end, and their error paths: every bad
//! input gives one line naming the problem, exit code 2, and no output file.

mod cli_support;
use cli_support::{data, filmsplat, tmp};

use std::path::Path;

fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn sample_then_render_as_disks_and_spheres_and_exr() {
    let ply = tmp("bubble.ply");
    let (code, out, err) = filmsplat(&[
        "sample",
        "bubble",
        "-o",
        ply.to_str().unwrap(),
        "--particles",
        "3000",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "stdout is for data: {out}");
    assert!(err.contains("3000 particles"), "{err}");
    let (code, out, err) = filmsplat(&["info", ply.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("3000") && out.contains("thickness"), "{out}");
    for prim in ["disk", "sphere", "mls"] {
        let png = tmp(&format!("bubble-{prim}.png"));
        let exr = tmp(&format!("bubble-{prim}.exr"));
        let (code, out, err) = filmsplat(&[
            "render",
            ply.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--exr",
            exr.to_str().unwrap(),
            "--primitive",
            prim,
            "--size",
            "64x48",
            "--spp",
            "2",
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(out.is_empty(), "stdout is for data: {out}");
        assert!(err.contains("3000 particles"), "{err}");
        assert_eq!(png_size(&png), (64, 48));
        let layers = filmsplat::image::read_exr(&exr).unwrap();
        assert_eq!((layers.width, layers.height), (64, 48));
        let covered = layers.rgba.iter().filter(|p| p[3] > 0.0).count();
        assert!(
            covered > 64 * 48 / 4,
            "{prim}: the bubble should fill the frame ({covered})"
        );
        assert!(layers.rgba.iter().flatten().all(|v| v.is_finite()));
        let thickness = layers.thickness.as_ref().unwrap();
        assert!(
            thickness
                .iter()
                .all(|t| t.is_finite() && *t >= 0.0 && *t < 1500.0)
        );
    }
}

/// Coverage, centroid (x, y) and mean linear RGB of a render (see [`exr_stats`]).
type Stats = (f64, [f64; 2], [f64; 3]);

/// What an EXR render shows: the fraction of pixels the film covers (alpha > 0.5), the centroid
/// of those pixels (x, y as fractions of the width and height), and the mean linear RGB over
/// the whole image.
fn exr_stats(path: &Path) -> Stats {
    let l = filmsplat::image::read_exr(path).unwrap();
    let (mut n, mut cx, mut cy, mut mean) = (0.0, 0.0, 0.0, [0.0; 3]);
    for (i, p) in l.rgba.iter().enumerate() {
        if p[3] > 0.5 {
            n += 1.0;
            cx += ((i % l.width) as f64 + 0.5) / l.width as f64;
            cy += ((i / l.width) as f64 + 0.5) / l.height as f64;
        }
        for c in 0..3 {
            mean[c] += p[c] as f64 / l.rgba.len() as f64;
        }
    }
    (n / l.rgba.len() as f64, [cx / n, cy / n], mean)
}

/// Checks `stats` against the values recorded from this render (coverage within 0.015,
/// centroid within 0.02 of the frame, each mean channel within 3 % + 0.001).
fn assert_stats(what: &str, got: Stats, want: Stats) {
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
    let ok = close(got.0, want.0, 0.015)
        && (0..2).all(|i| close(got.1[i], want.1[i], 0.02))
        && (0..3).all(|i| close(got.2[i], want.2[i], 0.03 * want.2[i] + 0.001));
    assert!(ok, "{what}: got {got:?}, recorded {want:?}");
}

#[test]
fn real_sph_files_render() {
    // Shared data from SPlisHSPlasH and splashsurf (see tests/data/ATTRIBUTION.md): no normals,
    // no thickness; normals are estimated, thickness is the default. Each render's coverage,
    // centroid and mean colour are those recorded from it (a regression in reading, estimating,
    // framing or shading moves them; the mean colours were recorded again when the default
    // studio became a dark ground under a diffuse dome, and the dam break's disks once the radius
    // fit stopped splats at the edges of its sparse splashes; its MLS once the MLS supports at
    // open edges stayed within half a rim spacing: coverage 0.111 -> 0.103; and again, all
    // brighter with coverage and centroids unchanged, when the studio's dark ground shrank to
    // the picture's frustum and the rims came to reflect the dome beside it; the dam break's
    // disks again when an inner cut's corner between its cut edges stopped bounding its
    // radius: coverage 0.113 -> 0.116, green 0.068 -> 0.065).
    let recorded: [(&str, &str, Stats); 6] = [
        (
            "splishsplash_sphere_shell.ply",
            "disk",
            (0.488, [0.500, 0.499], [0.2022, 0.1666, 0.1560]),
        ),
        (
            "splishsplash_sphere_shell.ply",
            "sphere",
            (0.519, [0.501, 0.500], [0.3928, 0.3491, 0.3786]),
        ),
        (
            "splishsplash_sphere_shell.ply",
            "mls",
            (0.485, [0.499, 0.499], [0.2042, 0.1676, 0.1555]),
        ),
        (
            "double_dam_break_frame_26.ply",
            "disk",
            (0.116, [0.498, 0.609], [0.1097, 0.0651, 0.0385]),
        ),
        (
            "double_dam_break_frame_26.ply",
            "sphere",
            (0.116, [0.490, 0.612], [0.0555, 0.0474, 0.0484]),
        ),
        (
            "double_dam_break_frame_26.ply",
            "mls",
            (0.103, [0.495, 0.588], [0.0934, 0.0572, 0.0299]),
        ),
    ];
    for (file, prim, want) in recorded {
        let png = tmp(&format!("{file}-{prim}.png"));
        let exr = tmp(&format!("{file}-{prim}.exr"));
        let (code, _, err) = filmsplat(&[
            "render",
            &data(file),
            "-o",
            png.to_str().unwrap(),
            "--exr",
            exr.to_str().unwrap(),
            "--primitive",
            prim,
            "--size",
            "64x48",
            "--spp",
            "1",
        ]);
        assert_eq!(code, 0, "{file} {prim}: {err}");
        assert_eq!(png_size(&png), (64, 48));
        let got = exr_stats(&exr);
        assert_stats(&format!("{file} {prim}"), got, want);
    }
}

/// Mean of a PNG's pixels (sRGB-encoded values as read, 0..1).
fn png_mean(path: &Path) -> f64 {
    let img = filmsplat::image::read_png(path).unwrap();
    let sum: f64 = img.data.iter().flatten().map(|v| *v as f64).sum();
    sum / (3 * img.data.len()) as f64
}

#[test]
fn scene_files_render_and_flags_override_them() {
    let scene = tmp("scene.toml");
    std::fs::write(
        &scene,
        "[input]\nsample = \"bubble\"\nparticles = 2000\n[render]\nwidth = 40\nheight = 30\nspp = 1\n[output]\npath = \"from-scene.png\"\nexposure = 1.0\n",
    )
    .unwrap();
    let (code, _, err) = filmsplat(&["render", scene.to_str().unwrap(), "-q"]);
    assert_eq!(code, 0, "{err}");
    let from_scene = scene.with_file_name("from-scene.png");
    assert_eq!(png_size(&from_scene), (40, 30));
    let out = tmp("override.png");
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "20x10",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(png_size(&out), (20, 10));
    // A flag wins over its key: --exposure -2 instead of the file's +1 darkens the image
    // (three stops: well below half the mean through the tone curve).
    let dark = tmp("override-dark.png");
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dark.to_str().unwrap(),
        "--exposure",
        "-2",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let (bright, dim) = (png_mean(&from_scene), png_mean(&dark));
    assert!(dim < 0.6 * bright && dim > 0.0, "{dim} vs {bright}");
}

#[test]
fn the_chart_is_written() {
    let png = tmp("chart.png");
    let (code, _, err) = filmsplat(&[
        "chart",
        "-o",
        png.to_str().unwrap(),
        "--size",
        "400x300",
        "--max-thickness",
        "800",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(png_size(&png), (400, 300));
    // The chart's colours as recorded: its mean and how colourful it is (mean spread between
    // a pixel's largest and smallest channel), each within 10 %.
    let img = filmsplat::image::read_png(&png).unwrap();
    let n = img.data.len() as f64;
    let spread = img
        .data
        .iter()
        .map(|p| {
            (p.iter().fold(0.0f32, |a, b| a.max(*b)) - p.iter().fold(1.0f32, |a, b| a.min(*b)))
                as f64
        })
        .sum::<f64>()
        / n;
    let (mean, want_mean, want_spread) = (png_mean(&png), 0.670, 0.278);
    assert!(
        (mean - want_mean).abs() <= 0.1 * want_mean
            && (spread - want_spread).abs() <= 0.1 * want_spread,
        "chart mean {mean} (recorded {want_mean}), spread {spread} (recorded {want_spread})"
    );
}

fn write(name: &str, bytes: &[u8]) -> String {
    let p = tmp(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn bad_input_gives_one_line_exit_2_and_no_output() {
    let ok = data("double_dam_break_frame_26.ply");
    let truncated = {
        let b = std::fs::read(&ok).unwrap();
        write("truncated.ply", &b[..b.len() / 2])
    };
    let absurd = write("absurd.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
    let nan = write("nan.ply", b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\nnan 1 1\n");
    let negative = write(
        "negative.ply",
        b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float rh\nend_header\n0 0 0 100\n1 0 0 -5\n",
    );
    let zero_normal = write(
        "zero-normal.ply",
        b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 0\n",
    );
    let bad_scene = write(
        "bad.toml",
        b"[input]\nsample = \"bubble\"\n[render]\nspps = 3\n",
    );
    let missing = tmp("does-not-exist.ply");
    let missing = missing.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["render", missing], "does-not-exist.ply"),
        (vec!["render", &truncated], "truncated.ply"),
        (vec!["render", &absurd], "absurd.ply"),
        (
            vec!["render", &nan],
            "nan.ply: 1 particle has non-finite positions",
        ),
        (
            vec!["render", &negative],
            "negative.ply: 1 particle has negative thickness",
        ),
        (
            vec!["render", &zero_normal],
            "zero-normal.ply: 1 particle has zero-length normals",
        ),
        (vec!["render", &bad_scene], "spps"),
        (vec!["render", &ok, "--spp", "0"], "spp"),
        (vec!["render", &ok, "--size", "0x10"], "size"),
        (vec!["render", &ok, "--primitive", "cube"], "cube"),
        (vec!["render", &ok, "--shading", "magic"], "magic"),
        (vec!["render", &ok, "--ior", "0.5"], "ior"),
        (vec!["render", &ok, "--roulette", "1.5"], "roulette"),
        (vec!["render", &ok, "--roulette", "NaN"], "roulette"),
        (
            vec!["render", &ok, "--thickness-unit", "furlong"],
            "furlong",
        ),
        (
            vec!["render", &ok, "--wavelengths", "0", "--shading", "rgb"],
            "wavelengths",
        ),
        (
            vec!["render", &ok, "--env", "/nonexistent/env.exr"],
            "env.exr",
        ),
        (vec!["info", missing], "does-not-exist.ply"),
        (vec!["info", &truncated], "truncated.ply"),
        (vec!["sample", "bubble", "--particles", "0"], "particles"),
    ];
    for (args, needle) in cases {
        let out_png = tmp("should-not-exist.png");
        let _ = std::fs::remove_file(&out_png);
        let mut full = args.clone();
        if args[0] == "render" {
            full.extend(
                ["-o", out_png.to_str().unwrap(), "--size", "16x16"]
                    .iter()
                    .filter(|_| !args.contains(&"--size")),
            );
            if args.contains(&"--size") {
                full.extend(["-o", out_png.to_str().unwrap()]);
            }
        }
        if args[0] == "sample" {
            full.extend(["-o", out_png.to_str().unwrap()]);
        }
        let (code, _, err) = filmsplat(&full);
        assert_eq!(code, 2, "{full:?}: exit {code}, stderr: {err}");
        assert!(!err.contains("panicked"), "{full:?}: {err}");
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "{full:?}: one line expected, got: {err}");
        assert!(lines[0].starts_with("filmsplat: error:"), "{full:?}: {err}");
        assert!(
            lines[0].contains(needle),
            "{full:?}: '{needle}' not in: {err}"
        );
        assert!(!out_png.exists(), "{full:?} left an output file");
    }
}

#[test]
fn a_latlong_environment_map_lights_the_scene() {
    // A uniform grey panorama: background pixels are the map's value, and a film in it keeps
    // energy (film pixels equal the same grey).
    let env = tmp("grey.exr");
    let layers = filmsplat::image::ExrLayers::rgba(8, 4, vec![[0.25, 0.5, 0.75, 1.0]; 32]);
    filmsplat::image::write_exr(&env, &layers).unwrap();
    let out = tmp("env-render.exr");
    let (code, _, err) = filmsplat(&[
        "render",
        &data("splishsplash_sphere_shell.ply"),
        "-o",
        out.to_str().unwrap(),
        "--env",
        env.to_str().unwrap(),
        "--env-intensity",
        "2",
        "--size",
        "32x24",
        "--spp",
        "1",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let img = filmsplat::image::read_exr(&out).unwrap();
    let mut film = 0;
    for p in &img.rgba {
        for (c, want) in [0.5, 1.0, 1.5].iter().enumerate() {
            assert!((p[c] - want).abs() < 2e-3, "{p:?}");
        }
        film += (p[3] > 0.0) as usize;
    }
    assert!(film > 100, "the shell should be in view ({film})");
}

#[test]
fn scientific_views_render_with_colour_bars() {
    let shell = data("splishsplash_sphere_shell.ply");
    for view in ["thickness", "normal", "depth", "particle-id", "coverage"] {
        // The bar goes inside the requested size, wide, tiny or portrait, PNG or EXR.
        for size in ["64x48", "320x180", "90x160"] {
            let png = tmp(&format!("view-{view}-{size}.png"));
            let exr = tmp(&format!("view-{view}-{size}.exr"));
            let (code, out, err) = filmsplat(&[
                "render",
                &shell,
                "--view",
                view,
                "-o",
                png.to_str().unwrap(),
                "--exr",
                exr.to_str().unwrap(),
                "--size",
                size,
            ]);
            assert_eq!(code, 0, "{view}: {err}");
            assert!(out.is_empty() && err.contains(view), "{out} / {err}");
            let (w, h) = size.split_once('x').unwrap();
            let want = (w.parse().unwrap(), h.parse().unwrap());
            assert_eq!(png_size(&png), want, "{view} PNG at {size}");
            let e = filmsplat::image::read_exr(&exr).unwrap();
            assert_eq!(
                (e.width as u32, e.height as u32),
                want,
                "{view} EXR at {size}"
            );
        }
    }
    let (code, _, err) = filmsplat(&[
        "render",
        &shell,
        "--view",
        "xray",
        "-o",
        tmp("x.png").to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("xray"), "{err}");
}

#[test]
fn repair_drops_or_fixes_bad_particles_and_says_so() {
    let ply = write(
        "repairable.ply",
        b"ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float rh\nend_header\n\
0 0 0 0 0 1 300\n0.1 0 0 0 0 1 300\nnan 0 0 0 0 1 300\n0 0.1 0 0 0 0 300\n0.1 0.1 0 0 0 1 -4\n",
    );
    let png = tmp("repaired.png");
    let (code, _, err) = filmsplat(&[
        "render",
        &ply,
        "-o",
        png.to_str().unwrap(),
        "--size",
        "16x16",
    ]);
    assert_eq!(code, 2, "refused without --repair: {err}");
    let (code, out, err) = filmsplat(&[
        "render",
        &ply,
        "-o",
        png.to_str().unwrap(),
        "--size",
        "16x16",
        "--repair",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(err.contains("dropped 1 with non-finite positions"), "{err}");
    assert!(err.contains("dropped 1 with bad thickness"), "{err}");
    assert!(err.contains("3 particles"), "{err}");
    assert_eq!(png_size(&png), (16, 16));
}

#[test]
fn convert_writes_what_was_read() {
    let ply = tmp("converted.ply");
    let (code, out, err) = filmsplat(&[
        "convert",
        &data("fluid_250_particles.vtu"),
        "-o",
        ply.to_str().unwrap(),
        "--keep",
        "density,pressure",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty() && err.contains("250 particles"), "{err}");
    let original = filmsplat::io::read_cloud(
        Path::new(&data("fluid_250_particles.vtu")),
        &Default::default(),
    )
    .unwrap();
    let back = filmsplat::io::read_cloud(&ply, &Default::default()).unwrap();
    assert_eq!(back.positions, original.positions);
    let mut names: Vec<&str> = back.extra.iter().map(|(n, _)| n.as_str()).collect();
    names.sort();
    assert_eq!(names, ["density", "pressure"]);
    assert_eq!(back.extra("density"), original.extra("density"));
    let (code, _, err) = filmsplat(&[
        "convert",
        &data("fluid_250_particles.vtu"),
        "-o",
        tmp("x.ply").to_str().unwrap(),
        "--keep",
        "bogus",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bogus") && err.contains("fluid_250_particles.vtu"),
        "{err}"
    );
    let (code, _, err) = filmsplat(&[
        "render",
        &data("fluid_250_particles.vtu"),
        "--normal-attr",
        "nope",
        "-o",
        tmp("y.png").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "an explicitly named attribute must exist: {err}");
}

#[test]
fn sequences_shard_resume_and_keep_going() {
    let dir = tmp("seq");
    std::fs::create_dir_all(&dir).unwrap();
    for (f, t) in [(0, "0"), (1, "0.5"), (2, "1"), (3, "1.5")] {
        let ply = dir.join(format!("frame_{f:04}.ply"));
        let (code, _, err) = filmsplat(&[
            "sample",
            "bubble",
            "-o",
            ply.to_str().unwrap(),
            "--particles",
            "1500",
            "--time",
            t,
        ]);
        assert_eq!(code, 0, "{err}");
    }
    let input = dir.join("frame_{:04}.ply");
    let render = |out: &str, extra: &[&str]| {
        let o = dir.join(out);
        let mut args = vec![
            "render",
            input.to_str().unwrap(),
            "-o",
            o.to_str().unwrap(),
            "--size",
            "24x16",
            "--spp",
            "1",
        ];
        args.extend_from_slice(extra);
        filmsplat(&args)
    };
    let (code, out, err) = render("all_{:02}.png", &["--frames", "0..4"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty() && err.contains("frame 3"), "{err}");
    for k in ["0/2", "1/2"] {
        let (code, _, err) = render("shard_{:02}.png", &["--frames", "0..=3", "--shard", k]);
        assert_eq!(code, 0, "{err}");
    }
    for f in 0..4 {
        let a = std::fs::read(dir.join(format!("all_{f:02}.png"))).unwrap();
        let b = std::fs::read(dir.join(format!("shard_{f:02}.png"))).unwrap();
        assert_eq!(
            a, b,
            "frame {f}: sharded output must equal the unsharded one bit for bit"
        );
    }
    assert_ne!(
        std::fs::read(dir.join("all_00.png")).unwrap(),
        std::fs::read(dir.join("all_03.png")).unwrap()
    );
    // --resume skips what exists.
    std::fs::remove_file(dir.join("all_02.png")).unwrap();
    let (code, out, err) = render("all_{:02}.png", &["--frames", "0..4", "--resume"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "{out}");
    assert_eq!(err.matches("skipped").count(), 3, "{err}");
    assert!(dir.join("all_02.png").exists());
    // A missing frame: stops without --keep-going, the others still render with it.
    std::fs::remove_file(dir.join("frame_0001.ply")).unwrap();
    let (code, _, err) = render("kg_{:02}.png", &["--frames", "0..4"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("frame 1") && err.contains("frame_0001.ply"),
        "{err}"
    );
    let (code, _, err) = render("kg_{:02}.png", &["--frames", "0..4", "--keep-going"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("1 of 4 frames failed"), "{err}");
    assert!(dir.join("kg_03.png").exists() && !dir.join("kg_01.png").exists());
    // Patterns are required.
    let (code, _, err) = render("no_pattern.png", &["--frames", "0..2"]);
    assert_eq!(code, 2);
    assert!(err.contains("frame pattern"), "{err}");
}

#[test]
fn frame_folders_of_the_thin_film_code_render_as_a_sequence() {
    // The research code's layout: u32 count, then f64 values; thickness in metres.
    let n = 800u32;
    for frame in [3u64, 4] {
        let dir = tmp(&format!("ff/frame_{frame:04}"));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |name: &str, vals: &[f64]| {
            let mut b = n.to_le_bytes().to_vec();
            vals.iter()
                .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
            std::fs::write(dir.join(name), b).unwrap();
        };
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let (mut x, mut rh) = (Vec::new(), Vec::new());
        for i in 0..n {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let a = golden * i as f64;
            x.extend([r * a.cos(), y, r * a.sin()]);
            rh.push((200.0 + 100.0 * frame as f64) * 1e-9);
        }
        write("x_bin", &x);
        write("norm_bin", &x);
        write("rh_bin", &rh);
    }
    let pattern = tmp("ff").join("frame_{:04}");
    let out = tmp("ff").join("img_{:04}.exr");
    let (code, _, err) = filmsplat(&[
        "render",
        pattern.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--frames",
        "3..=4",
        "--size",
        "32x24",
        "--spp",
        "1",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    for (frame, want) in [(3, 500.0), (4, 600.0)] {
        let img =
            filmsplat::image::read_exr(&tmp("ff").join(format!("img_{frame:04}.exr"))).unwrap();
        let t: Vec<f32> = img
            .thickness
            .unwrap()
            .into_iter()
            .filter(|t| *t > 0.0)
            .collect();
        assert!(!t.is_empty());
        assert!(
            t.iter().all(|v| (v - want).abs() < 1.0),
            "frame {frame}: metres become nm"
        );
    }
}

/// `info` and the render's notes say whether the radius fit runs: a clean sample bubble keeps
/// its radii (the fit run on every particle changes none), a half bubble's open rim is
/// fitted; `--fit-radii always` fits the bubble anyway, `--raw-radii` never fits.
#[test]
fn info_and_render_say_whether_the_radii_are_fitted() {
    let mut files = Vec::new();
    for name in ["bubble", "half-bubble"] {
        let ply = tmp(&format!("fit-screen-{name}.ply"));
        let p = ply.to_str().unwrap().to_string();
        let (code, _, err) = filmsplat(&["sample", name, "-o", &p, "--particles", "3000"]);
        assert_eq!(code, 0, "{err}");
        files.push(p);
    }
    let (_, out, _) = filmsplat(&["info", &files[0]]);
    assert!(out.contains("radii kept as read"), "{out}");
    let (_, out, _) = filmsplat(&["info", &files[1]]);
    assert!(
        out.contains("radii fitted: the radius fit would change"),
        "{out}"
    );
    let png = tmp("fit-screen.png");
    let render = |extra: &[&str]| {
        let mut args = vec!["render", &files[0], "-o", png.to_str().unwrap()];
        args.extend(["--size", "32x24", "--spp", "1"]);
        args.extend(extra);
        let (code, _, err) = filmsplat(&args);
        assert_eq!(code, 0, "{err}");
        err
    };
    let fitted = "splat radii fitted to the sampling";
    let err = render(&[]);
    assert!(
        err.contains("radii kept as read") && !err.contains(fitted),
        "{err}"
    );
    let err = render(&["--fit-radii", "always"]);
    assert!(
        !err.contains("radii kept as read") && err.contains(fitted),
        "{err}"
    );
    for never in [&["--raw-radii"][..], &["--fit-radii", "never"]] {
        let err = render(never);
        assert!(
            !err.contains("radii kept") && !err.contains(fitted),
            "{err}"
        );
    }
    let (code, _, err) = filmsplat(&["render", &files[0], "--fit-radii", "sometimes"]);
    assert_eq!(code, 2, "{err}");
}

/// The screen judges a large cloud on every 32nd particle: a film whose other particles are too
/// small to meet (here a cap of a 40,000-particle bubble, every particle but the sampled ones
/// shrunk to 0.3 of its radius) keeps its radii, the render finds the pinholes, and says so —
/// with `-q` too — naming the way out; `--fit-radii always` closes them, without the warning.
#[test]
fn pinholes_left_by_a_skipped_fit_are_warned_of() {
    use filmsplat::samples::{SampleKind, SampleParams};
    let p = SampleParams {
        particles: 40_000,
        ..SampleParams::default()
    };
    let mut cloud = SampleKind::from_name("bubble").unwrap().generate(&p);
    let top = cloud.positions.iter().map(|x| x.y).fold(f32::MIN, f32::max);
    let radii = cloud.radius.as_mut().unwrap();
    for (i, (r, x)) in radii.iter_mut().zip(&cloud.positions).enumerate() {
        if i % 32 != 0 && x.y > 0.5 * top {
            *r *= 0.3;
        }
    }
    let ply = tmp("screened-cap.ply");
    filmsplat::io::write_ply(&ply, &cloud).unwrap();
    let png = tmp("screened-cap.png");
    let render = |extra: &[&str]| {
        let mut args = vec!["render", ply.to_str().unwrap(), "-o", png.to_str().unwrap()];
        args.extend(["--size", "96x72", "--spp", "1", "-q", "--camera", "0,3,0.5"]);
        args.extend(["--look-at", "0,0,0"]);
        args.extend(extra);
        let (code, _, err) = filmsplat(&args);
        assert_eq!(code, 0, "{err}");
        err
    };
    let err = render(&[]);
    assert!(
        err.contains("warning: pinholes at") && err.contains("--fit-radii always"),
        "{err}"
    );
    let err = render(&["--fit-radii", "always"]);
    assert!(!err.contains("warning: pinholes"), "{err}");
}
