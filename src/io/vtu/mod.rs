//! VTK XML reader (`.vtu` unstructured grids, `.vtp` poly data) for particle clouds.
//!
//! Reads every `Piece` (concatenated in order): `Points` are the positions and every
//! `PointData` `DataArray` becomes an attribute (k components split by [`crate::io`]'s rules);
//! cells, cell data and field data are skipped. Array encodings: `ascii`, inline `binary`
//! (base64) and `appended` (`raw` or `base64`), with `UInt32` or `UInt64` headers, little- or
//! big-endian, uncompressed or `vtkZLibDataCompressor`. Other compressors (LZ4, LZMA) are
//! rejected. The whole file is read into memory; every size is checked against the bytes left
//! (and, for compressed data, against the best possible zlib ratio) before allocating.

use std::ops::Range;

use glam::Vec3;

mod data;

use super::ReadOptions;
use super::StoredAttribute;
use super::columns::{Columns, STANDARD, show};
use super::melp;
use super::num::Num;
use super::xml::Scanner;
use crate::error::Result;
use crate::pointcloud::PointCloud;
use data::{check_total_work, decode};

/// Largest ratio of inflated to deflated bytes zlib can reach (with a margin).
const MAX_ZLIB_RATIO: u64 = 1100;

/// The point count of a VTK XML piece (`NumberOfPoints="n"`) in a file's first bytes, if any.
pub(crate) fn header_count(head: &[u8]) -> Option<u64> {
    super::num::keyword_count(head, b"NumberOfPoints=\"")
}

/// Parses a whole file's bytes into a [`PointCloud`] and what the file stores (see the module
/// docs); [`crate::io::read_cloud`] and [`crate::io::read_bytes`] are its entry points, which
/// check the options and name the file in errors.
///
/// Cost: reads the file into memory, then one pass (plus inflating compressed arrays); peak
/// memory is the file plus the cloud plus one decoded array.
///
/// # Errors
/// A message naming the array or byte offset for malformed XML, unsupported dataset types, encodings or compressors, sizes that disagree with `NumberOfPoints`, truncated or corrupt data, or an attribute named in `opts` that is missing.
pub(crate) fn parse(
    bytes: &[u8],
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>), String> {
    into_cloud(columns(bytes)?, opts)
}

