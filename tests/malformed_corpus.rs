//! Every file in tests/data/malformed/ (truncated, byte-flipped, absurd-count, wrong-type,
//! missing-property, garbage and empty files of every format, and broken frame folders;
//! written by its make_malformed.py) ends in one clean error: the library returns an input
//! error naming the file, never panics; the CLI prints one line and exits with 2.

mod cli_support;

use filmsplat::Error;
use filmsplat::io::{ReadOptions, read_cloud};
use std::path::PathBuf;

fn corpus() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/malformed");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            name != "make_malformed.py" && name != "README.md"
        })
        .collect();
    v.sort();
    v
}

#[test]
fn every_malformed_input_is_a_clean_error() {
    let files = corpus();
    assert!(files.len() >= 90, "the corpus lost files: {}", files.len());
    let mut kinds = std::collections::BTreeMap::new();
    let mut accepted = Vec::new();
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let result = std::panic::catch_unwind(|| read_cloud(path, &ReadOptions::default()));
        let err = match result {
            Err(_) => panic!("{name}: the reader panicked"),
            Ok(Ok(c)) => {
                accepted.push(format!("{name} ({} particles)", c.len()));
                continue;
            }
            Ok(Err(e)) => e,
        };
        let msg = err.to_string();
        assert!(
            matches!(err, Error::Format { .. } | Error::Io { .. }),
            "{name}: not an input error: {err:?}"
        );
        assert_eq!(err.exit_code(), 2, "{name}");
        assert!(
            msg.contains(&name),
            "{name}: the message does not name it: {msg}"
        );
        assert!(!msg.contains('\n'), "{name}: more than one line: {msg}");
        let format = match &err {
            Error::Format { format, .. } => *format,
            _ => "I/O",
        };
        *kinds.entry(format).or_insert(0) += 1;
    }
    assert!(accepted.is_empty(), "read instead of failing: {accepted:?}");
    // Every reader is exercised.
    for f in [
        "PLY",
        "VTK legacy",
        "VTK XML",
        "BGEO",
        "CSV",
        "frame folder",
    ] {
        assert!(
            kinds.keys().any(|k| k.starts_with(f)),
            "no {f} errors: {kinds:?}"
        );
    }
}

#[test]
fn the_cli_reports_each_in_one_line_with_exit_2() {
    for path in corpus() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let (code, out, err) = cli_support::filmsplat(&["info", path.to_str().unwrap()]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(out.is_empty(), "{name}: {out}");
        assert_eq!(err.lines().count(), 1, "{name}: {err}");
        assert!(
            err.starts_with("filmsplat: error: ") && err.contains(&name),
            "{name}: {err}"
        );
    }
}
