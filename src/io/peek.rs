//! How many particles a file holds, from its header alone (for memory estimates before loading).

use std::io::Read;
use std::path::Path;

use super::CloudFormat;
use super::formats::{Reader, SizeEstimate, by_extension, detect_format, info};
use crate::error::{Error, Result};

/// Bytes of a file's start searched for a header count.
const HEAD_BYTES: u64 = 64 * 1024;

/// What a particle file's header says about its size, found without reading the body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CountHint {
    /// The file's format.
    pub format: CloudFormat,
    /// Number of particles: the header's count, or an estimate from the file size.
    pub particles: u64,
    /// True if `particles` is the count the header states; false if it is estimated from the
    /// file size (CSV/XYZ text, or a header without a count).
    pub exact: bool,
    /// Size on disk in bytes (for a frame folder, the sum of its `*_bin` files).
    pub file_bytes: u64,
    /// True if the reader holds the whole file in memory while parsing (every format but PLY,
    /// which streams).
    pub reads_whole_file: bool,
}

/// Peeks at `path` (file or frame folder): its format and particle count, reading at most
/// 64 KiB (for gzip BGEO, inflating at most 64 bytes). A pipe or standard input is not read:
/// its hint says 0 particles, not exact, format by extension (else PLY).
///
/// Header counts are capped at what the file size could hold (3 bytes a particle; gzip: the
/// deflate ratio limit), so an absurd header does not produce an absurd estimate. Without a
/// usable header count, the count is estimated as the file size over the length of the first
/// data lines (text) or over 12 bytes (three `f32` positions).
///
/// # Errors
/// As [`detect_format`]; [`Error::Io`] if the file cannot be read.
pub fn peek_count(path: &Path) -> Result<CountHint> {
    if super::input::is_stream(path) {
        // A pipe can be read only once: nothing is known before the reader reads it (its size
        // is bounded by `input::STREAM_LIMIT_BYTES`).
        return Ok(CountHint {
            format: by_extension(path).unwrap_or(CloudFormat::Ply),
            particles: 0,
            exact: false,
            file_bytes: 0,
            reads_whole_file: true,
        });
    }
    let format = detect_format(path)?;
    let header = match info(format).size {
        SizeEstimate::CountFile { file, bytes_each } if path.join(file).is_file() => {
            return peek_count_file(path, format, file, bytes_each);
        }
        SizeEstimate::CountFile { .. } | SizeEstimate::FolderBytes => {
            return peek_folder_bytes(path, format);
        }
        SizeEstimate::Collection => return peek_collection(path, format),
        SizeEstimate::Header(count) => Some(count),
        SizeEstimate::TextLines => None,
    };
    let file_bytes = std::fs::metadata(path)
        .map_err(|e| Error::io(path, e))?
        .len();
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(HEAD_BYTES).read_to_end(&mut head))
        .map_err(|e| Error::io(path, e))?;
    let gzip = head.starts_with(&[0x1f, 0x8b]);
    // Deflate expands at most ~1032:1; text needs at least "0 0 0\n" (6 bytes) a particle and
    // binary 12, so 3 bytes a particle bounds every uncompressed format.
    let cap = if gzip {
        file_bytes.saturating_mul(1032) / 3
    } else {
        file_bytes / 3
    };
    let (particles, exact) = match header.and_then(|count| count(&head)) {
        Some(n) => (n.min(cap), n <= cap),
        None if header.is_none() => (text_lines_estimate(&head, file_bytes), false),
        None => (file_bytes / 12, false),
    };
    Ok(CountHint {
        format,
        particles,
        exact,
        file_bytes,
        reads_whole_file: !matches!(info(format).reader, Reader::Streamed { .. }),
    })
}

/// A collection: the sum of the hints of its first timestep's files (the largest file held
/// whole, exact if every count is).
fn peek_collection(path: &Path, format: CloudFormat) -> Result<CountHint> {
    let Reader::Collection(files) = info(format).reader else {
        return peek_folder_bytes(path, format);
    };
    let mut hint = CountHint {
        format,
        particles: 0,
        exact: true,
        file_bytes: 0,
        reads_whole_file: false,
    };
    for f in files(path, 0)? {
        let h = peek_count(&f)?;
        hint.particles = hint.particles.saturating_add(h.particles);
        hint.exact &= h.exact;
        if h.reads_whole_file && h.file_bytes >= hint.file_bytes {
            hint.file_bytes = h.file_bytes;
            hint.reads_whole_file = true;
        }
    }
    Ok(hint)
}

/// File size over the mean length of the data lines in `head` (the first line is the header).
fn text_lines_estimate(head: &[u8], file_bytes: u64) -> u64 {
    let lines = head.iter().filter(|&&c| c == b'\n').count() as u64;
    if lines < 2 {
        return file_bytes / 6;
    }
    let mean = (head.len() as u64 / lines).max(1);
    file_bytes.div_ceil(mean)
}