/// Maps the columns to a cloud, as MELP's writers meant them when the arrays are theirs
/// ([`super::melp`]: `H` in metres, radius √(SA/π), disk glyphs collapsed).
fn into_cloud(
    c: Columns,
    opts: &ReadOptions,
) -> std::result::Result<(PointCloud, Vec<StoredAttribute>), String> {
    match melp::writer(&c) {
        None => c.into_cloud(opts, &STANDARD),
        Some(melp::Writer::Glyphs) => {
            melp::collapse_glyphs(c)?.into_cloud(opts, &melp::GLYPH_ALIASES)
        }
        Some(melp::Writer::Particles) => {
            let (mut cloud, mut stored) = c.into_cloud(opts, &melp::PARTICLE_ALIASES)?;
            super::part::radius_from_area(&mut cloud, &mut stored, "SA", opts);
            Ok((cloud, stored))
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Binary,
    Appended,
}

/// One `DataArray` to decode.
#[derive(Debug)]
struct Array {
    name: String,
    ty: Num,
    k: u64,
    enc: Encoding,
    offset: u64,
    /// Text content (ascii / inline binary), as ranges of the file outside child elements.
    text: Vec<Range<usize>>,
}

#[derive(Debug, Default)]
struct Piece {
    n: u64,
    points: Option<Array>,
    data: Vec<Array>,
}

/// File-wide settings.
struct Settings<'a> {
    big_endian: bool,
    header: Num,
    zlib: bool,
    /// Appended data after the `_`, and whether it is base64.
    appended: Option<(&'a [u8], bool)>,
}

fn num_type(name: &str) -> Option<Num> {
    Some(match name {
        "Int8" | "Char" => Num::I8,
        "UInt8" | "UChar" => Num::U8,
        "Int16" => Num::I16,
        "UInt16" => Num::U16,
        "Int32" => Num::I32,
        "UInt32" => Num::U32,
        "Int64" => Num::I64,
        "UInt64" => Num::U64,
        "Float32" => Num::F32,
        "Float64" => Num::F64,
        _ => return None,
    })
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Ctx {
    None,
    Points,
    PointData,
}

/// Parses the file into columns.
fn columns(b: &[u8]) -> Result<Columns, String> {
    if b.is_empty() {
        return Err("empty file".into());
    }
    let mut sc = Scanner { b, pos: 0 };
    let root = sc
        .next_tag()?
        .filter(|t| t.name == "VTKFile" && !t.end)
        .ok_or("not a VTK XML file (no <VTKFile> root element)")?;
    let ty = root.attr("type").unwrap_or("");
    if ty != "UnstructuredGrid" && ty != "PolyData" {
        return Err(format!(
            "VTKFile type '{}' is not supported (only UnstructuredGrid and PolyData)",
            show(ty)
        ));
    }
    let mut set = settings(&root)?;
    let mut pieces: Vec<Piece> = Vec::new();
    let mut ctx = Ctx::None;
    let mut closed = false;
    while let Some(t) = sc.next_tag()? {
        let at = t.start;
        match (t.name, t.end) {
            ("Piece", false) => {
                let n = t
                    .attr("NumberOfPoints")
                    .and_then(|s| s.trim().parse::<u64>().ok())
                    .ok_or_else(|| format!("byte offset {at}: Piece without a NumberOfPoints"))?;
                pieces.push(Piece {
                    n,
                    ..Piece::default()
                });
            }
            ("Points", false) if !t.empty => ctx = Ctx::Points,
            ("PointData", false) if !t.empty => ctx = Ctx::PointData,
            ("Points" | "PointData", true) => ctx = Ctx::None,
            ("DataArray", false) => {
                let mut arr = array_of(&t, at)?;
                if !t.empty {
                    arr.text = text_until_end(&mut sc)?;
                }
                let piece = pieces.last_mut();
                match (ctx, piece) {
                    (Ctx::Points, Some(p)) if p.points.is_none() => p.points = Some(arr),
                    (Ctx::Points, Some(_)) => {
                        return Err(format!("byte offset {at}: second Points array"));
                    }
                    (Ctx::PointData, Some(p)) => p.data.push(arr),
                    (Ctx::None, _) => {}
                    (_, None) => return Err(format!("byte offset {at}: DataArray outside Piece")),
                }
            }
            ("AppendedData", false) => {
                set.appended = Some(appended(b, &t)?);
                closed = true;
                break;
            }
            ("VTKFile", true) => {
                closed = true;
                break;
            }
            _ => {}
        }
    }
    if !closed {
        return Err(format!(
            "truncated: the file ends at byte {} before </VTKFile>",
            b.len()
        ));
    }
    if pieces.is_empty() {
        return Err("no Piece element".into());
    }
    check_total_work(&pieces, &set)?;
    assemble(b, &pieces, &set)
}

/// The file-wide settings of the `<VTKFile>` root: byte order, block header type, compressor.
fn settings<'a>(root: &super::xml::Tag<'_>) -> Result<Settings<'a>, String> {
    let big_endian = match root.attr("byte_order").unwrap_or("LittleEndian") {
        "LittleEndian" => false,
        "BigEndian" => true,
        o => return Err(format!("unknown byte_order '{}'", show(o))),
    };
    let header = match root.attr("header_type").unwrap_or("UInt32") {
        "UInt32" => Num::U32,
        "UInt64" => Num::U64,
        o => return Err(format!("unknown header_type '{}'", show(o))),
    };
    let zlib = match root.attr("compressor").unwrap_or("") {
        "" => false,
        "vtkZLibDataCompressor" => true,
        o => {
            return Err(format!(
                "compressor '{}' is not supported (only vtkZLibDataCompressor)",
                show(o)
            ));
        }
    };
    Ok(Settings {
        big_endian,
        header,
        zlib,
        appended: None,
    })
}

/// The appended data of an `<AppendedData>` tag `t` (after its `_`, up to the last
/// `</AppendedData>`), and whether it is base64.
fn appended<'a>(b: &'a [u8], t: &super::xml::Tag<'_>) -> Result<(&'a [u8], bool), String> {
    let base64 = match t.attr("encoding").unwrap_or("raw") {
        "raw" => false,
        "base64" => true,
        o => return Err(format!("unknown AppendedData encoding '{}'", show(o))),
    };
    let mut i = t.after;
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    if b.get(i) != Some(&b'_') {
        return Err(format!(
            "byte offset {i}: AppendedData does not start with '_'"
        ));
    }
    // Raw data may hold any bytes, so its end is the last closing tag; a file
    // without one was cut off.
    let close = b"</AppendedData>";
    let end = b[i..]
        .windows(close.len())
        .rposition(|w| w == close)
        .map(|k| i + k)
        .ok_or_else(|| {
            format!(
                "truncated: the appended data from byte offset {i} has no \
                 </AppendedData> after it"
            )
        })?;
    if !b[end..].windows(10).any(|w| w == b"</VTKFile>") {
        return Err(format!(
            "truncated: the file ends at byte {} before </VTKFile>",
            b.len()
        ));
    }
    Ok((&b[i + 1..end], base64))
}

