//! The one shell every particle reader shares: options checked once, the file's bytes (or a
//! pipe's) read once, the format picked, then that format's parse function. The formats
//! themselves (`ply`, `vtk`, `vtu`, `bgeo`, `csv`) only parse.

use std::path::Path;

use super::part::{CloudPart, PartKind, film_of};
use super::{
    CloudFormat, ReadOptions, StoredAttribute, bgeo, by_content, csv, detect_format, format_error,
    frame_folder, input, melp_folder, ply, pvd, read_file, snapshot, vtk, vtu,
};
use crate::error::Result;
use crate::pointcloud::PointCloud;

/// A cloud and what its file stores.
type Described = (PointCloud, Vec<StoredAttribute>);

/// A format's parse of a whole file in memory: the cloud and what the file stores, or what is
/// wrong (without the file's name, which the shell adds). Options are already checked.
type Parse = fn(&[u8], &ReadOptions) -> std::result::Result<Described, String>;

/// The parse of a format read whole from memory; `None` for folders and collections.
fn parse_of(format: CloudFormat) -> Option<Parse> {
    match format {
        CloudFormat::VtkLegacy => Some(vtk::parse),
        CloudFormat::VtkXml => Some(vtu::parse),
        CloudFormat::Bgeo => Some(bgeo::parse),
        CloudFormat::Csv => Some(csv::parse),
        CloudFormat::Ply
        | CloudFormat::FrameFolder
        | CloudFormat::SnapshotFolder
        | CloudFormat::MelpFolder
        | CloudFormat::Pvd => None,
    }
}

/// Reads a particle file (or frame folder) of any supported format (see [`detect_format`]).
/// Standard input (`-`) and pipes are read once into memory (at most
/// [`input::STREAM_LIMIT_BYTES`]) and their format is told from their first bytes.
///
/// Cost: about the cost of reading the file's bytes (plus inflating them if compressed).
///
/// # Errors
/// As [`detect_format`] and the format's reader: every error names the file, the format and
/// the problem.
///
/// # Example
/// A three-particle ASCII PLY with a thickness column (nanometres, the default unit):
/// ```
/// use filmsplat::io::{ReadOptions, read_cloud};
/// let dir = std::env::temp_dir().join(format!("filmsplat-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("three.ply");
/// std::fs::write(
///     &path,
///     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
///      property float z\nproperty float thickness\nend_header\n\
///      0 0 0 500\n1 0 0 520\n0 1 0 540\n",
/// )?;
/// let cloud = read_cloud(&path, &ReadOptions::default())?;
/// assert_eq!(cloud.len(), 3);
/// assert_eq!(cloud.positions[1], glam::Vec3::X);
/// assert_eq!(cloud.thickness_nm.as_deref(), Some(&[500.0, 520.0, 540.0][..]));
/// // A truncated file is an error naming the file, not a panic.
/// std::fs::write(&path, "ply\nformat ascii 1.0\nelement vertex 3\n")?;
/// let err = read_cloud(&path, &ReadOptions::default()).unwrap_err();
/// assert!(err.to_string().contains("three.ply"), "{err}");
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_cloud(path: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    read_cloud_described(path, opts).map(|(c, _)| c)
}

/// Reads a particle file like [`read_cloud`] and also says what the file stores: every
/// attribute with its stored type and what filmsplat read it as (for `filmsplat info`).
pub fn read_cloud_described(path: &Path, opts: &ReadOptions) -> Result<Described> {
    opts.check()?;
    if input::is_stream(path) {
        let bytes = input::read_all(path, &stream_head_ok(path))?;
        let format = by_content(&bytes, path)?;
        return parse_bytes(format, &bytes, path, opts);
    }
    read_checked(detect_format(path)?, path, opts)
}

/// Reads the file (or folder) at `path` as `format`, without looking at its content to pick
/// one: for a caller that knows the format (a test of one reader, a fuzzer).
///
/// # Errors
/// As [`read_cloud`].
pub fn read_as(format: CloudFormat, path: &Path, opts: &ReadOptions) -> Result<Described> {
    opts.check()?;
    read_checked(format, path, opts)
}

