//! Delimited text (`.csv`, `.tsv`, `.xyz`, `.txt`) with a header line naming the columns.
//!
//! The first non-blank line is the header (a leading `#` is dropped from it); the separator is
//! a comma if the header has one, else a tab if it has one, else runs of whitespace. Names
//! may be quoted (`"x"`). Columns `x y z` (any case) are the positions; every other column
//! is an attribute mapped by [`crate::io`]'s rules (`nx ny nz`, `rh`, `radius`, ...). If every
//! header field is a number the file has no header: its columns are `x y z` then `c3 c4 ..`.
//! Blank lines and lines starting with `#` are skipped; every record must have one number per
//! column. Memory grows with the data actually present, never with a declared count.

use glam::Vec3;

use super::ReadOptions;
use super::StoredAttribute;
use super::columns::{Columns, STANDARD, show};
use crate::error::Result;
use crate::pointcloud::PointCloud;

/// Parses a whole file's bytes into a [`PointCloud`] and what the file stores (see the module
/// docs); [`crate::io::read_cloud`] and [`crate::io::read_bytes`] are its entry points, which
/// check the options and name the file in errors.
///
/// Cost: reads the file into memory, then one pass; about 20–40 ns per value.
///
/// # Errors
/// A message naming the line for an empty file, a header without `x y z` or with repeated names, a record with the wrong number of fields, a field that is not a number, or an attribute named in `opts` that is missing.
pub(crate) fn parse(
    bytes: &[u8],
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>), String> {
    columns(bytes)?.into_cloud(opts, &STANDARD)
}

#[derive(Clone, Copy)]
enum Sep {
    Comma,
    Tab,
    Space,
}

fn fields(line: &str, sep: Sep) -> Vec<&str> {
    match sep {
        Sep::Comma => line.split(',').map(str::trim).collect(),
        Sep::Tab => line.split('\t').map(str::trim).collect(),
        Sep::Space => line.split_ascii_whitespace().collect(),
    }
}

/// The column names of header line `hl`'s fields `head`: the names (unquoted), or for a
/// headerless file (`numeric`) `x y z c3 c4 ..`. Each must be non-empty and unique.
fn column_names(head: &[&str], numeric: bool, hl: usize) -> Result<Vec<String>, String> {
    let names: Vec<String> = if numeric {
        if head.len() < 3 {
            return Err(format!(
                "line {hl}: a headerless file needs at least 3 columns (x y z), found {}",
                head.len()
            ));
        }
        (0..head.len())
            .map(|i| match i {
                0..3 => ["x", "y", "z"][i].to_string(),
                _ => format!("c{i}"),
            })
            .collect()
    } else {
        head.iter()
            .map(|f| f.trim_matches('"').trim_matches('\'').to_string())
            .collect()
    };
    for (i, n) in names.iter().enumerate() {
        if n.is_empty() {
            return Err(format!("line {hl}: header column {} has no name", i + 1));
        }
        if names[..i].contains(n) {
            return Err(format!("line {hl}: header names '{}' twice", show(n)));
        }
    }
    Ok(names)
}

fn columns(b: &[u8]) -> Result<Columns, String> {
    let text = std::str::from_utf8(b).map_err(|e| {
        let line = b[..e.valid_up_to()].iter().filter(|&&c| c == b'\n').count() + 1;
        format!("line {line}: not UTF-8 text")
    })?;
    let mut lines = text
        .split('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((hl, header)) = lines.next() else {
        return Err("empty file (no header line)".into());
    };
    let header = header.trim().trim_start_matches('#').trim();
    let sep = if header.contains(',') {
        Sep::Comma
    } else if header.contains('\t') {
        Sep::Tab
    } else {
        Sep::Space
    };
    let head = fields(header, sep);
    let numeric = head.iter().all(|f| f.parse::<f64>().is_ok());
    let names = column_names(&head, numeric, hl)?;
    let pos: Vec<usize> = ["x", "y", "z"]
        .iter()
        .map(|a| {
            names
                .iter()
                .position(|n| n.eq_ignore_ascii_case(a))
                .ok_or_else(|| {
                    format!(
                        "line {hl}: no '{a}' column in the header '{}' (a header line naming \
                         the columns, with x y z, is required)",
                        show(header)
                    )
                })
        })
        .collect::<Result<_, _>>()?;
    let mut data: Vec<Vec<f32>> = vec![Vec::new(); names.len()];
    let mut record = |ln: usize, line: &str| -> Result<(), String> {
        let f = fields(line.trim(), sep);
        if f.len() != names.len() {
            return Err(format!(
                "line {ln}: expected {} fields, found {}",
                names.len(),
                f.len()
            ));
        }
        for (c, tok) in f.iter().enumerate() {
            let v = tok.parse::<f32>().map_err(|_| {
                format!(
                    "line {ln}, column '{}': expected a number, found '{}'",
                    show(&names[c]),
                    show(tok)
                )
            })?;
            data[c].push(v);
        }
        Ok(())
    };
    if numeric {
        record(hl, header)?;
    }
    for (ln, line) in lines {
        if line.trim_start().starts_with('#') {
            continue;
        }
        record(ln, line)?;
    }
    Ok(into_columns(names, data, &pos))
}

/// The columns `names` with their `data`, the ones at `pos` (x, y, z) as the positions.
fn into_columns(names: Vec<String>, data: Vec<Vec<f32>>, pos: &[usize]) -> Columns {
    let mut cols = Columns::default();
    let (x, y, z) = (&data[pos[0]], &data[pos[1]], &data[pos[2]]);
    cols.positions = (0..x.len()).map(|i| Vec3::new(x[i], y[i], z[i])).collect();
    let xyz: Vec<&str> = pos.iter().map(|&i| names[i].as_str()).collect();
    cols.note_positions(&xyz.join(" "), "text");
    for (i, (name, v)) in names.into_iter().zip(data).enumerate() {
        if !pos.contains(&i) {
            cols.push(&name, 1, "text", v);
        }
    }
    cols
}
