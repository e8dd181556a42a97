//! Helpers shared by the CLI tests: run the binary, temporary files, test data paths.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Command;

// A test that takes both support modules loads this one twice: two sweeps, no harm.
#[allow(clippy::duplicate_mod)]
#[path = "../scratch/mod.rs"]
mod scratch;

/// Runs `filmsplat` with `args`; returns (exit code, stdout, stderr).
pub fn filmsplat(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_filmsplat"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A path in this test process's own temporary folder.
pub fn tmp(name: &str) -> PathBuf {
    scratch::dir("cli").join(name)
}

/// Path of a file in tests/data/.
pub fn data(name: &str) -> String {
    format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The header of an ASCII PLY of `n` particles with position, normal, radius and thickness
/// (`x y z nx ny nz radius thickness` a line), so nothing is estimated.
pub fn disk_ply_header(n: usize) -> String {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n\
         property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float radius\nproperty float thickness\nend_header\n"
    )
}
