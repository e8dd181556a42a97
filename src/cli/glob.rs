//! Quoted globs for `render 'frames/*.ply' -o 'out/{stem}.png'`: `*` (any run of characters)
//! and `?` (one character) in the last path component, matched against that folder's entries;
//! matches come sorted by name. `{stem}` in an output expands to each input's file stem.

use std::path::{Path, PathBuf};

use crate::{Error, Result};

/// True if the last component of `pattern` holds `*` or `?`.
pub(super) fn is_glob(pattern: &Path) -> bool {
    pattern
        .file_name()
        .is_some_and(|n| n.to_string_lossy().contains(['*', '?']))
}

/// True if `name` matches `pattern` (`*`: any run, `?`: one character). Cost: O(len(name) ·
/// len(pattern)) at worst (one backtrack point, the last `*`).
pub(super) fn matches(pattern: &str, name: &str) -> bool {
    let (p, n): (Vec<char>, Vec<char>) = (pattern.chars().collect(), name.chars().collect());
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < n.len() {
        if i < p.len() && (p[i] == '?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some((i, j));
            i += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

/// The entries of the pattern's folder whose names match its last component, sorted by name
/// (hidden files only if the pattern starts with `.`).
///
/// # Errors
/// [`Error::Io`] if the folder cannot be listed; [`Error::Invalid`] if a wildcard appears in a
/// folder name or nothing matches.
pub(super) fn expand(pattern: &Path) -> Result<Vec<PathBuf>> {
    let text = pattern.to_string_lossy();
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = match pattern.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if dir.to_string_lossy().contains(['*', '?']) {
        return Err(Error::invalid(format!(
            "{text}: wildcards are supported in the file name only, not in folders"
        )));
    }
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut found: Vec<PathBuf> = entries
        .flatten()
        .filter_map(|e| {
            let n = e.file_name().to_string_lossy().into_owned();
            let hidden_ok = !n.starts_with('.') || name.starts_with('.');
            (hidden_ok && matches(&name, &n)).then(|| pattern.with_file_name(n))
        })
        .collect();
    found.sort();
    if found.is_empty() {
        return Err(Error::invalid(format!("{text}: no file matches")));
    }
    Ok(found)
}

/// `inputs` without the droplets files `convert` wrote beside a film that is also among them
/// (`a.droplets.ply` beside `a.ply`: rendering `a.ply` reads them, see
/// [`crate::pipeline::beside`]), and how many were taken out.
pub(super) fn without_droplets_beside(inputs: Vec<PathBuf>) -> (Vec<PathBuf>, usize) {
    use crate::pipeline::beside::{droplets_path, is_droplets_name};
    let beside: std::collections::HashSet<PathBuf> = inputs
        .iter()
        .filter(|p| !is_droplets_name(p))
        .map(|p| droplets_path(p))
        .collect();
    let n = inputs.len();
    let kept: Vec<PathBuf> = inputs
        .into_iter()
        .filter(|p| !(is_droplets_name(p) && beside.contains(p)))
        .collect();
    let taken = n - kept.len();
    (kept, taken)
}

/// `output` with every `{stem}` replaced by `input`'s file stem (`frames/a.0001.ply` →
/// `a.0001`); unchanged without `{stem}`.
pub(super) fn with_stem(output: &Path, input: &Path) -> PathBuf {
    let stem = input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    PathBuf::from(output.to_string_lossy().replace("{stem}", &stem))
}

/// Refuses two inputs whose outputs (`outputs(input)`) share a file, as `{stem}` gives for
/// `a.ply` and `a.csv`: one would silently overwrite the other.
///
/// # Errors
/// [`Error::Invalid`] naming the output and both inputs.
pub(super) fn refuse_shared_outputs(
    inputs: &[PathBuf],
    outputs: impl Fn(&Path) -> Vec<PathBuf>,
) -> Result<()> {
    let mut seen: std::collections::HashMap<PathBuf, &Path> = std::collections::HashMap::new();
    for input in inputs {
        for o in outputs(input) {
            if let Some(before) = seen.insert(o.clone(), input) {
                return Err(Error::invalid(format!(
                    "{}: both {} and {} would be written to this file; name the outputs so \
                     they differ (or narrow the pattern)",
                    o.display(),
                    before.display(),
                    input.display()
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: every way to split `name` against the pattern.
    fn oracle(p: &[char], n: &[char]) -> bool {
        match p.split_first() {
            None => n.is_empty(),
            Some(('*', rest)) => (0..=n.len()).any(|k| oracle(rest, &n[k..])),
            Some((&c, rest)) => !n.is_empty() && (c == '?' || c == n[0]) && oracle(rest, &n[1..]),
        }
    }

    #[test]
    fn matcher_agrees_with_brute_force() {
        let alphabet = ['a', 'b', '*', '?'];
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as usize
        };
        for _ in 0..5000 {
            let p: String = (0..next() % 6).map(|_| alphabet[next() % 4]).collect();
            let n: String = (0..next() % 7).map(|_| alphabet[next() % 2]).collect();
            let (pc, nc): (Vec<char>, Vec<char>) = (p.chars().collect(), n.chars().collect());
            assert_eq!(matches(&p, &n), oracle(&pc, &nc), "{p} vs {n}");
        }
        assert!(matches("frame_*.ply", "frame_0001.ply"));
        assert!(!matches("frame_*.ply", "frame_0001.vtk"));
        assert!(matches("f?.ply", "f1.ply") && !matches("f?.ply", "f12.ply"));
    }

    #[test]
    fn stems_expand() {
        assert_eq!(
            with_stem(Path::new("out/{stem}.png"), Path::new("frames/a.0001.ply")),
            PathBuf::from("out/a.0001.png")
        );
        assert_eq!(
            with_stem(Path::new("x.png"), Path::new("a.ply")),
            PathBuf::from("x.png")
        );
    }
}
