//! ParaView collections (`.pvd`): `<VTKFile type="Collection">` with one
//! `<DataSet timestep=".." part=".." file=".."/>` per file, paths relative to the `.pvd`.
//!
//! A collection is read as one scene: every data set of one timestep (the first by default)
//! is a part, read by [`super::read_parts`]. [`timesteps`] lists what a collection holds, so a
//! sequence can pick timestep k.

use std::path::{Path, PathBuf};

use super::columns::show;
use super::xml::Scanner;
use super::{format_error, read_file};
use crate::error::Result;

/// Name used in error messages.
const FORMAT: &str = "PVD collection";

/// Most data sets one collection may name.
const MAX_DATASETS: usize = 100_000;

/// One `<DataSet>`.
#[derive(Debug, Clone, PartialEq)]
pub struct DataSet {
    /// The `timestep` attribute (0 if absent).
    pub timestep: f64,
    /// The file, resolved against the collection's folder.
    pub file: PathBuf,
}

/// The data sets of the collection at `path`, grouped by timestep in increasing order.
///
/// # Errors
/// [`crate::Error::Format`] naming the file if it is no collection, a data set has no `file`,
/// or a timestep is not a number.
pub fn timesteps(path: &Path) -> Result<Vec<(f64, Vec<PathBuf>)>> {
    let bytes = read_file(path)?;
    let err = |m: String| format_error(path, FORMAT, m);
    let base = path.parent().unwrap_or(Path::new(""));
    let mut sc = Scanner { b: &bytes, pos: 0 };
    let mut sets = Vec::new();
    let mut collection = false;
    while let Some(tag) = sc.next_tag().map_err(err)? {
        if tag.end {
            continue;
        }
        match tag.name {
            "VTKFile" => collection = tag.attr("type") == Some("Collection"),
            "DataSet" => {
                let file = tag
                    .attr("file")
                    .ok_or_else(|| err("a <DataSet> without a file attribute".into()))?;
                let timestep = match tag.attr("timestep") {
                    None => 0.0,
                    Some(t) => t
                        .trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|t| t.is_finite())
                        .ok_or_else(|| {
                            err(format!("timestep '{}' is not a finite number", show(t)))
                        })?,
                };
                if sets.len() == MAX_DATASETS {
                    return Err(err(format!("more than {MAX_DATASETS} data sets")));
                }
                sets.push(DataSet {
                    timestep,
                    file: base.join(file),
                });
            }
            _ => {}
        }
    }
    if !collection {
        return Err(err("not a <VTKFile type=\"Collection\">".into()));
    }
    if sets.is_empty() {
        return Err(err("the collection names no <DataSet>".into()));
    }
    sets.sort_by(|a, b| a.timestep.total_cmp(&b.timestep));
    let mut out: Vec<(f64, Vec<PathBuf>)> = Vec::new();
    for s in sets {
        match out.last_mut() {
            Some((t, files)) if *t == s.timestep => files.push(s.file),
            _ => out.push((s.timestep, vec![s.file])),
        }
    }
    Ok(out)
}

/// The data files of the collection's `k`-th timestep (0-based); read them with
/// [`super::read_timestep`].
///
/// # Errors
/// As [`timesteps`]; `k` past the last timestep is an error naming the count, and a collection
/// naming another collection is refused.
pub fn timestep_files(path: &Path, k: usize) -> Result<Vec<PathBuf>> {
    let steps = timesteps(path)?;
    let Some((_, files)) = steps.get(k) else {
        return Err(format_error(
            path,
            FORMAT,
            format!("timestep {k} asked for, the collection has {}", steps.len()),
        ));
    };
    if let Some(f) = files
        .iter()
        .find(|f| f.extension().is_some_and(|e| e.eq_ignore_ascii_case("pvd")))
    {
        return Err(format_error(
            path,
            FORMAT,
            format!("names another collection, {}", f.display()),
        ));
    }
    Ok(files.clone())
}
