//! The droplets `filmsplat convert` wrote beside a film: rendering `NAME.ply` also reads
//! `NAME.droplets.ply` from its folder when that file is marked as droplets
//! ([`crate::io::write_droplets_ply`]), and says so, so a converted frame renders as the
//! frame did.

use crate::Result;
use crate::io::{CloudPart, PartKind, ReadOptions, read_parts};
use std::path::{Path, PathBuf};

/// Where `convert` puts the droplets of a film written to `film`: `STEM.droplets.ply` beside
/// it.
pub fn droplets_path(film: &Path) -> PathBuf {
    let stem = film.file_stem().unwrap_or_default().to_string_lossy();
    film.with_file_name(format!("{stem}.droplets.ply"))
}

/// True if `path` names a droplets file by the name `convert` gives one.
pub fn is_droplets_name(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|n| n.to_string_lossy().ends_with(".droplets.ply"))
}

/// The droplets beside the PLY film `input` (see the module docs), with a note naming the
/// file; `None` when `input` is not a `.ply` file, is itself a droplets file, or has no marked
/// droplets file beside it.
///
/// # Errors
/// As [`read_parts`] for a droplets file that is there but cannot be read.
pub fn droplets_beside(input: &Path, opts: &ReadOptions) -> Result<Option<CloudPart>> {
    let is_ply = input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
    if !is_ply || is_droplets_name(input) || !input.is_file() {
        return Ok(None);
    }
    let path = droplets_path(input);
    if !path.is_file() {
        return Ok(None);
    }
    let mut parts = read_parts(&path, opts)?;
    let Some(mut part) = parts.pop().filter(|p| p.kind == PartKind::Droplets) else {
        return Ok(None);
    };
    part.notes.push(format!(
        "{}: the droplets beside {} (written by convert), read with it",
        path.display(),
        input.display()
    ));
    Ok(Some(part))
}
