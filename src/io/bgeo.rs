//! Houdini classic BGEO (V5) reader, plain or gzip-compressed (`.bgeo`, `.bgeo.gz`), as
//! written by Houdini's classic format, partio and SPlisHSPlasH.
//!
//! Layout (big-endian): `Bgeo`, `V`, version 5, then the counts of points, primitives, point
//! groups, primitive groups, point attributes, vertex attributes, primitive attributes and
//! detail attributes (`i32` each); then each point attribute's definition (`u16` name length,
//! name, `u16` size in 4-byte words, `i32` type: 0 float, 1 int, 5 vector, 4 indexed string;
//! then its default values, or for indexed strings their table); then per point `P` as 4
//! floats (x y z w; w is dropped) followed by every attribute's words. Everything after the
//! points (primitives, groups, detail attributes) is ignored.
//!
//! Float, int and vector attributes become attributes (sizes other than 1 split by
//! [`crate::io`]'s rules; ints are converted to f32); indexed-string attributes are skipped;
//! `string` (type 2) and unknown types are errors. The new JSON-based `.bgeo` of Houdini 12+
//! is recognised and rejected with a hint. A plain file is read into memory and the point count
//! checked against its size before allocating; gzip data is inflated only as far as the
//! header's counts need (the header, then exactly the declared points: never a bomb's
//! padding), after checking those counts against what the compressed size can hold and the
//! memory allowance ([`crate::budget`]).

use std::io::Read;

use glam::Vec3;

use super::ReadOptions;
use super::StoredAttribute;
use super::columns::{Columns, STANDARD, show};
use super::num::Num;
use crate::error::Result;
use crate::pointcloud::PointCloud;

/// The point count of a BGEO V5 header in a file's first bytes (for gzip data, its first 64
/// inflated bytes): `BgeoV`, version (i32 BE), then the point count (i32 BE).
pub(crate) fn header_count(head: &[u8]) -> Option<u64> {
    let mut inner = Vec::new();
    let b = if head.starts_with(&[0x1f, 0x8b]) {
        let _ = flate2::read::GzDecoder::new(head)
            .take(64)
            .read_to_end(&mut inner);
        inner.as_slice()
    } else {
        head
    };
    if !b.starts_with(b"BgeoV") || b.len() < 13 {
        return None;
    }
    let n = i32::from_be_bytes(b[9..13].try_into().ok()?);
    u64::try_from(n).ok()
}

/// Parses a whole file's bytes into a [`PointCloud`] and what the file stores (see the module
/// docs); [`crate::io::read_cloud`] and [`crate::io::read_bytes`] are its entry points, which
/// check the options and name the file in errors.
///
/// Cost: reads the file into memory (inflating gzip only up to the declared points), then one
/// pass over the points; peak memory is the file, the inflated header and points, and the
/// cloud.
///
/// # Errors
/// A message naming the byte offset (in the decompressed data) for corrupt gzip, a wrong magic or version, malformed attribute definitions, unsupported attribute types, truncated point data, or an attribute named in `opts` that is missing.
pub(crate) fn parse(
    raw: &[u8],
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>), String> {
    let bytes = if raw.starts_with(&[0x1f, 0x8b]) {
        std::borrow::Cow::Owned(inflate(raw)?)
    } else {
        std::borrow::Cow::Borrowed(raw)
    };
    columns(&bytes)?.into_cloud(opts, &STANDARD)
}

/// The header of a gzip-compressed file may take at most this many inflated bytes (its
/// attribute definitions and string tables).
const MAX_HEADER_BYTES: u64 = 64 << 20;

/// Largest ratio of inflated to deflated bytes deflate can reach (with a margin).
const MAX_DEFLATE_RATIO: u64 = 1100;

