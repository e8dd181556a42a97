//! Fail before the work: output folders are created, or refused with a one-line error and exit
//! code 2, before anything is rendered or written; a render estimated to need more memory than
//! the machine has available is refused before loading.

mod cli_support;
use cli_support::{filmsplat, tmp};

use filmsplat::pipeline::memory::{MemoryEstimate, available_memory};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh empty folder.
fn empty(name: &str) -> PathBuf {
    let d = tmp(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `filmsplat` in `dir`; returns (exit code, stdout, stderr).
fn filmsplat_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_filmsplat"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn the_readme_sequence_commands_work_in_an_empty_folder() {
    // docs/sequences.md: `filmsplat sample catenoid -o 'cat/{:04}.ply' --frames 0..48 --sparse 0.2`
    // (fewer particles and frames here), then the Slurm job array's render of every shard.
    let dir = empty("readme");
    let (code, _, err) = filmsplat_in(
        &dir,
        &[
            "sample",
            "catenoid",
            "-o",
            "cat/{:04}.ply",
            "--frames",
            "0..4",
            "--sparse",
            "0.2",
            "--particles",
            "3000",
        ],
    );
    assert_eq!(code, 0, "{err}");
    for f in 0..4 {
        assert!(dir.join(format!("cat/{f:04}.ply")).is_file(), "frame {f}");
    }
    for k in 0..2 {
        let (code, out, err) = filmsplat_in(
            &dir,
            &[
                "render",
                "cat/{:04}.ply",
                "-o",
                "out/{:04}.png",
                "--frames",
                "0..4",
                "--shard",
                &format!("{k}/2"),
                "--resume",
                "--keep-going",
                "-q",
                "--size",
                "32x24",
                "--spp",
                "1",
            ],
        );
        assert_eq!(code, 0, "shard {k}: {err}");
        assert!(out.is_empty(), "{out}");
    }
    for f in 0..4 {
        assert!(dir.join(format!("out/{f:04}.png")).is_file(), "frame {f}");
    }
    // A single render and a mesh sample into missing folders too.
    let (code, _, err) = filmsplat_in(
        &dir,
        &[
            "render",
            "cat/0000.ply",
            "-o",
            "one/deep/f.png",
            "--size",
            "16x12",
            "--spp",
            "1",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("one/deep/f.png").is_file());
    let (code, _, err) = filmsplat_in(
        &dir,
        &[
            "sample",
            "bubble-mesh",
            "-o",
            "mesh/b.ply",
            "--subdivisions",
            "1",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("mesh/b.ply").is_file());
}

#[test]
fn an_output_folder_that_cannot_be_made_is_refused_before_any_frame() {
    let dir = empty("blocked");
    // Frame 1's folder is taken by a file; frame 0's could be written, but must not be.
    std::fs::write(dir.join("o_0001"), b"a file").unwrap();
    let (code, out, err) = filmsplat_in(
        &dir,
        &[
            "sample",
            "bubble",
            "-o",
            "o_{:04}/c.ply",
            "--frames",
            "0..3",
            "--particles",
            "500",
        ],
    );
    assert_eq!(code, 2, "{out}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("o_0001/c.ply") && err.contains("cannot create the output folder"),
        "{err}"
    );
    assert!(
        !dir.join("o_0000/c.ply").exists(),
        "nothing written before the refusal"
    );
    std::fs::create_dir_all(dir.join("frames")).unwrap();
    for f in 0..3 {
        let (code, _, err) = filmsplat_in(
            &dir,
            &[
                "sample",
                "bubble",
                "-o",
                &format!("frames/{f}.ply"),
                "--particles",
                "500",
            ],
        );
        assert_eq!(code, 0, "{err}");
    }
    for extra in [&[][..], &["--keep-going"][..]] {
        let mut args = vec![
            "render",
            "frames/{}.ply",
            "-o",
            "o_{:04}/f.png",
            "--frames",
            "0..3",
            "--size",
            "16x12",
            "--spp",
            "1",
        ];
        args.extend_from_slice(extra);
        let (code, out, err) = filmsplat_in(&dir, &args);
        assert_eq!(code, 2, "{out}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains("o_0001/f.png") && err.contains("cannot create the output folder"),
            "{err}"
        );
        assert!(!err.contains("frame 0"), "refused before frame 0: {err}");
        assert!(!dir.join("o_0000/f.png").exists());
    }
    // One image, and compare's figure.
    let (code, _, err) = filmsplat_in(&dir, &["render", "frames/0.ply", "-o", "o_0001/x.png"]);
    assert_eq!(code, 2);
    assert!(err.contains("cannot create the output folder"), "{err}");
    let (code, _, err) = filmsplat_in(
        &dir,
        &[
            "compare",
            "disk",
            "sphere",
            "frames/0.ply",
            "-o",
            "o_0001/x.png",
        ],
    );
    assert_eq!(code, 2);
    assert!(err.contains("cannot create the output folder"), "{err}");
}

#[test]
fn a_render_bigger_than_the_available_memory_is_refused_up_front() {
    // 32768x32768 pixels need ~77 GB for the image alone. The cloud's body is cut short, so a
    // render that got past the check would stop at reading it, allocating little.
    let dir = empty("memory");
    let ply = dir.join("cut.ply");
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 40\n\
        property float x\nproperty float y\nproperty float z\nend_header\n"
        .to_vec();
    bytes.extend_from_slice(&[0u8; 100]);
    std::fs::write(&ply, &bytes).unwrap();
    let need = MemoryEstimate::new(40, 32_768, 32_768, false, 0).total();
    let Some(available) = available_memory() else {
        eprintln!("no /proc/meminfo here: no default limit to test");
        return;
    };
    if available >= need {
        eprintln!("this machine has {available} bytes available, more than {need}");
        return;
    }
    let out = dir.join("big.png");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "render",
            ply.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "32768x32768",
        ];
        args.extend_from_slice(extra);
        filmsplat(&args)
    };
    let (code, _, err) = run(&[]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    // The image alone does not fit: refused as the size is checked, before the input is read.
    assert!(
        err.contains("32768x32768 render needs") && err.contains("memory available"),
        "{err}"
    );
    assert!(err.contains("--max-memory"), "says what to do: {err}");
    // --max-memory sets the limit explicitly: above the estimate the render goes on (and stops
    // at the cut body), below it the message names the flag.
    let (code, _, err) = run(&["--max-memory", "1000T"]);
    assert_eq!(code, 2);
    assert!(
        !err.contains("exceeds") && err.contains("too short"),
        "past the check: {err}"
    );
    let (code, _, err) = run(&["--max-memory", "1G"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("more than the 1.0 GiB") && err.contains("--max-memory"),
        "{err}"
    );
    assert!(!out.exists());
    // Also for each frame of a sequence, before the first.
    std::fs::copy(&ply, dir.join("cut0.ply")).unwrap();
    let (code, out_text, err) = filmsplat(&[
        "render",
        dir.join("cut{}.ply").to_str().unwrap(),
        "-o",
        dir.join("f_{}.png").to_str().unwrap(),
        "--frames",
        "0..1",
        "--size",
        "32768x32768",
        "--camera",
        "0,0,5",
    ]);
    assert_eq!(code, 2, "{out_text}");
    assert!(err.contains("memory available"), "{err}");
    // The auto-framed sequence measures its first frame under the same check.
    let (code, _, err) = filmsplat(&[
        "render",
        dir.join("cut{}.ply").to_str().unwrap(),
        "-o",
        dir.join("g_{}.png").to_str().unwrap(),
        "--frames",
        "0..1",
        "--size",
        "32768x32768",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("memory available"), "{err}");
}
