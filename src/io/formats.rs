//! The one table of particle formats ([`FORMATS`]): per format its name, extensions, how its
//! content is recognised, its reader, how its size is estimated before reading (for
//! `--max-memory`) and its help text. Detection ([`detect_format`]), reading
//! ([`crate::io::read_cloud`], [`crate::io::read_parts`]), peeking ([`crate::io::peek_count`])
//! and the lists of known formats in messages all go through it.
//!
//! Adding a format: its reader in a file of its own (`io/NAME.rs`), a [`CloudFormat`] variant
//! (the compiler then points to [`info`]) and one row here. The tests check that every
//! variant has its row, every row an extension or a folder test, a help line, and that the
//! CLI's help names every extension.

use std::io::Read;
use std::path::{Path, PathBuf};

use super::{CloudFormat, CloudPart, ReadOptions, StoredAttribute, input};
use super::{bgeo, csv, folder_hint, frame_folder, melp_folder, ply, pvd, snapshot, vtk, vtu};
use crate::error::{Error, Result};
use crate::pointcloud::PointCloud;

/// A cloud and what its file stores.
pub(crate) type Described = (PointCloud, Vec<StoredAttribute>);

/// A format's parse of a whole file in memory: the cloud and what the file stores, or what is
/// wrong (without the file's name, which the caller adds). Options are already checked.
pub(crate) type Parse = fn(&[u8], &ReadOptions) -> std::result::Result<Described, String>;

/// Reads a path (options already checked).
type PathRead = fn(&Path, &ReadOptions) -> Result<Described>;
/// Reads a path's particle sets (options already checked).
type PartsRead = fn(&Path, &ReadOptions) -> Result<Vec<CloudPart>>;

/// How a format's content is recognised.
#[derive(Debug, Clone, Copy)]
pub enum Recognise {
    /// A file starting with one of these prefixes (for gzip data, its inflated start), else a
    /// file with one of the format's extensions.
    Magic(&'static [&'static [u8]]),
    /// A file with one of the format's extensions, once its content named no format (text).
    Extension,
    /// A file with one of the format's extensions, before its content is looked at (a `.pvd`
    /// is XML, like a VTK XML file).
    ExtensionFirst,
    /// A directory for which this test is true.
    Folder(fn(&Path) -> bool),
}

/// How a format is read.
#[derive(Debug, Clone, Copy)]
pub enum Reader {
    /// Read whole into memory (or from a pipe), then parsed.
    Bytes(Parse),
    /// Streamed from the file in chunks (a pipe's bytes are parsed from memory); `droplets`
    /// says whether the file's set is droplets rather than film.
    Streamed {
        /// Reads the file.
        file: PathRead,
        /// Parses a pipe's bytes; the path only names it in errors.
        bytes: fn(&[u8], &Path, &ReadOptions) -> Result<Described>,
        /// True if the file holds droplets.
        droplets: fn(&Path) -> Result<bool>,
    },
    /// A folder of several particle sets.
    Folder {
        /// Every set (film, droplets, bubbles).
        parts: PartsRead,
        /// The film alone, where the format reads it without the other sets (else the films
        /// of `parts`).
        film: Option<PathRead>,
    },
    /// A collection naming other files per timestep: the files of timestep `k` (0-based).
    Collection(fn(&Path, usize) -> Result<Vec<PathBuf>>),
}

/// How a format's particle count is estimated from a file's start, before it is read.
#[derive(Debug, Clone, Copy)]
pub enum SizeEstimate {
    /// The count its header states (`None` without one: file size over 12 bytes).
    Header(fn(&[u8]) -> Option<u64>),
    /// File size over the length of the first data lines.
    TextLines,
    /// The little-endian `u32` count at the start of this file of the folder (capped by that
    /// file's size at `bytes_each` a particle); the folder's bytes over 12 without it.
    CountFile {
        /// The file holding the count.
        file: &'static str,
        /// Bytes a particle in that file after its 4-byte count.
        bytes_each: u64,
    },
    /// The folder's bytes (with its subfolders') over 12.
    FolderBytes,
    /// The sum over the first timestep's files.
    Collection,
}

/// One row of the table.
#[derive(Debug, Clone, Copy)]
pub struct FormatInfo {
    /// The format.
    pub format: CloudFormat,
    /// Display name, e.g. `PLY`.
    pub name: &'static str,
    /// File name endings, lower case, without the dot (`bgeo.gz`); none for folders.
    pub extensions: &'static [&'static str],
    /// How its content is recognised.
    pub recognise: Recognise,
    /// Its reader.
    pub reader: Reader,
    /// How its size is estimated before reading.
    pub size: SizeEstimate,
    /// One line for help texts.
    pub help: &'static str,
}

