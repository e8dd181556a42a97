//! `filmsplat stability` on a tiny rendered sequence, and its error paths.

mod cli_support;
use cli_support::{filmsplat, tmp};

#[test]
fn stability_of_a_tiny_sequence() {
    let dir = tmp("stab");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("s.toml");
    std::fs::write(
        &scene,
        "[input]\nsample = \"oscillating-bubble\"\nparticles = 2000\n[render]\nwidth = 24\nheight = 16\nspp = 1\n",
    )
    .unwrap();
    let png = dir.join("{:02}.png");
    let exr = dir.join("{:02}.exr");
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--exr",
        exr.to_str().unwrap(),
        "--frames",
        "0..3",
    ]);
    assert_eq!(code, 0, "{err}");
    // Frame 3 repeats frame 2: that pair does not change at all.
    std::fs::copy(dir.join("02.exr"), dir.join("03.exr")).unwrap();
    std::fs::copy(dir.join("02.png"), dir.join("03.png")).unwrap();
    let (code, out, err) = filmsplat(&["stability", exr.to_str().unwrap(), "--frames", "0..4"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("3 pairs") && out.contains("depth change <= 1 %"),
        "{out}"
    );
    let line = out.lines().find(|l| l.starts_with("frames 2-3")).unwrap();
    assert!(line.contains("mean dE00 0.000"), "{line}");
    let first = out.lines().find(|l| l.starts_with("frames 0-1")).unwrap();
    assert!(
        !first.contains("mean dE00 0.000"),
        "an oscillating bubble changes: {first}"
    );
    // PNG frames with the EXRs' depth, and PNG frames alone (every pixel).
    let (code, out, _) = filmsplat(&[
        "stability",
        png.to_str().unwrap(),
        "--frames",
        "0..4",
        "--depth",
        exr.to_str().unwrap(),
    ]);
    assert!(code == 0 && out.contains("depth change"), "{out}");
    let (code, out, _) = filmsplat(&["stability", png.to_str().unwrap(), "--frames", "0..4"]);
    assert!(code == 0 && out.contains("every pixel"), "{out}");

    // EXRs without a depth layer: as frames they compare every pixel; as --depth they are
    // refused. Frames of different sizes are refused.
    for (f, w) in [(0, 24), (1, 24), (2, 8)] {
        let layers = filmsplat::image::ExrLayers::rgba(w, 16, vec![[0.5, 0.4, 0.3, 1.0]; w * 16]);
        filmsplat::image::write_exr(&dir.join(format!("nd_{f:02}.exr")), &layers).unwrap();
    }
    let nd = dir.join("nd_{:02}.exr");
    let nd = nd.to_str().unwrap();
    let (code, out, _) = filmsplat(&["stability", nd, "--frames", "0..2"]);
    assert!(
        code == 0 && out.contains("mean dE00 0.000") && out.contains("every pixel"),
        "{out}"
    );
    let png_s = png.to_str().unwrap();
    for (args, needle) in [
        (
            vec!["stability", png_s, "--frames", "0..2", "--depth", nd],
            "no depth layer",
        ),
        (
            vec!["stability", nd, "--frames", "1..3"],
            "frame 2: cannot compare",
        ),
        (
            vec![
                "stability",
                png_s,
                "--frames",
                "0..2",
                "--depth-tolerance=-1",
            ],
            "depth-tolerance",
        ),
        (
            vec!["stability", "no-pattern.exr", "--frames", "0..3"],
            "frame pattern",
        ),
        (
            vec!["stability", exr.to_str().unwrap(), "--frames", "0..9"],
            "04.exr",
        ),
        (
            vec!["stability", exr.to_str().unwrap(), "--frames", "1"],
            "two frames",
        ),
    ] {
        let (code, _, err) = filmsplat(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.starts_with("filmsplat: error:") && err.contains(needle),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}