/// Inflates gzip data only as far as the header's counts need: first the header (growing the
/// inflated prefix until it parses, at most [`MAX_HEADER_BYTES`]), then exactly the points it
/// declares; whatever follows (primitives, groups, a bomb's padding) is never inflated. A header
/// declaring more than the compressed bytes could hold, or more than the memory allowance, is
/// refused before inflating the points.
fn inflate(raw: &[u8]) -> Result<Vec<u8>, String> {
    let mut z = flate2::read::MultiGzDecoder::new(raw);
    let mut out = Vec::new();
    let corrupt = |e: std::io::Error, n: usize| {
        format!("gzip data is corrupt or truncated after {n} bytes: {e}")
    };
    let mut want: u64 = 64 << 10;
    loop {
        let before = out.len() as u64;
        (&mut z)
            .take(want - before)
            .read_to_end(&mut out)
            .map_err(|e| corrupt(e, out.len()))?;
        let ended = (out.len() as u64) < want;
        match header(&out) {
            Ok(h) => {
                let total = h.data_start as u64 + h.n.saturating_mul(h.stride as u64);
                if total > (raw.len() as u64).saturating_mul(MAX_DEFLATE_RATIO) + 1024 {
                    return Err(format!(
                        "the header's {} points need {total} bytes, more than {} compressed \
                         bytes can inflate to",
                        h.n,
                        raw.len()
                    ));
                }
                crate::budget::check(total, || format!("inflating {} points", h.n))?;
                if (out.len() as u64) < total && !ended {
                    let need = total - out.len() as u64;
                    out.try_reserve_exact(need as usize)
                        .map_err(|_| format!("cannot allocate {need} bytes for the points"))?;
                    (&mut z)
                        .take(need)
                        .read_to_end(&mut out)
                        .map_err(|e| corrupt(e, out.len()))?;
                }
                out.truncate(total.min(out.len() as u64) as usize);
                return Ok(out);
            }
            // The parse reports what is wrong.
            Err(_) if ended || want >= MAX_HEADER_BYTES => return Ok(out),
            Err(_) => want = (want * 4).min(MAX_HEADER_BYTES),
        }
    }
}

/// A big-endian cursor.
struct Cur<'a> {
    b: &'a [u8],
    pos: usize,
}

impl<'a> Cur<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        match self.pos.checked_add(n).filter(|&e| e <= self.b.len()) {
            Some(e) => {
                let s = &self.b[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(format!(
                "data runs out at byte offset {} reading {what} ({n} bytes needed, {} left)",
                self.pos,
                self.b.len() - self.pos.min(self.b.len())
            )),
        }
    }
    fn i32(&mut self, what: &str) -> Result<i32, String> {
        let s = self.take(4, what)?;
        Ok(i32::from_be_bytes([s[0], s[1], s[2], s[3]]))
    }
    fn u16(&mut self, what: &str) -> Result<u16, String> {
        let s = self.take(2, what)?;
        Ok(u16::from_be_bytes([s[0], s[1]]))
    }
    fn count(&mut self, what: &str) -> Result<u64, String> {
        let at = self.pos;
        let v = self.i32(what)?;
        u64::try_from(v).map_err(|_| format!("byte offset {at}: negative {what} ({v})"))
    }
    fn string(&mut self, what: &str) -> Result<String, String> {
        let n = self.u16(what)?;
        let s = self.take(usize::from(n), what)?;
        Ok(String::from_utf8_lossy(s).into_owned())
    }
}

/// One point attribute: name, words per point, type, word offset in the point record.
struct Attr {
    name: String,
    size: usize,
    ty: Num,
    offset: usize,
    keep: bool,
}

/// What the header says: the point count, the attributes, the bytes per point and where the
/// points start.
struct Header {
    n: u64,
    attrs: Vec<Attr>,
    stride: usize,
    data_start: usize,
}

