//! Frame folders of the thin-film SPH research code: one directory per frame holding one file
//! per attribute, `NAME_bin`.
//!
//! Each file is a little-endian `u32` count n followed by n×3 (vector) or n (scalar) `f64`;
//! vector or scalar is decided by the size (4 + 24n or 4 + 8n bytes, anything else is an
//! error naming the file). `x_bin` holds the positions and is required; every other `*_bin`
//! file becomes the attribute `NAME` (vectors `NAME_x/_y/_z`), mapped by
//! [`FRAME_NORMAL_ALIASES`] (`norm_bin` first), [`FRAME_THICKNESS_ALIASES`] (`rh_bin`, then
//! `h_bin`) and [`crate::io::RADIUS_ALIASES`] unless named explicitly. Thickness is in metres
//! unless [`ReadOptions::thickness_unit_explicit`] says otherwise. All counts must agree.
//! Other files and subdirectories are ignored.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::StoredAttribute;
use super::columns::{Aliases, Columns};
use super::{FRAME_NORMAL_ALIASES, FRAME_THICKNESS_ALIASES, RADIUS_ALIASES, ReadOptions};
use super::{format_error, read_file};
use crate::error::{Error, Result};
use crate::pointcloud::PointCloud;

/// Name used in error messages.
const FORMAT: &str = "frame folder";

/// The folder's aliases: thickness in metres.
const ALIASES: Aliases = Aliases {
    thickness: FRAME_THICKNESS_ALIASES,
    normal: FRAME_NORMAL_ALIASES,
    radius: RADIUS_ALIASES,
    default_scale_to_nm: 1e9,
};

/// Reads the frame folder `dir` into a [`PointCloud`] (see the module docs).
///
/// Cost: reads every `*_bin` file once; peak memory is the cloud plus the largest file.
///
/// # Errors
/// [`Error::Io`] if a file cannot be read; [`Error::Format`] naming the file if `dir` is not a
/// directory, `x_bin` is missing or not a vector file, a file's size fits neither layout
/// (truncated files report where the data runs out), counts disagree, or an attribute named
/// in `opts` is missing; [`Error::Invalid`] for a bad option.
pub fn read(dir: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    read_described(dir, opts).map(|(c, _)| c)
}

/// Like [`read`], and also returns what the file stores ([`StoredAttribute`]s).
pub fn read_described(
    dir: &Path,
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>)> {
    opts.check()?;
    let meta = std::fs::metadata(dir).map_err(|e| Error::io(dir, e))?;
    if !meta.is_dir() {
        return Err(format_error(dir, FORMAT, "not a directory"));
    }
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(attr) = name.strip_suffix("_bin") else {
            continue;
        };
        if attr.is_empty() || attr == "x" || !entry.path().is_file() {
            continue;
        }
        files.push((attr.to_string(), entry.path()));
    }
    files.sort();

    let xp = dir.join("x_bin");
    if !xp.is_file() {
        return Err(format_error(
            &xp,
            FORMAT,
            "missing: x_bin holds the positions",
        ));
    }
    let (k, x) = parse(&read_file(&xp)?).map_err(|m| format_error(&xp, FORMAT, m))?;
    if k == 1 && !x.is_empty() {
        return Err(format_error(
            &xp,
            FORMAT,
            format!(
                "holds {} scalars; positions need 3 values per particle",
                x.len()
            ),
        ));
    }
    let n = x.len() / 3;
    let mut cols = Columns {
        positions: x
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect(),
        ..Columns::default()
    };
    cols.note_positions("x", "float64");
    for (attr, p) in files {
        let (k, v) = parse(&read_file(&p)?).map_err(|m| format_error(&p, FORMAT, m))?;
        if v.len() / k != n {
            return Err(format_error(
                &p,
                FORMAT,
                format!("count {} disagrees with x_bin's {n} particles", v.len() / k),
            ));
        }
        let normal_name = match &opts.normal_attr {
            Some(p) => *p == attr,
            None => FRAME_NORMAL_ALIASES.contains(&attr.as_str()),
        };
        if normal_name && k == 1 && n > 0 {
            return Err(format_error(
                &p,
                FORMAT,
                format!(
                    "holds {n} scalars, but '{attr}' names normals (3 values per particle); \
                     a vector file cut to 4 + 8n bytes looks like this"
                ),
            ));
        }
        cols.push(&attr, k, "float64", v);
    }
    cols.into_cloud(opts, &ALIASES)
        .map_err(|m| format_error(dir, FORMAT, m))
}

