//! How many particles a file holds, from its header alone (for memory estimates before loading).

use std::io::Read;
use std::path::Path;

use super::{CloudFormat, detect_format};
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
            format: super::by_extension(path).unwrap_or(CloudFormat::Ply),
            particles: 0,
            exact: false,
            file_bytes: 0,
            reads_whole_file: true,
        });
    }
    let format = detect_format(path)?;
    match format {
        CloudFormat::FrameFolder if path.join("x_bin").is_file() => {
            return peek_frame_folder(path);
        }
        CloudFormat::FrameFolder | CloudFormat::SnapshotFolder | CloudFormat::MelpFolder => {
            return peek_folder_bytes(path, format);
        }
        _ => {}
    }
    let file_bytes = std::fs::metadata(path)
        .map_err(|e| Error::io(path, e))?
        .len();
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(HEAD_BYTES).read_to_end(&mut head))
        .map_err(|e| Error::io(path, e))?;
    let gzip = head.starts_with(&[0x1f, 0x8b]);
    let header = match format {
        CloudFormat::Ply => keyword_count(&head, b"element vertex "),
        CloudFormat::VtkLegacy => keyword_count(&head, b"POINTS "),
        CloudFormat::VtkXml => keyword_count(&head, b"NumberOfPoints=\""),
        CloudFormat::Bgeo if gzip => {
            let mut inner = Vec::with_capacity(64);
            let _ = flate2::read::GzDecoder::new(head.as_slice())
                .take(64)
                .read_to_end(&mut inner);
            bgeo_count(&inner)
        }
        CloudFormat::Bgeo => bgeo_count(&head),
        _ => None,
    };
    // Deflate expands at most ~1032:1; text needs at least "0 0 0\n" (6 bytes) a particle and
    // binary 12, so 3 bytes a particle bounds every uncompressed format.
    let cap = if gzip {
        file_bytes.saturating_mul(1032) / 3
    } else {
        file_bytes / 3
    };
    let (particles, exact) = match header {
        Some(n) => (n.min(cap), n <= cap),
        None if format == CloudFormat::Csv => (text_lines_estimate(&head, file_bytes), false),
        None => (file_bytes / 12, false),
    };
    Ok(CountHint {
        format,
        particles,
        exact,
        file_bytes,
        reads_whole_file: format != CloudFormat::Ply,
    })
}

/// The decimal number after the first `key` in `head` (PLY, VTK legacy and VTK XML headers).
fn keyword_count(head: &[u8], key: &[u8]) -> Option<u64> {
    let at = head.windows(key.len()).position(|w| w == key)? + key.len();
    let digits: Vec<u8> = head[at..]
        .iter()
        .copied()
        .skip_while(|c| *c == b' ')
        .take_while(u8::is_ascii_digit)
        .take(20)
        .collect();
    std::str::from_utf8(&digits).ok()?.parse().ok()
}

/// BGEO V5: `BgeoV`, version (i32 BE), then the point count (i32 BE).
fn bgeo_count(b: &[u8]) -> Option<u64> {
    if !b.starts_with(b"BgeoV") || b.len() < 13 {
        return None;
    }
    let n = i32::from_be_bytes(b[9..13].try_into().ok()?);
    u64::try_from(n).ok()
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

/// A frame folder: the count at the start of `x_bin` (little-endian u32), capped by its size.
fn peek_frame_folder(dir: &Path) -> Result<CountHint> {
    let mut file_bytes = 0;
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        if entry.file_name().to_string_lossy().ends_with("_bin") {
            file_bytes += entry.metadata().map(|m| m.len()).unwrap_or(0);
        }
    }
    let x = dir.join("x_bin");
    let x_bytes = std::fs::metadata(&x).map_err(|e| Error::io(&x, e))?.len();
    let mut head = Vec::with_capacity(4);
    std::fs::File::open(&x)
        .and_then(|f| f.take(4).read_to_end(&mut head))
        .map_err(|e| Error::io(&x, e))?;
    let cap = x_bytes.saturating_sub(4) / 24;
    let (particles, exact) = match head.get(..4) {
        Some(b) => {
            let n = u64::from(u32::from_le_bytes(b.try_into().expect("4 bytes")));
            (n.min(cap), n <= cap)
        }
        None => (0, false),
    };
    Ok(CountHint {
        format: CloudFormat::FrameFolder,
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
        let ply = b"ply\nformat ascii 1.0\nelement vertex 1234\nproperty float x\nend_header\n";
        assert_eq!(keyword_count(ply, b"element vertex "), Some(1234));
        assert_eq!(
            keyword_count(b"<Piece NumberOfPoints=\"250\" ", b"NumberOfPoints=\""),
            Some(250)
        );
        assert_eq!(keyword_count(b"POINTS  77 float\n", b"POINTS "), Some(77));
        assert_eq!(keyword_count(b"POINTS x", b"POINTS "), None);
        let mut bgeo = b"BgeoV".to_vec();
        bgeo.extend(5i32.to_be_bytes());
        bgeo.extend(6859i32.to_be_bytes());
        assert_eq!(bgeo_count(&bgeo), Some(6859));
        bgeo[9..13].copy_from_slice(&(-1i32).to_be_bytes());
        assert_eq!(bgeo_count(&bgeo), None);
        // 10 data lines of 10 bytes after an 10-byte header: a 1000-byte file holds ~100 lines.
        let text = b"x,y,z,abc\n".repeat(11);
        assert_eq!(text_lines_estimate(&text, 1000), 100);
    }
}