/// The pieces' points and point arrays decoded and joined into columns (every piece must
/// hold the same arrays).
fn assemble(b: &[u8], pieces: &[Piece], set: &Settings<'_>) -> Result<Columns, String> {
    let mut cols = Columns::default();
    let mut data: Vec<(String, u64, Num, Vec<f32>)> = Vec::new();
    for (pi, p) in pieces.iter().enumerate() {
        let pts = p
            .points
            .as_ref()
            .ok_or_else(|| format!("Piece {pi} has no Points array"))?;
        if pts.k != 3 {
            return Err(format!("Points array has {} components, expected 3", pts.k));
        }
        let v = decode(b, pts, p.n, set)?;
        if pi == 0 {
            cols.note_positions("Points", pts.ty.name());
        }
        cols.positions
            .extend(v.chunks_exact(3).map(|q| Vec3::new(q[0], q[1], q[2])));
        if pi > 0 && p.data.len() != data.len() {
            return Err(format!(
                "Piece {pi} has {} point arrays, Piece 0 has {}",
                p.data.len(),
                data.len()
            ));
        }
        for (ai, a) in p.data.iter().enumerate() {
            let v = decode(b, a, p.n, set)?;
            if pi == 0 {
                data.push((a.name.clone(), a.k, a.ty, v));
            } else if data[ai].0 != a.name || data[ai].1 != a.k {
                return Err(format!(
                    "Piece {pi}'s point array {ai} is '{}', Piece 0's is '{}'",
                    show(&a.name),
                    show(&data[ai].0)
                ));
            } else {
                data[ai].3.extend(v);
            }
        }
    }
    for (name, k, ty, v) in data {
        cols.push(&name, k as usize, ty.name(), v);
    }
    Ok(cols)
}

/// The array described by a `DataArray` tag.
fn array_of(t: &super::xml::Tag<'_>, at: usize) -> Result<Array, String> {
    let name = t.attr("Name").unwrap_or("unnamed").to_string();
    let tyname = t.attr("type").unwrap_or("");
    let ty = num_type(tyname).ok_or_else(|| {
        format!(
            "byte offset {at}: array '{}' has unsupported type '{}'",
            show(&name),
            show(tyname)
        )
    })?;
    let k = match t.attr("NumberOfComponents") {
        None => 1,
        Some(s) => s
            .trim()
            .parse::<u64>()
            .ok()
            .filter(|k| (1..=64).contains(k))
            .ok_or_else(|| {
                format!(
                    "byte offset {at}: array '{}' has NumberOfComponents '{}' (1 to 64 supported)",
                    show(&name),
                    show(s)
                )
            })?,
    };
    let enc = match t.attr("format").unwrap_or("ascii") {
        "ascii" => Encoding::Ascii,
        "binary" => Encoding::Binary,
        "appended" => Encoding::Appended,
        o => {
            return Err(format!(
                "byte offset {at}: array '{}' has unknown format '{}'",
                show(&name),
                show(o)
            ));
        }
    };
    let offset = match (enc, t.attr("offset")) {
        (Encoding::Appended, Some(s)) => s
            .trim()
            .parse::<u64>()
            .map_err(|_| format!("byte offset {at}: array '{}' has a bad offset", show(&name)))?,
        (Encoding::Appended, None) => {
            return Err(format!(
                "byte offset {at}: appended array '{}' has no offset",
                show(&name)
            ));
        }
        _ => 0,
    };
    Ok(Array {
        name,
        ty,
        k,
        enc,
        offset,
        text: Vec::new(),
    })
}

/// Collects the text directly inside the current element up to its end tag (skipping child
/// elements such as `InformationKey`).
fn text_until_end(sc: &mut Scanner<'_>) -> Result<Vec<Range<usize>>, String> {
    let mut text = Vec::new();
    let mut depth = 0usize;
    loop {
        let from = sc.pos;
        let t = sc
            .next_tag()?
            .ok_or_else(|| format!("byte offset {from}: file ends inside a DataArray"))?;
        if depth == 0 {
            text.push(from..t.start);
        }
        match (t.end, t.empty) {
            (true, _) if depth == 0 => return Ok(text),
            (true, _) => depth -= 1,
            (false, false) => depth += 1,
            (false, true) => {}
        }
    }
}
