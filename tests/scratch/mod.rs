//! Scratch folders for the integration tests: under Cargo's `target/tmp`, not the system's
//! temporary folder, one per kind and test process. The folders a test process of the same kind
//! left behind are removed once it has ended, so repeated runs do not pile them up.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// `target/tmp/filmsplat-<kind>-<pid>`, created. The first call for `kind` in a process also
/// removes the `filmsplat-<kind>-<pid>` folders of processes no longer running (where
/// `/proc` tells; elsewhere nothing is removed).
pub fn dir(kind: &str) -> PathBuf {
    static SWEPT: Mutex<Vec<String>> = Mutex::new(Vec::new());
    let base = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let prefix = format!("filmsplat-{kind}-");
    {
        let mut swept = SWEPT.lock().unwrap();
        if !swept.contains(&prefix) {
            sweep(base, &prefix);
            swept.push(prefix.clone());
        }
    }
    let d = base.join(format!("{prefix}{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Removes `base/<prefix><pid>` for every `pid` that is not a running process.
fn sweep(base: &Path, prefix: &str) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(base) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(pid) = name
            .strip_prefix(prefix)
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        if pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}
