//! The one shell every particle reader shares: options checked once, the file's bytes (or a
//! pipe's) read once, the format picked, then that format's reader from its row of
//! [`FORMATS`](super::formats::FORMATS). The formats themselves only parse.

use std::path::Path;

use super::formats::{Described, Reader, by_content, detect_format, info, sniffed_names};
use super::part::{CloudPart, PartKind, film_of};
use super::{CloudFormat, ReadOptions, format_error, input, read_file};
use crate::error::Result;
use crate::pointcloud::PointCloud;

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
    // A pipe or standard input is read once, as a single set.
    let stream = input::is_stream(path);
    let format = if stream {
        None
    } else {
        Some(detect_format(path)?)
    };
    let droplets = match format.map(|f| info(f).reader) {
        Some(Reader::Folder { parts, .. }) => return parts(path, opts),
        Some(Reader::Collection(files)) => return collection_parts(files, path, 0, opts),
        Some(Reader::Streamed { droplets, .. }) => droplets(path)?,
        Some(Reader::Bytes(_)) | None => false,
    };
    let (cloud, stored) = read_cloud_described(path, opts)?;
    let mut part = CloudPart::film(path.display().to_string(), cloud, stored);
    if droplets {
        part.kind = PartKind::Droplets;
    }
    Ok(vec![part])
}

/// The parts of every data set of the `.pvd` collection's `k`-th timestep (0-based).
///
/// # Errors
/// As [`super::pvd::timestep_files`] and the data sets' readers.
pub fn read_timestep(path: &Path, k: usize, opts: &ReadOptions) -> Result<Vec<CloudPart>> {
    collection_parts(super::pvd::timestep_files, path, k, opts)
}

/// The parts of every file of a collection's `k`-th timestep, `files` listing them.
fn collection_parts(
    files: fn(&Path, usize) -> Result<Vec<std::path::PathBuf>>,
    path: &Path,
    k: usize,
    opts: &ReadOptions,
) -> Result<Vec<CloudPart>> {
    let mut parts = Vec::new();
    for f in files(path, k)? {
        parts.extend(read_parts(&f, opts)?);
    }
    Ok(parts)
}

/// [`read_as`] with the options checked.
fn read_checked(format: CloudFormat, path: &Path, opts: &ReadOptions) -> Result<Described> {
    match info(format).reader {
        Reader::Streamed { file, .. } => file(path, opts),
        Reader::Folder {
            film: Some(film), ..
        } => film(path, opts),
        Reader::Folder { film: None, .. } | Reader::Collection(_) => {
            Ok(film_of(read_parts(path, opts)?))
        }
        Reader::Bytes(_) => parse_bytes(format, &read_file(path)?, path, opts),
    }
}

/// [`read_bytes`] with the options checked.
fn parse_bytes(
    format: CloudFormat,
    bytes: &[u8],
    path: &Path,
    opts: &ReadOptions,
) -> Result<Described> {
    match info(format).reader {
        Reader::Streamed { bytes: parse, .. } => parse(bytes, path, opts),
        Reader::Bytes(parse) => {
            parse(bytes, opts).map_err(|m| format_error(path, format.name(), m))
        }
        Reader::Folder { .. } | Reader::Collection(_) => {
            Err(format_error(path, "input", "not a folder"))
        }
    }
}

/// A stream's first bytes are acceptable if they (or the path's extension) name a format.
fn stream_head_ok(path: &Path) -> impl Fn(&[u8]) -> std::result::Result<(), String> + '_ {
    move |head: &[u8]| {
        by_content(head, path).map(|_| ()).map_err(|e| match e {
            crate::Error::Format { message, .. } if message.starts_with("gzip-compressed") => {
                message
            }
            _ => format!(
                "its first bytes are not {} (a pipe's format is told from its content)",
                sniffed_names()
            ),
        })
    }
}
