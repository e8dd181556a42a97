//! What the command line says and where: stdout carries data only, messages go to stderr,
//! `-q` silences progress and summaries but never warnings; a thickness in the wrong unit
//! never gives a silent blank picture; help lists only what a command takes; `--threads`;
//! `convert` writes every part of a frame.

mod cli_support;
use cli_support::{data, filmsplat, tmp};
use std::process::Command;

/// A PLY bubble of 400 particles whose `rh` is in metres (2e-7..4e-7), as a simulator writes.
fn bubble_in_metres() -> String {
    let n = 400;
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n\
         property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float rh\nend_header\n"
    );
    for i in 0..n {
        let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let r = (1.0 - y * y).sqrt();
        let t = i as f64 * 2.399_963;
        let (x, z) = (r * t.cos(), r * t.sin());
        text += &format!("{x} {y} {z} {x} {y} {z} {}\n", 3e-7 + 1e-7 * y);
    }
    let p = tmp("bubble_in_metres.ply");
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// Share of pixels of an RGBA EXR with any coverage.
fn covered(exr: &std::path::Path) -> f64 {
    let e = filmsplat::image::read_exr(exr).unwrap();
    e.rgba.iter().filter(|p| p[3] > 0.0).count() as f64 / e.rgba.len() as f64
}