/// Every format, in the order detection tries them.
pub const FORMATS: &[FormatInfo] = &[
    FormatInfo {
        format: CloudFormat::Ply,
        name: "PLY",
        extensions: &["ply"],
        recognise: Recognise::Magic(&[b"ply\n", b"ply\r"]),
        reader: Reader::Streamed {
            file: ply::read_file,
            bytes: ply::parse_bytes,
            droplets: ply::holds_droplets,
        },
        size: SizeEstimate::Header(ply::header_count),
        help: "Stanford PLY (ASCII, binary little or big endian)",
    },
    FormatInfo {
        format: CloudFormat::VtkLegacy,
        name: "VTK legacy",
        extensions: &["vtk"],
        recognise: Recognise::Magic(&[b"# vtk DataFile"]),
        reader: Reader::Bytes(vtk::parse),
        size: SizeEstimate::Header(vtk::header_count),
        help: "VTK legacy (ASCII, binary)",
    },
    FormatInfo {
        format: CloudFormat::VtkXml,
        name: "VTK XML",
        extensions: &["vtu", "vtp"],
        recognise: Recognise::Magic(&[b"<?xml", b"<VTKFile"]),
        reader: Reader::Bytes(vtu::parse),
        size: SizeEstimate::Header(vtu::header_count),
        help: "VTK XML unstructured grid or poly data (ascii, base64, appended, zlib)",
    },
    FormatInfo {
        format: CloudFormat::Bgeo,
        name: "BGEO",
        extensions: &["bgeo", "bgeo.gz"],
        recognise: Recognise::Magic(&[b"Bgeo", b"\x7fNSJ"]),
        reader: Reader::Bytes(bgeo::parse),
        size: SizeEstimate::Header(bgeo::header_count),
        help: "Houdini classic BGEO V5, plain or gzip-compressed",
    },
    FormatInfo {
        format: CloudFormat::Csv,
        name: "CSV",
        extensions: &["csv", "tsv", "xyz", "txt"],
        recognise: Recognise::Extension,
        reader: Reader::Bytes(csv::parse),
        size: SizeEstimate::TextLines,
        help: "delimited text with a header line naming the columns",
    },
    FormatInfo {
        format: CloudFormat::FrameFolder,
        name: "frame folder",
        extensions: &[],
        recognise: Recognise::Folder(frame_folder::is_frame_folder),
        reader: Reader::Folder {
            parts: frame_folder::read_parts,
            film: Some(frame_folder::read_checked),
        },
        size: SizeEstimate::CountFile {
            file: "x_bin",
            bytes_each: 24,
        },
        help: "thin-film SPH frame folder (x_bin, norm_bin, rh_bin, ...; droplets in *_3d)",
    },
    FormatInfo {
        format: CloudFormat::SnapshotFolder,
        name: "snapshot folder",
        extensions: &[],
        recognise: Recognise::Folder(snapshot::is_snapshot_folder),
        reader: Reader::Folder {
            parts: snapshot::read_parts,
            film: None,
        },
        size: SizeEstimate::FolderBytes,
        help: "thin-film SPH snapshot folder (x.bin, e.bin, rh.bin, ...; droplets in 3d/)",
    },
    FormatInfo {
        format: CloudFormat::MelpFolder,
        name: "MELP frame folder",
        extensions: &[],
        recognise: Recognise::Folder(melp_folder::is_melp_folder),
        reader: Reader::Folder {
            parts: melp_folder::read_parts,
            film: None,
        },
        size: SizeEstimate::FolderBytes,
        help: "MELP foam frame folder (l_tracker_points_R, l_h_bin_R, ... per bubble R)",
    },
    FormatInfo {
        format: CloudFormat::Pvd,
        name: "PVD collection",
        extensions: &["pvd"],
        recognise: Recognise::ExtensionFirst,
        reader: Reader::Collection(pvd::timestep_files),
        size: SizeEstimate::Collection,
        help: "ParaView .pvd collection of VTK XML files (its first timestep)",
    },
];

/// The row of `format`.
pub fn info(format: CloudFormat) -> &'static FormatInfo {
    // Exhaustive: a new format fails to compile here until it has a row.
    let row = match format {
        CloudFormat::Ply => 0,
        CloudFormat::VtkLegacy => 1,
        CloudFormat::VtkXml => 2,
        CloudFormat::Bgeo => 3,
        CloudFormat::Csv => 4,
        CloudFormat::FrameFolder => 5,
        CloudFormat::SnapshotFolder => 6,
        CloudFormat::MelpFolder => 7,
        CloudFormat::Pvd => 8,
    };
    &FORMATS[row]
}

