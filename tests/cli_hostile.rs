//! Hostile conditions end to end: renders that would not fit in memory refuse before loading,
//! and an interrupted sequence leaves only complete frames that `--resume` completes.

mod cli_support;
use cli_support::{filmsplat, tmp};

use std::path::Path;

fn sample(path: &Path, particles: &str) {
    let (code, _, err) = filmsplat(&[
        "sample",
        "bubble",
        "-o",
        path.to_str().unwrap(),
        "--particles",
        particles,
    ]);
    assert_eq!(code, 0, "{err}");
}

/// The number after `marker` in `text`, with a binary unit (B, KiB, MiB, GiB), in bytes.
fn bytes_after(text: &str, marker: &str) -> f64 {
    let rest = &text[text
        .find(marker)
        .unwrap_or_else(|| panic!("{marker}: {text}"))
        + marker.len()..];
    let mut it = rest.split_whitespace();
    let v: f64 = it.next().unwrap().parse().unwrap();
    let unit = it.next().unwrap().trim_end_matches([',', ';', ')']);
    v * match unit {
        "B" => 1.0,
        "KiB" => 1024.0,
        "MiB" => 1024.0 * 1024.0,
        "GiB" => 1024.0 * 1024.0 * 1024.0,
        u => panic!("unit {u}"),
    }
}