#[test]
fn a_thickness_in_metres_is_refused_with_the_fix_not_rendered_blank() {
    let ply = bubble_in_metres();
    let png = tmp("metres.png");
    let _ = std::fs::remove_file(&png);
    let base = [
        "render",
        &ply,
        "-o",
        png.to_str().unwrap(),
        "--size",
        "48x32",
    ];
    for quiet in [false, true] {
        let mut args = base.to_vec();
        if quiet {
            args.push("-q");
        }
        let (code, out, err) = filmsplat(&args);
        assert_eq!(
            code, 2,
            "quiet {quiet}: refused, not a blank picture: {err}"
        );
        assert!(out.is_empty(), "{out}");
        assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
        assert!(
            err.starts_with("filmsplat: error: ")
                && err.contains("bubble_in_metres.ply")
                && err.contains("add --thickness-unit m"),
            "names the file and the fix: {err}"
        );
        assert!(!png.exists(), "nothing written");
    }
    // The fix works: the film is there.
    let exr = tmp("metres.exr");
    let (code, _, err) = filmsplat(&[
        "render",
        &ply,
        "-o",
        exr.to_str().unwrap(),
        "--size",
        "48x32",
        "--thickness-unit",
        "m",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.is_empty(), "nothing to warn about: {err}");
    assert!(covered(&exr) > 0.3);
    // Naming the unit is the user's call: rendered, with a warning even under -q.
    let (code, out, err) = filmsplat(&[
        "render",
        &ply,
        "-o",
        exr.to_str().unwrap(),
        "--size",
        "48x32",
        "--thickness-unit",
        "nm",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.starts_with("filmsplat: warning:") && err.contains("--thickness-unit m"),
        "{err}"
    );
}

#[test]
fn a_render_to_a_file_prints_nothing_on_stdout_and_logs_each_stage_on_stderr() {
    let png = tmp("quiet-stdout.png");
    let frame = data("thin-film-sph/bursting_bubble/60");
    let args = [
        "render",
        frame.as_str(),
        "-o",
        png.to_str().unwrap(),
        "--size",
        "48x32",
        "--preset",
        "preview",
    ];
    let (code, out, err) = filmsplat(&args);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "stdout is for data: {out}");
    // stderr is not a terminal here: a line per stage of a second or more (none on this small
    // frame), then the summary with every stage's time.
    assert!(!err.contains("read 2,562 particles ("), "{err}");
    let summary = err.lines().last().unwrap();
    for time in ["load ", "estimate ", "build ", "render 48x32"] {
        assert!(summary.contains(time), "{time}: {summary}");
    }
    // -q: nothing at all (no warning is due).
    let mut quiet = args.to_vec();
    quiet.push("-q");
    let (code, out, err) = filmsplat(&quiet);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty() && err.is_empty(), "{out} / {err}");
    // Other commands that write files talk on stderr too.
    let ply = tmp("msg-sample.ply");
    let (code, out, err) = filmsplat(&[
        "sample",
        "bubble",
        "-o",
        ply.to_str().unwrap(),
        "--particles",
        "500",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.is_empty() && err.contains("wrote 500 particles"),
        "{out} / {err}"
    );
    let chart = tmp("msg-chart.png");
    let (code, out, err) =
        filmsplat(&["chart", "-o", chart.to_str().unwrap(), "--size", "400x300"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty() && err.contains("wrote"), "{out} / {err}");
    // Data still goes to stdout.
    let (code, out, _) = filmsplat(&["info", ply.to_str().unwrap()]);
    assert!(code == 0 && out.contains("500"), "{out}");
}

#[test]
fn convert_writes_the_droplets_too_and_says_where() {
    let frame = data("thin-film-sph/bursting_bubble/60");
    let ply = tmp("f60.ply");
    let drops = tmp("f60.droplets.ply");
    let _ = std::fs::remove_file(&drops);
    let (code, out, err) = filmsplat(&["convert", &frame, "-o", ply.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("wrote 1770 particles") && err.contains("wrote 792 droplets"),
        "{err}"
    );
    assert!(err.contains("f60.droplets.ply"), "{err}");
    let opts = filmsplat::io::ReadOptions::default();
    let film = filmsplat::io::read_cloud(&ply, &opts).unwrap();
    let d = filmsplat::io::read_cloud(&drops, &opts).unwrap();
    // Every particle of the frame, none dropped: 1,770 + 792 = 2,562.
    assert_eq!(film.len() + d.len(), 2562);
    assert_eq!(d.len(), 792);
    let r = d.radius.as_ref().expect("droplet radii written");
    assert!(r.iter().all(|r| *r > 0.0 && *r < 1e-3), "{:?}", &r[..3]);
}

#[test]
fn help_lists_only_what_each_command_takes() {
    let (code, view, _) = filmsplat(&["view", "--help"]);
    assert_eq!(code, 0);
    for flag in [
        "--output",
        "--exr",
        "--shard",
        "--resume",
        "--keep-going",
        "--frame-all",
    ] {
        let listed = |help: &str| {
            help.lines().any(|l| {
                let l = l.trim_start();
                l.starts_with(flag) || l.starts_with(&format!("-o, {flag}"))
            })
        };
        assert!(!listed(&view), "view --help offers {flag}");
    }
    assert!(view.contains("--primitive") && view.contains("--port"));
    let (_, compare, _) = filmsplat(&["compare", "--help"]);
    assert!(
        !compare.contains("--view"),
        "compare has no --view, so no --view-range"
    );
    let (_, render, _) = filmsplat(&["render", "--help"]);
    let first = render.lines().next().unwrap();
    assert!(
        first.contains("VTK") && first.contains("frame folders"),
        "{first}"
    );
    for flag in [
        "--output",
        "--shard",
        "--frame-all",
        "--threads",
        "FILMSPLAT_THREADS",
    ] {
        assert!(render.contains(flag), "render --help lacks {flag}");
    }
    // A bad flag value is the flag's error, even over a scene file.
    let scene = format!("{}/samples/bubble.toml", env!("CARGO_MANIFEST_DIR"));
    for (flag, value) in [
        ("--primitive", "disks"),
        ("--shading", "fast"),
        ("--tonemap", "aces"),
    ] {
        let (code, out, err) = filmsplat(&["render", &scene, flag, value, "-o", "x.png"]);
        assert_eq!(code, 2);
        assert!(out.is_empty());
        assert!(
            err.contains(flag) && err.contains(value) && !err.contains("line "),
            "{flag}: {err}"
        );
        assert!(
            !err.contains("film.primitive") && !err.contains("render."),
            "{err}"
        );
    }
    // view refuses render's output flags without talking about its save button.
    let (code, _, err) = filmsplat(&["view", &scene, "--shard", "0/2"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--shard") && err.contains("filmsplat render"),
        "{err}"
    );
}

#[test]
fn threads_come_from_the_flag_or_the_environment_and_bad_counts_are_refused() {
    let png = tmp("threads.png");
    let scene = format!("{}/samples/bubble.toml", env!("CARGO_MANIFEST_DIR"));
    let render = |extra: &[&str], env: Option<&str>| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_filmsplat"));
        c.args([
            "render",
            &scene,
            "-o",
            png.to_str().unwrap(),
            "--size",
            "32x24",
            "--spp",
            "1",
            "-q",
        ]);
        c.args(extra);
        match env {
            Some(v) => c.env("FILMSPLAT_THREADS", v),
            None => c.env_remove("FILMSPLAT_THREADS"),
        };
        let o = c.output().unwrap();
        (
            o.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, err) = render(&["--threads", "1"], None);
    assert_eq!(code, 0, "{err}");
    let one = std::fs::read(&png).unwrap();
    let (code, err) = render(&[], Some("2"));
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        one,
        std::fs::read(&png).unwrap(),
        "same picture on any thread count"
    );
    for (flag, env, names) in [
        (vec!["--threads", "0"], None, "--threads"),
        (vec![], Some("many"), "FILMSPLAT_THREADS"),
    ] {
        let (code, err) = render(&flag, env);
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(names), "{err}");
    }
}
