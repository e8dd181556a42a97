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
    count: usize,
    /// The fewest and most digits seen.
    widths: (usize, usize),
    /// Whether any number had a leading zero.
    padded: bool,
    /// The lowest and the highest number, each with its entry's name.
    lo: Option<(u64, String)>,
    hi: Option<(u64, String)>,
}

impl Run {
    fn add(&mut self, digits: &str, name: &str) {
        let Ok(n) = digits.parse::<u64>() else { return };
        self.widths = if self.count == 0 {
            (digits.len(), digits.len())
        } else {
            (
                self.widths.0.min(digits.len()),
                self.widths.1.max(digits.len()),
            )
        };
        if self.lo.as_ref().is_none_or(|(m, _)| n < *m) {
            self.lo = Some((n, name.to_string()));
        }
        if self.hi.as_ref().is_none_or(|(m, _)| n > *m) {
            self.hi = Some((n, name.to_string()));
        }
        self.padded |= digits.len() > 1 && digits.starts_with('0');
        self.count += 1;
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
            (r.count, b.starts_with("l_"), std::cmp::Reverse(b.clone()))
        })?;
    let pattern = dir.join(format!("{before}{}{after}", run.placeholder()?));
    let (Some((lo, first)), Some((hi, last))) = (run.lo, run.hi) else {
        return None;
    };
    if is_dir && !is_frame_folder(&dir.join(&first)) {
        return None;
    }
    let what = if is_dir {
        "frame folders"
    } else {
        "particle files"
    };
    let count = run.count;
    if count == 1 {
        // One frame: no sequence to name, and no "files … to …" range.
        let one = what.trim_end_matches('s');
        return Some(format!(
            "it holds one numbered {one}: render it, '{}'",
            dir.join(&first).display()
        ));
    }
    let gaps = if u128::from(hi - lo) + 1 == count as u128 {
        ""
    } else {
        ", with gaps"
    };
    Some(format!(
        "it holds {count} numbered {what} ({} to {}{gaps}): render one of them, or the sequence \
         with '{}' --frames {lo}..={hi}",
        first,
        last,
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
    fn a_single_numbered_file_is_named_as_one_file_not_a_sequence() {
        // The project's tests/data/melp/bubble holds one frame's l_ and e_ files.
        let d = dir_with(&["l_particles_0100.vtp", "e_particles_0100.vtp"], &[]);
        let h = hint(d.path(), |_| true, vtp).unwrap();
        let want = format!("'{}'", d.path().join("l_particles_0100.vtp").display());
        assert!(h.contains("one numbered particle file:"), "{h}");
        assert!(h.contains(&want) && !h.contains("--frames"), "{h}");
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
