//! `filmsplat sample NAME` for every generator, --sparse, --frames, and their error paths.

mod cli_support;
use cli_support::{filmsplat, tmp};
use filmsplat::io::{ReadOptions, read_cloud};
use filmsplat::samples::SampleKind;

#[test]
fn every_sample_writes_a_readable_cloud() {
    for kind in SampleKind::ALL {
        let out = tmp(&format!("{}.ply", kind.name()));
        let p = out.to_str().unwrap();
        let (code, stdout, err) = filmsplat(&[
            "sample",
            kind.name(),
            "-o",
            p,
            "--particles",
            "600",
            "--time",
            "0.5",
        ]);
        assert_eq!(code, 0, "{}: {err}", kind.name());
        assert!(stdout.is_empty(), "stdout is for data: {stdout}");
        assert!(err.contains("wrote 600 particles"), "{err}");
        let c = read_cloud(&out, &ReadOptions::default()).unwrap();
        assert_eq!(c.len(), 600);
        assert!(c.normals.is_some() && c.thickness_nm.is_some() && c.radius.is_some());
        // The same cloud as the library's generator (thickness written in nm).
        let lib = kind.generate(&filmsplat::samples::SampleParams {
            particles: 600,
            time: 0.5,
            seed: 1,
        });
        assert_eq!(c.positions, lib.positions, "{}", kind.name());
        assert_eq!(c.thickness_nm, lib.thickness_nm, "{}", kind.name());
    }
}

#[test]
fn sparse_keeps_a_fraction_and_frames_write_a_sequence() {
    let out = tmp("sparse.ply");
    let (code, _, err) = filmsplat(&[
        "sample",
        "catenoid",
        "-o",
        out.to_str().unwrap(),
        "--particles",
        "2000",
        "--sparse",
        "0.3",
    ]);
    assert_eq!(code, 0, "{err}");
    let n = read_cloud(&out, &ReadOptions::default()).unwrap().len();
    assert!((500..700).contains(&n), "{n}");

    let dir = tmp("seq");
    std::fs::create_dir_all(&dir).unwrap();
    let pattern = dir.join("f_{:03}.ply");
    let (code, _, err) = filmsplat(&[
        "sample",
        "oscillating-bubble",
        "-o",
        pattern.to_str().unwrap(),
        "--particles",
        "300",
        "--frames",
        "2..5",
    ]);
    assert_eq!(code, 0, "{err}");
    let frames: Vec<_> = (2..5)
        .map(|f| read_cloud(&dir.join(format!("f_{f:03}.ply")), &ReadOptions::default()).unwrap())
        .collect();
    assert!(!dir.join("f_001.ply").exists() && !dir.join("f_005.ply").exists());
    // Frame f is the sample at time f/24 s: the shape moves between frames.
    assert_ne!(frames[0].positions, frames[1].positions);
    let single = tmp("single.ply");
    filmsplat(&[
        "sample",
        "oscillating-bubble",
        "-o",
        single.to_str().unwrap(),
        "--particles",
        "300",
        "--time",
        &(3.0f32 / 24.0).to_string(),
    ]);
    assert_eq!(
        read_cloud(&single, &ReadOptions::default())
            .unwrap()
            .positions,
        frames[1].positions
    );
}

#[test]
fn bad_arguments_fail_with_one_line_and_no_file() {
    let out = tmp("bad.ply");
    let o = out.to_str().unwrap();
    for (args, needle) in [
        (vec!["sample", "drip", "-o", o, "--sparse", "0"], "sparse"),
        (vec!["sample", "drip", "-o", o, "--sparse", "1.5"], "sparse"),
        (
            vec!["sample", "drip", "-o", o, "--particles", "0"],
            "particles",
        ),
        (vec!["sample", "drip", "-o", o, "--time", "NaN"], "time"),
        (
            vec!["sample", "drip", "-o", o, "--frames", "0..2"],
            "frame pattern",
        ),
    ] {
        let _ = std::fs::remove_file(&out);
        let (code, _, err) = filmsplat(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "{args:?}: {err}");
        assert!(
            lines[0].starts_with("filmsplat: error:") && lines[0].contains(needle),
            "{err}"
        );
        assert!(!out.exists(), "{args:?} wrote a file");
    }
    // An unknown name is refused by the argument parser, listing the names.
    let (code, _, err) = filmsplat(&["sample", "teapot", "-o", o]);
    assert_eq!(code, 2);
    assert!(
        err.contains("teapot") && err.contains("half-bubble"),
        "{err}"
    );
    // ... and in a scene file, naming the key.
    let scene = tmp("teapot.toml");
    std::fs::write(&scene, "[input]\nsample = \"teapot\"\n").unwrap();
    let png = tmp("teapot.png");
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.starts_with("filmsplat: error:")
            && err.contains("input.sample")
            && err.contains("catenoid"),
        "{err}"
    );
    std::fs::write(&scene, "[input]\nsample = \"drip\"\nsparse = 0.0\n").unwrap();
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("input.sparse"), "{err}");
    assert!(!png.exists());
}