/// The known formats for a message: `PLY (.ply), ..., frame folder, ...`.
pub fn known_formats() -> String {
    let rows = FORMATS.iter().map(|f| match f.extensions {
        [] => f.name.to_string(),
        exts => {
            let exts: Vec<String> = exts.iter().map(|e| format!(".{e}")).collect();
            format!("{} ({})", f.name, exts.join(", "))
        }
    });
    rows.collect::<Vec<_>>().join(", ")
}

/// The names of the formats told by their first bytes (what a pipe may hold).
pub(crate) fn sniffed_names() -> String {
    let names: Vec<&str> = FORMATS
        .iter()
        .filter(|f| matches!(f.recognise, Recognise::Magic(_)))
        .map(|f| f.name)
        .collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

/// The format named by a file's first bytes, if any.
fn sniff(head: &[u8]) -> Option<CloudFormat> {
    FORMATS.iter().find_map(|f| match f.recognise {
        Recognise::Magic(m) => m.iter().any(|p| head.starts_with(p)).then_some(f.format),
        _ => None,
    })
}

/// True if `path`'s file name ends with one of `f`'s extensions (case-insensitive).
fn has_extension(path: &Path, f: &FormatInfo) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    f.extensions
        .iter()
        .any(|e| name.strip_suffix(e).is_some_and(|s| s.ends_with('.')))
}

/// The format a path's extension names among the formats told by content or extension (not
/// `.pvd`, decided before the content), if any.
pub(crate) fn by_extension(path: &Path) -> Option<CloudFormat> {
    FORMATS
        .iter()
        .filter(|f| matches!(f.recognise, Recognise::Magic(_) | Recognise::Extension))
        .find(|f| has_extension(path, f))
        .map(|f| f.format)
}

/// The format told by a file's first bytes (inflating the start of gzip data), else by the
/// extension of `path`.
pub(crate) fn by_content(head: &[u8], path: &Path) -> Result<CloudFormat> {
    let unknown = |message: String| Error::Format {
        path: path.to_path_buf(),
        format: "particle file",
        message,
    };
    if let Some(f) = sniff(head) {
        return Ok(f);
    }
    if head.starts_with(&[0x1f, 0x8b]) {
        let mut inner = Vec::with_capacity(16);
        let _ = flate2::read::GzDecoder::new(head)
            .take(16)
            .read_to_end(&mut inner);
        match sniff(&inner) {
            Some(CloudFormat::Bgeo) => return Ok(CloudFormat::Bgeo),
            Some(f) => {
                return Err(unknown(format!(
                    "gzip-compressed {} is not supported (only BGEO); decompress it first",
                    f.name()
                )));
            }
            None => {}
        }
    }
    by_extension(path).ok_or_else(|| {
        unknown(if head.is_empty() {
            "empty file".to_string()
        } else {
            format!("unrecognised format (supported: {})", known_formats())
        })
    })
}

/// The message for a directory that is no frame folder, with what it holds if that is a
/// numbered run of frame folders or particle files ([`folder_hint`]).
fn not_a_frame_folder(path: &Path) -> String {
    let base = "a directory that is no simulator frame folder (expected x_bin or tracker_points \
                of the thin-film SPH code, x.bin of its snapshots, or MELP's l_tracker_points_0)";
    let is_frame = |p: &Path| {
        FORMATS
            .iter()
            .any(|f| matches!(f.recognise, Recognise::Folder(is) if is(p)))
    };
    let is_file = |p: &Path| FORMATS.iter().any(|f| has_extension(p, f));
    match folder_hint::hint(path, is_frame, is_file) {
        Some(h) => format!("{base}; {h}"),
        None => base.to_string(),
    }
}