#[test]
fn info_estimates_peak_memory_and_render_refuses_above_max_memory() {
    let small = tmp("mem_small.ply");
    let big = tmp("mem_big.ply");
    sample(&small, "2000");
    sample(&big, "20000");
    let info = |p: &Path, size: &str| {
        let (code, out, err) = filmsplat(&["info", p.to_str().unwrap(), "--size", size]);
        assert_eq!(code, 0, "{err}");
        assert!(out.contains("estimated peak memory of a"), "{out}");
        bytes_after(&out, "render: ")
    };
    // Particles and pixels both cost: 18 000 more particles add ~258 B each.
    let (s, b) = (info(&small, "64x48"), info(&big, "64x48"));
    let per_particle = (b - s) / 18_000.0;
    assert!((200.0..320.0).contains(&per_particle), "{per_particle}");
    assert!(info(&small, "1920x1080") > s + 1920.0 * 1080.0 * 60.0);

    let out = tmp("mem_refused.png");
    let (code, _, err) = filmsplat(&[
        "render",
        small.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--spp",
        "1",
        "--max-memory",
        "4M",
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.starts_with("filmsplat: error: ")
            && err.contains("mem_small.ply")
            && err.contains("estimated peak memory")
            && err.contains("for 2000 particles")
            && err.contains("exceeds --max-memory 4.0 MiB"),
        "{err}"
    );
    assert!(!out.exists());
    let (code, _, err) = filmsplat(&[
        "render",
        small.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--spp",
        "1",
        "--max-memory",
        "1G",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.exists());

    // A generated sample is refused before it is generated (50 M particles would take GiBs).
    let scene = tmp("mem_huge.toml");
    std::fs::write(
        &scene,
        "[input]\nsample = \"bubble\"\nparticles = 50000000\n",
    )
    .unwrap();
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        tmp("mem_huge.png").to_str().unwrap(),
        "--max-memory",
        "8G",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("for 50000000 particles") && err.contains("exceeds --max-memory 8.0 GiB"),
        "{err}"
    );

    // A header claiming 10^12 vertices in a tiny file: the estimate is capped by the file
    // size, so the reader gets to say what is wrong.
    let liar = tmp("mem_liar.ply");
    std::fs::write(
        &liar,
        "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\n\
         property float y\nproperty float z\nend_header\n0 0 0\n",
    )
    .unwrap();
    let (code, _, err) = filmsplat(&[
        "render",
        liar.to_str().unwrap(),
        "-o",
        tmp("mem_liar.png").to_str().unwrap(),
        "--max-memory",
        "1G",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("mem_liar.ply") && err.contains("PLY"), "{err}");
    assert!(!err.contains("peak memory"), "{err}");

    for bad in ["8X", "0", "G", "1.5Q"] {
        let (code, _, err) = filmsplat(&[
            "render",
            small.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--max-memory",
            bad,
        ]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(err.contains("memory size"), "{err}");
    }
}

/// Every visible file in `dir` is a complete image (PNG decodes, EXR reads); every hidden one
/// is an unfinished `.NAME.tmp-PID-N` of the atomic writer. Returns (images, temporaries).
fn check_outputs(dir: &Path) -> (Vec<String>, Vec<String>) {
    let (mut images, mut temps) = (Vec::new(), Vec::new());
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        let path = dir.join(&name);
        if name.starts_with('.') {
            assert!(name.contains(".tmp-"), "unexpected hidden file {name}");
            temps.push(name);
        } else if name.ends_with(".png") {
            let img = image::open(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!((img.width(), img.height()), (32, 24), "{name}");
            images.push(name);
        } else if name.ends_with(".exr") {
            let layers =
                filmsplat::image::read_exr(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!((layers.width, layers.height), (32, 24), "{name}");
            images.push(name);
        } else {
            panic!("unexpected file {name}");
        }
    }
    images.sort();
    (images, temps)
}

/// Starts a sequence render, waits until `more` new frames exist, then stops it with `stop`.
fn interrupt(
    args: &[String],
    dir: &Path,
    more: usize,
    stop: impl FnOnce(&mut std::process::Child),
) {
    let before = check_outputs(dir).0.len();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_filmsplat"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    loop {
        let done = std::fs::read_dir(dir)
            .unwrap()
            .filter(|e| {
                !e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with('.')
            })
            .count();
        if done >= before + more || start.elapsed().as_secs() > 120 {
            break;
        }
        if child.try_wait().unwrap().is_some() {
            break; // finished before we could interrupt it
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    stop(&mut child);
    let _ = child.wait().unwrap();
}

#[test]
fn an_interrupted_sequence_leaves_whole_frames_and_resume_finishes_it() {
    let dir = tmp("interrupted");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A generated bubble animates with the frame number: no input files needed.
    let scene = tmp("interrupted.toml");
    std::fs::write(&scene, "[input]\nsample = \"bubble\"\nparticles = 1500\n").unwrap();
    const FRAMES: usize = 12;
    let args = |resume: bool| {
        let mut v: Vec<String> = [
            "render",
            scene.to_str().unwrap(),
            "-o",
            dir.join("f_{:03}.png").to_str().unwrap(),
            "--exr",
            dir.join("f_{:03}.exr").to_str().unwrap(),
            "--frames",
            &format!("0..{FRAMES}"),
            "--size",
            "32x24",
            "--spp",
            "1",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        if resume {
            v.push("--resume".into());
        }
        v
    };
    // SIGKILL: no chance to clean up.
    interrupt(&args(false), &dir, 3, |c| c.kill().unwrap());
    let (images, _) = check_outputs(&dir);
    eprintln!("after SIGKILL: {} images", images.len());
    assert!(!images.is_empty());
    // SIGINT (Ctrl-C), as a terminal sends it.
    interrupt(&args(true), &dir, 3, |c| {
        let ok = std::process::Command::new("kill")
            .args(["-INT", &c.id().to_string()])
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            c.kill().unwrap();
        }
    });
    let (images, _) = check_outputs(&dir);
    eprintln!("after SIGINT: {} images", images.len());
    // What a kill during a write leaves: a hidden temporary, never a partial visible file.
    for name in [".f_005.png.tmp-4000000-0", ".f_011.exr.tmp-4000000-1"] {
        std::fs::write(dir.join(name), b"\x89PNG partial").unwrap();
    }
    let (code, out, err) =
        cli_support::filmsplat(&args(true).iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    let (all, temps) = check_outputs(&dir);
    assert_eq!(all.len(), 2 * FRAMES, "{all:?}");
    assert!(temps.is_empty(), "{temps:?}");
    assert!(out.is_empty(), "{out}");
    assert!(err.contains("removed 1 unfinished temporary file"), "{err}");
    // Frames finished before the interruptions (PNG and EXR) were skipped, not rendered again;
    // a frame killed between its PNG and its EXR was rendered again.
    let finished = images
        .iter()
        .filter(|n| n.ends_with(".png") && images.contains(&n.replace(".png", ".exr")))
        .count();
    assert!(finished > 0);
    assert_eq!(
        err.matches("skipped").count(),
        finished,
        "{images:?}\n{err}"
    );
}
