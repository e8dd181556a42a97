//! Readers: particle files in, [`PointCloud`] out.
//!
//! [`read_cloud`] picks the reader from the file's first bytes (magic) or else its extension.
//! Only PLY exists today ([`ply`]); new formats add a [`CloudFormat`] variant and a match arm.
//!
//! Attribute names: positions are always `x y z`. Normals, thickness and radius are found by
//! the first present name in [`NORMAL_ALIASES`], [`THICKNESS_ALIASES`] and [`RADIUS_ALIASES`],
//! unless [`ReadOptions`] names them explicitly (then a missing name is an error). Every other
//! scalar attribute lands in [`PointCloud::extra`]. Readers do not validate values.

pub mod ply;
mod write_ply;

pub use write_ply::write_ply;

use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};
use crate::pointcloud::PointCloud;

/// Thickness attribute names tried in order: `rh` (film thickness), `thickness`, `h`.
/// Beware that SPH files often use `h` for the smoothing length; name the attribute
/// explicitly ([`ReadOptions::thickness_attr`]) if so.
pub const THICKNESS_ALIASES: &[&str] = &["rh", "thickness", "h"];

/// Normal attribute prefixes tried in order; a prefix `p` means the three attributes `px py pz`
/// or `p_x p_y p_z`: `n` → `nx ny nz`, `normal` → `normal_x normal_y normal_z`.
pub const NORMAL_ALIASES: &[&str] = &["n", "normal"];

/// Radius attribute names tried in order: `radius`, `pscale` (Houdini's per-point scale).
pub const RADIUS_ALIASES: &[&str] = &["radius", "pscale"];

/// How to read a particle file.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadOptions {
    /// Factor turning the file's thickness values into nanometres: 1 for nm, 1e3 for µm,
    /// 1e9 for m. Must be finite and positive. Default 1.
    pub thickness_scale_to_nm: f64,
    /// Thickness attribute name; `None` tries [`THICKNESS_ALIASES`].
    pub thickness_attr: Option<String>,
    /// Normal attribute prefix (`"n"` → `nx ny nz`, `"normal"` → `normal_x ..`); `None` tries
    /// [`NORMAL_ALIASES`].
    pub normal_attr: Option<String>,
    /// Radius attribute name; `None` tries [`RADIUS_ALIASES`].
    pub radius_attr: Option<String>,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            thickness_scale_to_nm: 1.0,
            thickness_attr: None,
            normal_attr: None,
            radius_attr: None,
        }
    }
}

impl ReadOptions {
    /// Checks the options themselves (not the file).
    ///
    /// # Errors
    /// [`Error::Invalid`] if `thickness_scale_to_nm` is not finite and positive.
    pub fn check(&self) -> Result<()> {
        let s = self.thickness_scale_to_nm;
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::invalid(format!(
                "thickness scale to nm must be finite and positive, got {s}"
            )));
        }
        Ok(())
    }
}

/// A particle file format filmsplat can read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum CloudFormat {
    /// Stanford PLY (ASCII or binary), read by [`ply::read`].
    Ply,
}

impl CloudFormat {
    /// Display name, e.g. `"PLY"`.
    pub fn name(self) -> &'static str {
        match self {
            CloudFormat::Ply => "PLY",
        }
    }
}

/// Decides a file's format from its first bytes, else from its extension (case-insensitive).
///
/// Cost: opens the file and reads at most 16 bytes.
///
/// # Errors
/// [`Error::Io`] if the path cannot be opened or is a directory; [`Error::Format`] if neither
/// the content nor the extension is a known format.
pub fn detect_format(path: &Path) -> Result<CloudFormat> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        let e = std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a directory");
        return Err(Error::io(path, e));
    }
    let mut head = Vec::with_capacity(16);
    std::fs::File::open(path)
        .and_then(|f| f.take(16).read_to_end(&mut head))
        .map_err(|e| Error::io(path, e))?;
    if head.starts_with(b"ply\n") || head.starts_with(b"ply\r") {
        return Ok(CloudFormat::Ply);
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("ply") => Ok(CloudFormat::Ply),
        _ => Err(Error::Format {
            path: path.to_path_buf(),
            format: "particle file",
            message: if head.is_empty() {
                "empty file".to_string()
            } else {
                "unrecognised format (supported: PLY)".to_string()
            },
        }),
    }
}

/// Reads a particle file of any supported format (see [`detect_format`]).
///
/// Cost: one pass over the file (plus a 16-byte sniff); about the cost of reading its bytes.
///
/// # Errors
/// As [`detect_format`] and the format's reader (e.g. [`ply::read`]): every error names the
/// file, the format and the problem.
pub fn read_cloud(path: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    match detect_format(path)? {
        CloudFormat::Ply => ply::read(path, opts),
    }
}
