//! A frame converted to PLY renders as the frame did: `convert` marks its `NAME.droplets.ply`
//! as droplets, reading it back gives a droplets part, rendering `NAME.ply` reads the droplets
//! beside it (and says so), and a glob over the folder does not turn the droplets file into a
//! frame of its own.

mod cli_support;
use cli_support::{data, filmsplat, tmp};
use filmsplat::io::{PartKind, ReadOptions, read_parts};

/// Converts bursting frame 60 (film and droplets) into a folder of its own; returns the film's
/// and the droplets' paths.
fn converted(dir: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = tmp(dir);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let ply = dir.join("f60.ply");
    let frame = data("thin-film-sph/bursting_bubble/60");
    let (code, _, err) = filmsplat(&["convert", &frame, "-o", ply.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    (ply, dir.join("f60.droplets.ply"))
}

#[test]
fn droplets_file_reads_back_as_droplets() {
    let (ply, drops) = converted("round-trip-parts");
    let parts = read_parts(&drops, &ReadOptions::default()).unwrap();
    assert_eq!(parts.len(), 1);
    assert_eq!(parts[0].kind, PartKind::Droplets);
    assert_eq!(parts[0].cloud.len(), 792);
    let film = read_parts(&ply, &ReadOptions::default()).unwrap();
    assert_eq!(film.len(), 1);
    assert_eq!(film[0].kind, PartKind::Film);
    let (code, out, err) = filmsplat(&["info", drops.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("(droplets)"), "{out}");
}

#[test]
fn converted_frame_renders_as_the_frame() {
    let (ply, _) = converted("round-trip-render");
    let frame = data("thin-film-sph/bursting_bubble/60");
    let a = ply.with_file_name("converted.png");
    let b = ply.with_file_name("frame.png");
    let args = ["--size", "64x48", "--seed", "3"];
    let (code, _, err) = filmsplat(
        &[
            &["render", ply.to_str().unwrap(), "-o", a.to_str().unwrap()][..],
            &args,
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("f60.droplets.ply: the droplets beside"),
        "{err}"
    );
    let (code, _, err) =
        filmsplat(&[&["render", &frame, "-o", b.to_str().unwrap()][..], &args].concat());
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn glob_reads_droplets_with_their_film() {
    let (ply, _) = converted("round-trip-glob");
    let dir = ply.parent().unwrap();
    let pattern = dir.join("*.ply");
    let out = dir.join("{stem}.png");
    let (code, _, err) = filmsplat(&[
        "render",
        pattern.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("1 of the files matching"), "{err}");
    assert!(dir.join("f60.png").is_file());
    assert!(!dir.join("f60.droplets.png").exists());
}