/// Decodes one `*_bin` file's content already in memory: returns (components per particle,
/// 1 or 3; the values as f32). `path` only names the file in errors. Never panics.
///
/// # Errors
/// [`Error::Format`] naming `path` if the size fits neither layout.
pub fn read_bin_bytes(bytes: &[u8], path: &Path) -> Result<(usize, Vec<f32>)> {
    parse(bytes).map_err(|m| format_error(path, FORMAT, m))
}

/// Decodes one `*_bin` file: returns (components, values as f32). An empty file body
/// (count 0) reads as scalar.
fn parse(bytes: &[u8]) -> std::result::Result<(usize, Vec<f32>), String> {
    let Some((head, body)) = bytes.split_first_chunk::<4>() else {
        return Err(format!(
            "{} bytes: shorter than its 4-byte count",
            bytes.len()
        ));
    };
    let n = u64::from(u32::from_le_bytes(*head));
    let have = body.len() as u64;
    let k = if have == 8 * n {
        1
    } else if have == 24 * n {
        3
    } else if have < 8 * n {
        return Err(format!(
            "truncated: count {n} needs {} bytes (scalars) or {} (vectors) after the count, \
             the file has {have}: data runs out at value {} (byte offset {})",
            8 * n,
            24 * n,
            have / 8,
            4 + have / 8 * 8
        ));
    } else if have < 24 * n {
        return Err(format!(
            "truncated or malformed: count {n} needs {} bytes (scalars) or {} (vectors) after \
             the count, the file has {have}: as vectors the data runs out at particle {} \
             (byte offset {})",
            8 * n,
            24 * n,
            have / 24,
            4 + have / 24 * 24
        ));
    } else {
        return Err(format!(
            "size {} bytes matches neither 4 + 8n = {} (scalars) nor 4 + 24n = {} (vectors) \
             for its count n = {n}",
            bytes.len(),
            4 + 8 * n,
            4 + 24 * n
        ));
    };
    let v = body
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])) as f32)
        .collect();
    Ok((k, v))
}

#[cfg(test)]
mod tests {
    use super::parse;

    fn file(n: u32, vals: &[f64]) -> Vec<u8> {
        let mut b = n.to_le_bytes().to_vec();
        vals.iter().for_each(|v| b.extend(v.to_le_bytes()));
        b
    }

    #[test]
    fn layouts() {
        assert_eq!(parse(&file(2, &[1.0, 2.0])).unwrap(), (1, vec![1.0, 2.0]));
        let (k, v) = parse(&file(1, &[1.0, 2.0, 3.0])).unwrap();
        assert_eq!((k, v.len()), (3, 3));
        assert_eq!(parse(&file(0, &[])).unwrap(), (1, vec![]));
        let e = parse(&file(3, &[1.0, 2.0])).unwrap_err();
        assert!(e.contains("truncated") && e.contains("value 2"), "{e}");
        let e = parse(&file(1, &[1.0, 2.0])).unwrap_err();
        assert!(e.contains("runs out at particle 0"), "{e}");
        let e = parse(&file(1, &[1.0, 2.0, 3.0, 4.0])).unwrap_err();
        assert!(e.contains("neither"), "{e}");
        assert!(parse(&[1, 0]).unwrap_err().contains("4-byte count"));
        let e = parse(&file(u32::MAX, &[1.0])).unwrap_err();
        assert!(e.contains("truncated"), "{e}");
    }
}
