//! VTK legacy reader (`.vtk`, ASCII or BINARY big-endian) for particle clouds.
//!
//! Reads `DATASET UNSTRUCTURED_GRID` or `POLYDATA`: `POINTS n float|double` are the positions;
//! every `POINT_DATA` array (`SCALARS` with any `LOOKUP_TABLE` line, `VECTORS`, `NORMALS`,
//! `TEXTURE_COORDINATES`, `TENSORS`, `GLOBAL_IDS`, `PEDIGREE_IDS`, `FIELD` arrays) becomes an
//! attribute (k-component arrays split by [`crate::io`]'s rules). Cells (`CELLS`, `VERTICES`,
//! `CELL_TYPES`, ..., also the 5.x `OFFSETS`/`CONNECTIVITY` layout), `CELL_DATA`, dataset-level
//! `FIELD` data and `METADATA` blocks are skipped. `long` is taken as 8 bytes, `vtkIdType` as
//! 4; `bit` arrays are rejected. The whole file is read into memory first; every count is
//! checked against the bytes left before anything is allocated.

use glam::Vec3;

use super::ReadOptions;
use super::StoredAttribute;
use super::columns::{Columns, STANDARD, show};
use super::num::Num;
use crate::error::Result;
use crate::pointcloud::PointCloud;

/// The point count of a VTK legacy header (`POINTS n`) in a file's first bytes, if any.
pub(crate) fn header_count(head: &[u8]) -> Option<u64> {
    super::num::keyword_count(head, b"POINTS ")
}

/// Parses a whole file's bytes into a [`PointCloud`] and what the file stores (see the module
/// docs); [`crate::io::read_cloud`] and [`crate::io::read_bytes`] are its entry points, which
/// check the options and name the file in errors.
///
/// Cost: reads the file into memory, then one pass; peak memory is the file plus the cloud.
///
/// # Errors
/// A message naming the line (ASCII) or byte offset (binary) for a malformed or truncated file, an unsupported dataset or type, or an attribute named in `opts` that is missing.
pub(crate) fn parse(
    bytes: &[u8],
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>), String> {
    columns(bytes)?.into_cloud(opts, &STANDARD)
}

/// Where the following data goes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Section {
    /// Before any POINT_DATA / CELL_DATA: dataset-level field data (skipped).
    Dataset,
    Point,
    /// CELL_DATA with this many cells (skipped).
    Cell(u64),
}

/// A cursor over the file.
struct Cur<'a> {
    b: &'a [u8],
    pos: usize,
    binary: bool,
    /// The last position [`Cur::at`] numbered and its 0-based line, so numbering the lines in
    /// file order costs O(file size) in all (not O(position) per call).
    line_cache: std::cell::Cell<(usize, usize)>,
}

impl<'a> Cur<'a> {
    /// "line L" (ASCII) or "byte offset X" (binary) for the position `at`.
    fn at(&self, at: usize) -> String {
        if self.binary {
            format!("byte offset {at}")
        } else {
            let at = at.min(self.b.len());
            let (from, mut line) = match self.line_cache.get() {
                (p, l) if p <= at => (p, l),
                _ => (0, 0),
            };
            line += self.b[from..at].iter().filter(|&&c| c == b'\n').count();
            self.line_cache.set((at, line));
            format!("line {}", line + 1)
        }
    }

    /// The next raw line (without `\n` and trailing whitespace) and its start, or `None` at
    /// the end.
    fn raw_line(&mut self) -> Option<(usize, &'a str)> {
        if self.pos >= self.b.len() {
            return None;
        }
        let start = self.pos;
        let rest = &self.b[start..];
        let len = rest.iter().position(|&c| c == b'\n').unwrap_or(rest.len());
        self.pos = (start + len + 1).min(self.b.len());
        let text = std::str::from_utf8(&rest[..len]).unwrap_or("\u{fffd}");
        Some((start, text.trim_end()))
    }

    /// Skips lines up to and including the next blank one (a METADATA block).
    fn skip_block(&mut self) {
        while let Some((_, l)) = self.raw_line() {
            if l.trim().is_empty() {
                break;
            }
        }
    }

    /// The next non-blank line, trimmed.
    fn line(&mut self) -> Option<(usize, &'a str)> {
        while let Some((at, l)) = self.raw_line() {
            if !l.trim().is_empty() {
                return Some((at, l.trim()));
            }
        }
        None
    }

