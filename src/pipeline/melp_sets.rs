//! MELP writes every film twice per frame (wang-mengdi/melp-thin-film, `melp/VTKIOFunc.cpp`):
//! the Lagrangian particles (`l_particles_NNNN.vtp`, `l_circles_NNNN.vtp`), which carry the
//! film, and the Eulerian ones (`e_…`), the same film resampled. Given both of one frame, the
//! scene would hold two copies of one film; [`choose`] keeps one set (`input.melp_set`,
//! `--melp-set`) and says so.

use std::path::{Path, PathBuf};

use crate::{Error, Result};

/// Which of a MELP frame's particle sets are drawn when both are given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MelpSet {
    /// The Lagrangian particles (`l_`), which carry the film (the default).
    #[default]
    Lagrangian,
    /// The Eulerian particles (`e_`).
    Eulerian,
    /// Both, as two copies of the film.
    Both,
}

impl MelpSet {
    /// Parses "lagrangian", "eulerian" or "both" (`None`: the default).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the accepted values.
    pub fn parse(name: Option<&str>) -> Result<Self> {
        match name {
            None | Some("lagrangian") => Ok(MelpSet::Lagrangian),
            Some("eulerian") => Ok(MelpSet::Eulerian),
            Some("both") => Ok(MelpSet::Both),
            Some(other) => Err(Error::invalid(format!(
                "input.melp_set: '{other}' is not lagrangian, eulerian or both"
            ))),
        }
    }
}

/// The set letter (`e`/`l`) of a MELP file name `e_particles_0100.vtp`, and the key of its
/// frame (folder, kind, number).
fn melp_file(path: &Path) -> Option<(char, (PathBuf, String))> {
    let name = path.file_name()?.to_str()?;
    let stem = name.strip_suffix(".vtp")?;
    let (set, rest) = stem.split_at_checked(2)?;
    let set = match set {
        "e_" => 'e',
        "l_" => 'l',
        _ => return None,
    };
    let (kind, frame) = rest.rsplit_once('_')?;
    let frame_ok = !frame.is_empty() && frame.bytes().all(|b| b.is_ascii_digit());
    let kind_ok = matches!(kind, "particles" | "circles");
    (frame_ok && kind_ok).then(|| {
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        (set, (dir, format!("{kind}_{frame}")))
    })
}

/// The inputs to read: where one frame's `e_` and `l_` files are both given, only `set`'s
/// (both for [`MelpSet::Both`]); with a one-line note when that happened.
pub fn choose(paths: &[PathBuf], set: MelpSet) -> (Vec<PathBuf>, Option<String>) {
    let files: Vec<_> = paths.iter().map(|p| melp_file(p)).collect();
    let paired = |key: &(PathBuf, String), want: char| {
        files.iter().flatten().any(|(s, k)| *s == want && k == key)
    };
    let mut pairs = Vec::new();
    let mut keep = Vec::new();
    for (p, f) in paths.iter().zip(&files) {
        let Some((s, key)) = f else {
            keep.push(p.clone());
            continue;
        };
        let other = if *s == 'e' { 'l' } else { 'e' };
        if !paired(key, other) {
            keep.push(p.clone());
            continue;
        }
        if *s == 'l' {
            pairs.push(key.1.clone());
        }
        let wanted = match set {
            MelpSet::Lagrangian => *s == 'l',
            MelpSet::Eulerian => *s == 'e',
            MelpSet::Both => true,
        };
        if wanted {
            keep.push(p.clone());
        }
    }
    if pairs.is_empty() {
        return (keep, None);
    }
    let drawn = match set {
        MelpSet::Lagrangian => {
            "drawing the Lagrangian set only (--melp-set eulerian or both for the others)"
        }
        MelpSet::Eulerian => "drawing the Eulerian set only, as asked",
        MelpSet::Both => "drawing both, as asked: two copies of one film",
    };
    let note = format!(
        "MELP: the Eulerian (e_) and Lagrangian (l_) particles of one film were both given ({}): {drawn}",
        pairs.join(", ")
    );
    (keep, Some(note))
}

/// The one line a MELP foam folder gets: a folder is always read as its Lagrangian set
/// (`l_…_R`, the film), so a `set` other than that is not applied; by default, the line says
/// the Eulerian files (`e_…_R`, the same film resampled) are not drawn (`None` if there are
/// none).
pub fn folder_note(dir: &Path, set: MelpSet) -> Option<String> {
    if set != MelpSet::Lagrangian {
        return Some(format!(
            "{}: a MELP foam folder is read as its Lagrangian set (input.melp_set / --melp-set \
             chooses between e_ and l_ .vtp files)",
            dir.display()
        ));
    }
    let has_eulerian = dir.join("e_tracker_points_0").is_file();
    has_eulerian.then(|| {
        format!(
            "MELP: the Eulerian (e_) and Lagrangian (l_) particles of one film are both in {}: \
             drawing the Lagrangian set only (a foam folder has no Eulerian choice)",
            dir.display()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> PathBuf {
        PathBuf::from(s)
    }

    #[test]
    fn keeps_one_set_of_a_frame_given_twice() {
        let paths = [
            p("run/e_particles_0100.vtp"),
            p("run/l_particles_0100.vtp"),
            p("run/l_particles_0101.vtp"),
            p("other.ply"),
        ];
        let (keep, note) = choose(&paths, MelpSet::Lagrangian);
        assert_eq!(keep, [paths[1].clone(), paths[2].clone(), paths[3].clone()]);
        assert!(note.unwrap().contains("particles_0100"));
        let (keep, _) = choose(&paths, MelpSet::Eulerian);
        assert_eq!(keep, [paths[0].clone(), paths[2].clone(), paths[3].clone()]);
        let (keep, note) = choose(&paths, MelpSet::Both);
        assert_eq!(keep.len(), 4);
        assert!(note.unwrap().contains("two copies"));
        // Different frames, folders or kinds are not one film given twice.
        let apart = [p("a/e_particles_0100.vtp"), p("b/l_particles_0100.vtp")];
        assert_eq!(choose(&apart, MelpSet::Lagrangian), (apart.to_vec(), None));
        assert!(MelpSet::parse(Some("lagrange")).is_err());
    }
}
