//! What a directory that is no frame folder holds, for its error message: a run of numbered
//! frame folders (a simulator's output directory) or of numbered particle files (MELP's
//! `l_particles_0100.vtp`, …), named as the sequence that renders them.
//!
//! Cost: lists at most [`MAX_ENTRIES`] entries of the directory and looks into one
//! sub-directory; it never reads a particle file.

use std::collections::BTreeMap;
use std::path::Path;

/// Entries looked at, so a huge directory costs a bounded time.
pub(crate) const MAX_ENTRIES: usize = 100_000;

/// Numbered entries sharing a name around their number.
#[derive(Default)]
struct Run {
    numbers: Vec<u64>,
    /// Digit counts seen, and whether any number had a leading zero.
    widths: (usize, usize),
    padded: bool,
    /// The name of the lowest number.
    first_name: String,
    /// The name of the highest number.
    last_name: String,
}

impl Run {
    fn add(&mut self, digits: &str, name: &str) {
        let Ok(n) = digits.parse::<u64>() else { return };
        if self.numbers.is_empty() {
            self.widths = (digits.len(), digits.len());
        }
        if self.numbers.iter().all(|&m| n < m) {
            self.first_name = name.to_string();
        }
        if self.numbers.iter().all(|&m| n > m) {
            self.last_name = name.to_string();
        }
        self.widths = (
            self.widths.0.min(digits.len()),
            self.widths.1.max(digits.len()),
        );
        self.padded |= digits.len() > 1 && digits.starts_with('0');
        self.numbers.push(n);
    }

    /// The frame pattern's placeholder, or `None` if the names mix widths with padding.
    fn placeholder(&self) -> Option<String> {
        match (self.padded, self.widths) {
            (false, _) => Some("{}".into()),
            (true, (a, b)) if a == b => Some(format!("{{:0{a}}}")),
            _ => None,
        }
    }
}

/// The name split around its last run of digits: (before, digits, after).
fn split_number(name: &str) -> Option<(&str, &str, &str)> {
    let end = name.rfind(|c: char| c.is_ascii_digit())? + 1;
    let start = name[..end]
        .rfind(|c: char| !c.is_ascii_digit())
        .map_or(0, |i| i + 1);
    Some((&name[..start], &name[start..end], &name[end..]))
}

/// A sentence saying what `dir` holds and how to render it, if it holds numbered frame folders
/// (`is_frame_folder`, looked at for the first one only) or numbered particle files
/// (`is_particle_file`, by name).
pub(crate) fn hint(
    dir: &Path,
    is_frame_folder: impl Fn(&Path) -> bool,
    is_particle_file: impl Fn(&Path) -> bool,
) -> Option<String> {
    let mut runs: BTreeMap<(bool, String, String), Run> = BTreeMap::new();
    for entry in std::fs::read_dir(dir).ok()?.take(MAX_ENTRIES).flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        if !is_dir && !is_particle_file(&entry.path()) {
            continue;
        }
        if let Some((before, digits, after)) = split_number(&name) {
            if is_dir && !(before.is_empty() && after.is_empty()) {
                continue; // only plainly numbered folders are frames
            }
            let key = (is_dir, before.to_string(), after.to_string());
            runs.entry(key).or_default().add(digits, &name);
        }
    }
    // The longest run; on a tie a Lagrangian (`l_`) set before an Eulerian one, then by name.
    let ((is_dir, before, after), run) = runs
        .into_iter()
        .filter(|(_, r)| r.placeholder().is_some())
        .max_by_key(|((_, b, _), r)| {
            (
                r.numbers.len(),
                b.starts_with("l_"),
                std::cmp::Reverse(b.clone()),
            )
        })?;
    if is_dir && !is_frame_folder(&dir.join(&run.first_name)) {
        return None;
    }
    let (lo, hi) = run
        .numbers
        .iter()
        .fold((u64::MAX, 0), |(a, b), &n| (a.min(n), b.max(n)));
    let pattern = dir.join(format!("{before}{}{after}", run.placeholder()?));
    let what = if is_dir {
        "frame folders"
    } else {
        "particle files"
    };
    let count = run.numbers.len();
    let gaps = if (hi - lo + 1) as usize == count {
        ""
    } else {
        ", with gaps"
    };
    Some(format!(
        "it holds {count} numbered {what} ({} to {}{gaps}): render one of them, or the sequence \
         with '{}' --frames {lo}..={hi}",
        run.first_name,
        run.last_name,
        pattern.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory holding empty `files` and empty sub-directories `dirs`.
    struct Scratch(std::path::PathBuf);

    impl Scratch {
        fn path(&self) -> &Path {
            &self.0
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn dir_with(files: &[&str], dirs: &[&str]) -> Scratch {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static N: AtomicUsize = AtomicUsize::new(0);
        let d = std::env::temp_dir().join(format!(
            "filmsplat-hint-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&d).unwrap();
        for f in files {
            std::fs::write(d.join(f), b"").unwrap();
        }
        for s in dirs {
            std::fs::create_dir(d.join(s)).unwrap();
        }
        Scratch(d)
    }

    fn vtp(p: &Path) -> bool {
        p.extension().is_some_and(|e| e == "vtp")
    }

    #[test]
    fn melp_files_name_the_lagrangian_sequence() {
        let d = dir_with(
            &[
                "e_particles_0100.vtp",
                "e_particles_0101.vtp",
                "l_particles_0100.vtp",
                "l_particles_0101.vtp",
                "l_circles_0100.vtp",
                "notes.txt",
            ],
            &[],
        );
        let h = hint(d.path(), |_| true, vtp).unwrap();
        let want = format!(
            "'{}' --frames 100..=101",
            d.path().join("l_particles_{:04}.vtp").display()
        );
        assert!(h.contains("2 numbered particle files"), "{h}");
        assert!(h.contains(&want), "{h}");
    }

    #[test]
    fn numbered_frame_folders_name_the_run() {
        let d = dir_with(&[], &["0", "1", "2", "10", "snapshot"]);
        let h = hint(
            d.path(),
            |p| p.ends_with("0") || p.ends_with("1") || p.ends_with("2") || p.ends_with("10"),
            vtp,
        )
        .unwrap();
        assert!(h.contains("4 numbered frame folders"), "{h}");
        assert!(
            h.contains("--frames 0..=10") && h.contains("with gaps"),
            "{h}"
        );
        assert!(
            h.contains(&format!("'{}'", d.path().join("{}").display())),
            "{h}"
        );
    }

    #[test]
    fn nothing_numbered_gives_no_hint() {
        let d = dir_with(&["a.txt"], &["x"]);
        assert!(hint(d.path(), |_| true, vtp).is_none());
        let d = dir_with(&[], &["0", "1"]);
        assert!(
            hint(d.path(), |_| false, vtp).is_none(),
            "folders that are no frames"
        );
    }

    #[test]
    fn split_finds_the_last_number() {
        assert_eq!(
            split_number("l_particles_0100.vtp"),
            Some(("l_particles_", "0100", ".vtp"))
        );
        assert_eq!(split_number("12"), Some(("", "12", "")));
        assert_eq!(split_number("abc"), None);
    }
}