/// Decides a file's format: a directory by the files it holds (a frame folder holds `x_bin`
/// or `tracker_points`, a snapshot folder `x.bin`, a MELP folder `l_tracker_points_0`); a
/// `.pvd` by its extension; another file by its first bytes (for gzip, the decompressed first
/// bytes), else by its extension (case-insensitive: ply, vtk, vtu, vtp, bgeo, bgeo.gz, csv,
/// tsv, xyz, txt). See [`FORMATS`].
///
/// A pipe or standard input (`-`) is not opened (its bytes can be read only once;
/// [`crate::io::read_cloud`] tells its format from them): only its extension can decide here.
///
/// Cost: opens the file and reads (and, for gzip, inflates) at most a few hundred bytes.
///
/// # Errors
/// [`Error::Io`] if the path cannot be opened; [`Error::Format`] if neither the content nor
/// the extension is a known format, a directory is no simulator folder, the path is a device
/// or a socket, or a pipe's name has no known extension.
pub fn detect_format(path: &Path) -> Result<CloudFormat> {
    let unknown = |message: &str| Error::Format {
        path: path.to_path_buf(),
        format: "particle file",
        message: message.to_string(),
    };
    match input::kind(path)? {
        input::Kind::Dir => {
            return FORMATS
                .iter()
                .find(|f| matches!(f.recognise, Recognise::Folder(is) if is(path)))
                .map(|f| f.format)
                .ok_or_else(|| unknown(&not_a_frame_folder(path)));
        }
        input::Kind::Stdin | input::Kind::Pipe => {
            return by_extension(path)
                .ok_or_else(|| unknown("a pipe's format is told from its bytes when it is read"));
        }
        input::Kind::File(_) => {}
    }
    if let Some(f) = FORMATS
        .iter()
        .find(|f| matches!(f.recognise, Recognise::ExtensionFirst) && has_extension(path, f))
    {
        return Ok(f.format);
    }
    // 4 KiB: enough to inflate the first bytes of gzip data.
    let mut head = Vec::with_capacity(4096);
    std::fs::File::open(path)
        .and_then(|f| f.take(4096).read_to_end(&mut head))
        .map_err(|e| Error::io(path, e))?;
    by_content(&head, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every variant, for the checks below (a new one added here and not to [`info`] fails
    /// to compile there; one added to neither is caught by the length check).
    const ALL: [CloudFormat; 9] = [
        CloudFormat::Ply,
        CloudFormat::VtkLegacy,
        CloudFormat::VtkXml,
        CloudFormat::Bgeo,
        CloudFormat::Csv,
        CloudFormat::FrameFolder,
        CloudFormat::SnapshotFolder,
        CloudFormat::MelpFolder,
        CloudFormat::Pvd,
    ];

    #[test]
    fn every_format_has_one_complete_row() {
        assert_eq!(FORMATS.len(), ALL.len());
        for f in ALL {
            let row = info(f);
            assert_eq!(row.format, f, "info({f:?}) is another format's row");
            assert_eq!(FORMATS.iter().filter(|r| r.format == f).count(), 1);
            assert!(!row.help.is_empty() && !row.name.is_empty(), "{f:?}");
            let folder = matches!(row.recognise, Recognise::Folder(_));
            assert_eq!(
                row.extensions.is_empty(),
                folder,
                "{f:?}: extensions or folder"
            );
            assert_eq!(
                matches!(row.reader, Reader::Folder { .. }),
                folder,
                "{f:?}: a folder format reads folders"
            );
            for e in row.extensions {
                assert_eq!(*e, e.to_ascii_lowercase(), "{f:?}");
                let p = PathBuf::from(format!("Frame_01.{}", e.to_ascii_uppercase()));
                if !matches!(row.recognise, Recognise::ExtensionFirst) {
                    assert_eq!(by_extension(&p), Some(f), "{e}");
                }
            }
        }
    }

    #[test]
    fn magic_and_extensions_decide() {
        assert_eq!(sniff(b"ply\nformat"), Some(CloudFormat::Ply));
        assert_eq!(
            sniff(b"# vtk DataFile Version"),
            Some(CloudFormat::VtkLegacy)
        );
        assert_eq!(sniff(b"<VTKFile type"), Some(CloudFormat::VtkXml));
        assert_eq!(sniff(b"BgeoV"), Some(CloudFormat::Bgeo));
        assert_eq!(sniff(b"x,y,z\n"), None);
        assert_eq!(
            by_extension(Path::new("a.bgeo.gz")),
            Some(CloudFormat::Bgeo)
        );
        assert_eq!(by_extension(Path::new("a.gz")), None);
        assert_eq!(by_extension(Path::new("a.pvd")), None);
        assert_eq!(by_extension(Path::new("ply")), None);
        assert_eq!(sniffed_names(), "PLY, VTK legacy, VTK XML or BGEO");
        let known = known_formats();
        assert!(
            known.starts_with("PLY (.ply), VTK legacy (.vtk)"),
            "{known}"
        );
        assert!(known.contains("MELP frame folder"), "{known}");
    }

    /// The CLI's help of its inputs names every extension of the table.
    #[test]
    fn the_cli_help_names_every_extension() {
        let help = include_str!("../cli/render_args.rs");
        let start = help.find("/// Particle inputs").expect("the inputs' help");
        let help = &help[start..start + 700];
        for f in FORMATS {
            for e in f.extensions {
                let tail = e.rsplit('.').next().unwrap_or(e);
                assert!(help.contains(&format!(".{tail}")), "{e} missing in: {help}");
            }
        }
    }
}