/// Parses the header (everything before the points).
fn header(b: &[u8]) -> Result<Header, String> {
    if b.is_empty() {
        return Err("empty file".into());
    }
    if b.starts_with(b"\x7fNSJ") || b.starts_with(b"{") || b.starts_with(b"[") {
        return Err(
            "Houdini JSON geometry (bgeo of Houdini 12+) is not supported; \
                    export classic BGEO V5 (.bhclassic) instead"
                .into(),
        );
    }
    let mut c = Cur { b, pos: 0 };
    let magic = c.take(5, "the magic")?;
    if magic != b"BgeoV" {
        return Err("not a classic BGEO file (no 'BgeoV' magic)".into());
    }
    let version = c.i32("the version")?;
    if version != 5 {
        return Err(format!("version {version} is not supported (only 5)"));
    }
    let n = c.count("point count")?;
    let _prims = c.count("primitive count")?;
    let _pgroups = c.count("point group count")?;
    let _prgroups = c.count("primitive group count")?;
    let nattr = c.count("point attribute count")?;
    let _vattr = c.count("vertex attribute count")?;
    let _prattr = c.count("primitive attribute count")?;
    let _dattr = c.count("detail attribute count")?;
    // Each definition takes at least 8 bytes.
    if nattr.saturating_mul(8) > (b.len() - c.pos) as u64 {
        return Err(format!(
            "{nattr} point attributes cannot fit in the {} bytes left",
            b.len() - c.pos
        ));
    }
    let mut attrs = Vec::new();
    let mut words = 4usize; // P (x y z w)
    for i in 0..nattr {
        let at = c.pos;
        let name = c.string("an attribute name")?;
        let size = usize::from(c.u16("an attribute size")?);
        let ty = c.i32("an attribute type")?;
        let what = format!("attribute {i} '{}'", show(&name));
        if size == 0 {
            return Err(format!("byte offset {at}: {what} has size 0"));
        }
        let (num, keep) = match ty {
            0 | 5 => (Num::F32, true),
            1 => (Num::I32, true),
            4 => {
                let k = c.count("a string table size")?;
                for _ in 0..k {
                    c.string("a string table entry")?;
                }
                (Num::I32, false)
            }
            2 => {
                return Err(format!(
                    "byte offset {at}: {what} has type string (unsupported)"
                ));
            }
            t => return Err(format!("byte offset {at}: {what} has unknown type {t}")),
        };
        if ty != 4 {
            c.take(4 * size, "attribute defaults")?;
        }
        attrs.push(Attr {
            name,
            size,
            ty: num,
            offset: words,
            keep,
        });
        words += size;
    }
    Ok(Header {
        n,
        attrs,
        stride: 4 * words,
        data_start: c.pos,
    })
}

/// Parses the decompressed file into columns.
fn columns(b: &[u8]) -> Result<Columns, String> {
    let Header {
        n,
        attrs,
        stride,
        data_start,
    } = header(b)?;
    let mut c = Cur { b, pos: data_start };
    let left = (b.len() - c.pos) as u64;
    let need = n.saturating_mul(stride as u64);
    if need > left {
        return Err(format!(
            "data runs out: {n} points of {stride} bytes need {need} bytes after byte offset \
             {}, {left} left (it ends in point {})",
            c.pos,
            left / stride as u64
        ));
    }
    let n = n as usize;
    let body = c.take(need as usize, "the points")?;
    let mut cols = Columns {
        positions: Vec::with_capacity(n),
        ..Columns::default()
    };
    cols.note_positions("P", "float32");
    let mut p = Vec::with_capacity(3 * n);
    for rec in body.chunks_exact(stride) {
        Num::F32.decode(&rec[..12], true, &mut p);
    }
    cols.positions
        .extend(p.chunks_exact(3).map(|q| Vec3::new(q[0], q[1], q[2])));
    drop(p);
    let mut v = Vec::new();
    for a in attrs.iter().filter(|a| a.keep) {
        v.clear();
        v.reserve(n * a.size);
        let (o, e) = (4 * a.offset, 4 * (a.offset + a.size));
        for rec in body.chunks_exact(stride) {
            a.ty.decode(&rec[o..e], true, &mut v);
        }
        cols.push(&a.name, a.size, a.ty.name(), std::mem::take(&mut v));
    }
    Ok(cols)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn bomb(declared: i32, padding: usize) -> (Vec<u8>, usize) {
        let mut b = b"BgeoV".to_vec();
        for v in [5, declared, 0, 0, 0, 0, 0, 0, 0] {
            b.extend(v.to_be_bytes());
        }
        let header = b.len();
        b.resize(header + 16 * declared.max(0) as usize, 1);
        let implied = b.len();
        b.resize(b.len() + padding, 0);
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        e.write_all(&b).unwrap();
        (e.finish().unwrap(), implied)
    }

    #[test]
    fn inflates_exactly_what_the_header_implies() {
        // 5 points and 32 MiB of padding: only the header and the 5 points are inflated.
        let (gz, implied) = bomb(5, 32 << 20);
        assert_eq!(inflate(&gz).unwrap().len(), implied);
        // Points beyond the first inflated chunk are inflated too, and nothing after them.
        let (gz, implied) = bomb(20_000, 1 << 20);
        assert_eq!(inflate(&gz).unwrap().len(), implied);
        // Truncated data: what there is, for the parser to report.
        let (gz, _) = bomb(5, 0);
        let cut = inflate(&gz[..gz.len() - 30]);
        assert!(cut.is_err() || cut.unwrap().len() < 45 + 80);
    }
}