    /// The next non-blank line if it starts with `keyword` (consumed), else nothing consumed.
    fn line_if(&mut self, keyword: &str) -> Option<(usize, &'a str)> {
        let save = self.pos;
        match self.line() {
            Some((at, l)) if first_word_is(l, keyword) => Some((at, l)),
            _ => {
                self.pos = save;
                None
            }
        }
    }

    /// Reads `count` values of type `ty` (binary: big-endian) as f32, or skips them if
    /// `keep` is false. `what` names the array in messages.
    fn values(&mut self, ty: Num, count: u64, keep: bool, what: &str) -> Result<Vec<f32>, String> {
        let left = (self.b.len() - self.pos.min(self.b.len())) as u64;
        let mut out = Vec::new();
        if self.binary {
            let need = count.saturating_mul(ty.size() as u64);
            if need > left {
                return Err(format!(
                    "{}: data runs out in {what}: {count} values need {need} bytes, {left} left \
                     (at value {} of {count})",
                    self.at(self.pos),
                    left / ty.size() as u64
                ));
            }
            let end = self.pos + need as usize;
            if keep {
                out.reserve_exact(count as usize);
                ty.decode(&self.b[self.pos..end], true, &mut out);
            }
            self.pos = end;
            return Ok(out);
        }
        // ASCII: each value takes at least 2 bytes (a digit and a separator), bar the last.
        if count > left.div_ceil(2) {
            return Err(format!(
                "{}: data runs out in {what}: {count} values cannot fit in the {left} bytes left",
                self.at(self.pos)
            ));
        }
        if keep {
            out.reserve_exact(count as usize);
        }
        for i in 0..count {
            while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let start = self.pos;
            while self.pos < self.b.len() && !self.b[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let tok = std::str::from_utf8(&self.b[start..self.pos]).unwrap_or("\u{fffd}");
            if tok.is_empty() {
                return Err(format!(
                    "{}: data runs out in {what} at value {i} of {count}",
                    self.at(start)
                ));
            }
            match tok.parse::<f32>() {
                Ok(v) if keep => out.push(v),
                Ok(_) => {}
                Err(_) => {
                    return Err(format!(
                        "{}: expected a number (value {i} of {what}), found '{}'",
                        self.at(start),
                        show(tok)
                    ));
                }
            }
        }
        Ok(out)
    }
}

fn first_word_is(line: &str, keyword: &str) -> bool {
    line.split_ascii_whitespace()
        .next()
        .is_some_and(|w| w.eq_ignore_ascii_case(keyword))
}

/// A VTK legacy type name.
fn num_type(name: &str) -> Option<Num> {
    Some(match name.to_ascii_lowercase().as_str() {
        "char" | "signed_char" | "vtktypeint8" => Num::I8,
        "unsigned_char" | "vtktypeuint8" => Num::U8,
        "short" | "vtktypeint16" => Num::I16,
        "unsigned_short" | "vtktypeuint16" => Num::U16,
        "int" | "vtktypeint32" | "vtkidtype" => Num::I32,
        "unsigned_int" | "vtktypeuint32" => Num::U32,
        "long" | "vtktypeint64" => Num::I64,
        "unsigned_long" | "vtktypeuint64" => Num::U64,
        "float" | "vtktypefloat32" => Num::F32,
        "double" | "vtktypefloat64" => Num::F64,
        _ => return None,
    })
}

/// The first three lines: the version line, the title and ASCII or BINARY (noted in `c`).
fn preamble(c: &mut Cur<'_>) -> Result<(), String> {
    match c.raw_line() {
        Some((_, l)) if l.starts_with("# vtk DataFile Version") => {}
        Some(_) => {
            return Err("line 1: not a VTK legacy file (no '# vtk DataFile Version')".into());
        }
        None => return Err("empty file".into()),
    }
    c.raw_line()
        .ok_or("file ends after line 1 (no title line)")?;
    match c.line() {
        Some((_, l)) if l.eq_ignore_ascii_case("ASCII") => {}
        Some((_, l)) if l.eq_ignore_ascii_case("BINARY") => c.binary = true,
        Some((at, l)) => {
            return Err(format!(
                "{}: expected ASCII or BINARY, found '{}'",
                c.at(at),
                show(l)
            ));
        }
        None => return Err("file ends before the ASCII/BINARY line".into()),
    }
    Ok(())
}

/// Skips a cell section of `n` cells and `size` values: the classic layout, or the 5.x
/// `OFFSETS` / `CONNECTIVITY` arrays.
fn skip_cells(c: &mut Cur<'_>, n: u64, size: u64, keyword: &str, here: &str) -> Result<(), String> {
    if let Some((oat, ol)) = c.line_if("OFFSETS") {
        let t = ol.split_ascii_whitespace().nth(1).and_then(num_type);
        let t = t.ok_or_else(|| format!("{}: bad OFFSETS line", c.at(oat)))?;
        c.values(t, n, false, "OFFSETS")?;
        let (cat, cl) = c
            .line_if("CONNECTIVITY")
            .ok_or_else(|| format!("{here}: OFFSETS without CONNECTIVITY"))?;
        let t = cl.split_ascii_whitespace().nth(1).and_then(num_type);
        let t = t.ok_or_else(|| format!("{}: bad CONNECTIVITY line", c.at(cat)))?;
        c.values(t, size, false, "CONNECTIVITY")?;
    } else {
        c.values(Num::I32, size, false, keyword)?;
    }
    Ok(())
}

/// The `arrays` arrays of a FIELD block: kept as columns when it is point data (`keep`),
/// each then holding one tuple per point; skipped otherwise.
fn field_arrays(
    c: &mut Cur<'_>,
    arrays: u64,
    keep: bool,
    n_points: Option<u64>,
    here: &str,
    cols: &mut Columns,
) -> Result<(), String> {
    for _ in 0..arrays {
        let (fat, fl) = c
            .line()
            .ok_or_else(|| format!("{here}: file ends inside FIELD"))?;
        let fw: Vec<&str> = fl.split_ascii_whitespace().collect();
        let fhere = c.at(fat);
        if fw.first().is_some_and(|s| *s == "NULL_ARRAY") {
            continue;
        }
        let num = |i: usize| fw.get(i).and_then(|s| s.parse::<u64>().ok());
        let (Some(k), Some(tuples), Some(t)) =
            (num(1), num(2), fw.get(3).copied().and_then(num_type))
        else {
            return Err(format!(
                "{fhere}: expected 'name components tuples type' in FIELD, found '{}'",
                show(fl)
            ));
        };
        let aname = fw[0].replace("%20", " ");
        if keep && Some(tuples) != n_points {
            return Err(format!(
                "{fhere}: FIELD array '{}' has {tuples} tuples for {} points",
                show(&aname),
                n_points.unwrap_or(0)
            ));
        }
        if !(1..=64).contains(&k) {
            return Err(format!(
                "{fhere}: FIELD array '{}' has {k} components (1 to 64 supported)",
                show(&aname)
            ));
        }
        let v = c.values(t, tuples.saturating_mul(k), keep, &aname)?;
        if keep {
            cols.push(&aname, k as usize, t.name(), v);
        }
        if c.line_if("METADATA").is_some() {
            c.skip_block();
        }
    }
    Ok(())
}

/// Parses the whole file into columns.
fn columns(b: &[u8]) -> Result<Columns, String> {
    let mut c = Cur {
        b,
        pos: 0,
        binary: false,
        line_cache: std::cell::Cell::new((0, 0)),
    };
    preamble(&mut c)?;
    let mut cols = Columns::default();
    let mut n_points: Option<u64> = None;
    let mut dataset = false;
    let mut section = Section::Dataset;
    while let Some((at, line)) = c.line() {
        let w: Vec<&str> = line.split_ascii_whitespace().collect();
        let here = c.at(at);
        let bad = |msg: &str| format!("{here}: {msg} in '{}'", show(line));
        let count = |i: usize| -> Result<u64, String> {
            w.get(i)
                .and_then(|s| s.parse::<u64>().ok())
                .ok_or_else(|| bad("expected a count"))
        };
        let ty = |i: usize| -> Result<Num, String> {
            let name = w.get(i).copied().unwrap_or("");
            num_type(name).ok_or_else(|| {
                format!(
                    "{here}: unsupported data type '{}' in '{}'",
                    show(name),
                    show(line)
                )
            })
        };
        let name = |i: usize| -> Result<String, String> {
            w.get(i)
                .map(|s| s.replace("%20", " "))
                .ok_or_else(|| bad("expected a name"))
        };
        let keyword = w[0].to_ascii_uppercase();
        if !dataset && keyword != "DATASET" && keyword != "FIELD" {
            return Err(bad("expected DATASET"));
        }
        // (name, components, type) of a data array, if this line starts one.
        let mut array: Option<(String, u64, Num)> = None;
        match keyword.as_str() {
            "DATASET" => {
                let t = w.get(1).map(|s| s.to_ascii_uppercase()).unwrap_or_default();
                if t != "UNSTRUCTURED_GRID" && t != "POLYDATA" {
                    return Err(format!(
                        "{here}: DATASET '{}' is not supported (only UNSTRUCTURED_GRID and \
                         POLYDATA)",
                        show(&t)
                    ));
                }
                dataset = true;
            }
            "POINTS" => {
                if n_points.is_some() {
                    return Err(bad("second POINTS section"));
                }
                let n = count(1)?;
                let t = ty(2)?;
                if !matches!(t, Num::F32 | Num::F64) {
                    return Err(bad("POINTS must be float or double"));
                }
                let v = c.values(t, n.saturating_mul(3), true, "POINTS")?;
                cols.note_positions("POINTS", t.name());
                cols.positions = v
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2]))
                    .collect();
                n_points = Some(n);
            }
            "METADATA" => c.skip_block(),
            "CELLS" | "VERTICES" | "LINES" | "POLYGONS" | "TRIANGLE_STRIPS" => {
                skip_cells(&mut c, count(1)?, count(2)?, &keyword, &here)?;
            }
            "CELL_TYPES" => {
                c.values(Num::I32, count(1)?, false, "CELL_TYPES")?;
            }
            "POINT_DATA" => {
                let n = count(1)?;
                match n_points {
                    Some(p) if p == n => section = Section::Point,
                    Some(p) => {
                        return Err(format!("{here}: POINT_DATA {n} but POINTS has {p} points"));
                    }
                    None => return Err(format!("{here}: POINT_DATA before POINTS")),
                }
            }
            "CELL_DATA" => section = Section::Cell(count(1)?),
            "SCALARS" => {
                let k = match w.get(3) {
                    Some(_) => count(3)?,
                    None => 1,
                };
                if !(1..=16).contains(&k) {
                    return Err(bad("SCALARS must have 1 to 16 components"));
                }
                c.line_if("LOOKUP_TABLE");
                array = Some((name(1)?, k, ty(2)?));
            }
            "VECTORS" | "NORMALS" => array = Some((name(1)?, 3, ty(2)?)),
            "TENSORS" => array = Some((name(1)?, 9, ty(2)?)),
            "TENSORS6" => array = Some((name(1)?, 6, ty(2)?)),
            "GLOBAL_IDS" | "PEDIGREE_IDS" => array = Some((name(1)?, 1, ty(2)?)),
            "TEXTURE_COORDINATES" => {
                let k = count(2)?;
                if !(1..=3).contains(&k) {
                    return Err(bad("TEXTURE_COORDINATES must have 1 to 3 components"));
                }
                array = Some((name(1)?, k, ty(3)?));
            }
            "COLOR_SCALARS" => {
                let k = count(2)?;
                if !(1..=4).contains(&k) {
                    return Err(bad("COLOR_SCALARS must have 1 to 4 components"));
                }
                let t = if c.binary { Num::U8 } else { Num::F32 };
                array = Some((name(1)?, k, t));
            }
            "LOOKUP_TABLE" => {
                let t = if c.binary { Num::U8 } else { Num::F32 };
                c.values(t, count(2)?.saturating_mul(4), false, "LOOKUP_TABLE")?;
            }
            "FIELD" => {
                let keep = section == Section::Point;
                field_arrays(&mut c, count(2)?, keep, n_points, &here, &mut cols)?;
            }
            _ => return Err(format!("{here}: unknown keyword '{}'", show(w[0]))),
        }
        if let Some((aname, k, t)) = array {
            let tuples = match section {
                Section::Point => n_points.unwrap_or(0),
                Section::Cell(n) => n,
                Section::Dataset => {
                    return Err(bad("data array outside POINT_DATA / CELL_DATA"));
                }
            };
            let keep = section == Section::Point;
            let v = c.values(t, tuples.saturating_mul(k), keep, &aname)?;
            if keep {
                cols.push(&aname, k as usize, t.name(), v);
            }
        }
    }
    if n_points.is_none() {
        return Err("no POINTS section".into());
    }
    Ok(cols)
}