/// A folder of simulator arrays without a count to peek at: every file's bytes, and at most
/// one particle per 12 of them (three `f32` coordinates), not exact.
fn peek_folder_bytes(dir: &Path, format: CloudFormat) -> Result<CountHint> {
    let mut file_bytes = 0u64;
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).map_err(|e| Error::io(&d, e))? {
            let entry = entry.map_err(|e| Error::io(&d, e))?;
            let Ok(meta) = entry.metadata() else { continue };
            if meta.is_dir() && d == dir {
                stack.push(entry.path());
            } else if meta.is_file() {
                file_bytes += meta.len();
            }
        }
    }
    Ok(CountHint {
        format,
        particles: file_bytes / 12,
        exact: false,
        file_bytes,
        reads_whole_file: true,
    })
}

/// A folder with a count file (a frame folder's `x_bin`): the little-endian `u32` at its
/// start, capped by its size at `bytes_each` a particle; the folder's bytes are its `*_bin`
/// files'.
fn peek_count_file(
    dir: &Path,
    format: CloudFormat,
    file: &str,
    bytes_each: u64,
) -> Result<CountHint> {
    let mut file_bytes = 0;
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        if entry.file_name().to_string_lossy().ends_with("_bin") {
            file_bytes += entry.metadata().map(|m| m.len()).unwrap_or(0);
        }
    }
    let x = dir.join(file);
    let x_bytes = std::fs::metadata(&x).map_err(|e| Error::io(&x, e))?.len();
    let mut head = Vec::with_capacity(4);
    std::fs::File::open(&x)
        .and_then(|f| f.take(4).read_to_end(&mut head))
        .map_err(|e| Error::io(&x, e))?;
    let cap = x_bytes.saturating_sub(4) / bytes_each;
    let (particles, exact) = match head.get(..4) {
        Some(b) => {
            let n = u64::from(u32::from_le_bytes(b.try_into().expect("4 bytes")));
            (n.min(cap), n <= cap)
        }
        None => (0, false),
    };
    Ok(CountHint {
        format,
        particles,
        exact,
        file_bytes,
        reads_whole_file: true,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_counts() {
        use crate::io::{bgeo, ply, vtk, vtu};
        let head = b"ply\nformat ascii 1.0\nelement vertex 1234\nproperty float x\nend_header\n";
        assert_eq!(ply::header_count(head), Some(1234));
        assert_eq!(
            vtu::header_count(b"<Piece NumberOfPoints=\"250\" "),
            Some(250)
        );
        assert_eq!(vtk::header_count(b"POINTS  77 float\n"), Some(77));
        assert_eq!(vtk::header_count(b"POINTS x"), None);
        let mut b = b"BgeoV".to_vec();
        b.extend(5i32.to_be_bytes());
        b.extend(6859i32.to_be_bytes());
        assert_eq!(bgeo::header_count(&b), Some(6859));
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        std::io::Write::write_all(&mut gz, &b).unwrap();
        assert_eq!(bgeo::header_count(&gz.finish().unwrap()), Some(6859));
        b[9..13].copy_from_slice(&(-1i32).to_be_bytes());
        assert_eq!(bgeo::header_count(&b), None);
        // 10 data lines of 10 bytes after an 10-byte header: a 1000-byte file holds ~100 lines.
        let text = b"x,y,z,abc\n".repeat(11);
        assert_eq!(text_lines_estimate(&text, 1000), 100);
    }

    /// A collection's estimate is its first timestep's files' (the XML's own size said
    /// nothing: 250-particle files named twice were ~0 particles, not exact).
    #[test]
    fn a_collection_sums_its_first_timestep() {
        let dir = std::env::temp_dir().join(format!("filmsplat-peek-pvd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        std::fs::copy(data.join("fluid_250_particles.vtu"), dir.join("a.vtu")).unwrap();
        let pvd = dir.join("run.pvd");
        std::fs::write(
            &pvd,
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\"><Collection>\n\
             <DataSet timestep=\"0\" part=\"0\" file=\"a.vtu\"/>\n\
             <DataSet timestep=\"0\" part=\"1\" file=\"a.vtu\"/>\n\
             <DataSet timestep=\"1\" part=\"0\" file=\"a.vtu\"/>\n\
             </Collection></VTKFile>\n",
        )
        .unwrap();
        let hint = peek_count(&pvd).unwrap();
        let vtu_bytes = std::fs::metadata(dir.join("a.vtu")).unwrap().len();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(hint.format, CloudFormat::Pvd);
        assert_eq!((hint.particles, hint.exact), (500, true));
        assert_eq!((hint.file_bytes, hint.reads_whole_file), (vtu_bytes, true));
    }
}
