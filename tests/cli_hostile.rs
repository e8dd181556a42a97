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