/// Reads a particle file's content already in memory as `format`; `path` only names the source
/// in errors. Never panics, whatever the bytes.
///
/// # Errors
/// As [`read_cloud`], without the I/O errors; [`crate::Error::Format`] for a folder format.
pub fn read_bytes(
    format: CloudFormat,
    bytes: &[u8],
    path: &Path,
    opts: &ReadOptions,
) -> Result<Described> {
    opts.check()?;
    parse_bytes(format, bytes, path, opts)
}

/// Reads every particle set of `path` (a file, a frame or snapshot folder of the thin-film SPH
/// code, a MELP foam frame folder, or a `.pvd` collection). Single-set formats give one film
/// part. Parts may be empty (a film that has fully ruptured).
///
/// # Errors
/// As [`read_cloud`].
pub fn read_parts(path: &Path, opts: &ReadOptions) -> Result<Vec<CloudPart>> {
    // A pipe or standard input is read once, by the single-set readers.
    let format = if input::is_stream(path) {
        CloudFormat::Ply
    } else {
        detect_format(path)?
    };
    match format {
        CloudFormat::FrameFolder => frame_folder::read_parts(path, opts),
        CloudFormat::SnapshotFolder => snapshot::read_parts(path, opts),
        CloudFormat::MelpFolder => melp_folder::read_parts(path, opts),
        CloudFormat::Pvd => read_timestep(path, 0, opts),
        _ => {
            let droplets =
                format == CloudFormat::Ply && !input::is_stream(path) && ply::holds_droplets(path)?;
            let (cloud, stored) = read_cloud_described(path, opts)?;
            let mut part = CloudPart::film(path.display().to_string(), cloud, stored);
            if droplets {
                part.kind = PartKind::Droplets;
            }
            Ok(vec![part])
        }
    }
}

/// The parts of every data set of the `.pvd` collection's `k`-th timestep (0-based).
///
/// # Errors
/// As [`pvd::timestep_files`] and the data sets' readers.
pub fn read_timestep(path: &Path, k: usize, opts: &ReadOptions) -> Result<Vec<CloudPart>> {
    let mut parts = Vec::new();
    for f in pvd::timestep_files(path, k)? {
        parts.extend(read_parts(&f, opts)?);
    }
    Ok(parts)
}

/// [`read_as`] with the options checked.
fn read_checked(format: CloudFormat, path: &Path, opts: &ReadOptions) -> Result<Described> {
    match format {
        // PLY streams from the file in chunks instead of reading it whole.
        CloudFormat::Ply => ply::read_file(path, opts),
        CloudFormat::FrameFolder => frame_folder::read_checked(path, opts),
        CloudFormat::SnapshotFolder | CloudFormat::MelpFolder | CloudFormat::Pvd => {
            Ok(film_of(read_parts(path, opts)?))
        }
        f => parse_bytes(f, &read_file(path)?, path, opts),
    }
}

/// [`read_bytes`] with the options checked.
fn parse_bytes(
    format: CloudFormat,
    bytes: &[u8],
    path: &Path,
    opts: &ReadOptions,
) -> Result<Described> {
    if format == CloudFormat::Ply {
        return ply::parse_bytes(bytes, path, opts);
    }
    let parse = parse_of(format).ok_or_else(|| format_error(path, "input", "not a folder"))?;
    parse(bytes, opts).map_err(|m| format_error(path, format.name(), m))
}

/// A stream's first bytes are acceptable if they (or the path's extension) name a format.
fn stream_head_ok(path: &Path) -> impl Fn(&[u8]) -> std::result::Result<(), String> + '_ {
    move |head: &[u8]| {
        by_content(head, path).map(|_| ()).map_err(|e| match e {
            crate::Error::Format { message, .. } if message.starts_with("gzip-compressed") => {
                message
            }
            _ => "its first bytes are not PLY, VTK, VTK XML or BGEO (a pipe's format is told \
                  from its content)"
                .to_string(),
        })
    }
}
