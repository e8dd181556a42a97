//! ASCII body decoding: one record per line, values separated by spaces or tabs.
//!
//! Lines holding only whitespace are ignored; elements without properties occupy no lines.
//! Errors give the file's line number (counting the header lines).

use std::io::Read;

use super::header::{Element, Header, PropKind};
use super::source::{Line, Source};
use super::{Fail, Outputs, Plan, record_name};

/// Longest body line accepted, in bytes.
const MAX_LINE: usize = 1 << 20;

/// Skips the elements before `vertex` (index `vi`) and parses `vertex` into `out`. Returns the
/// number of the last line read.
pub(super) fn read<R: Read>(
    src: &mut Source<R>,
    header: &Header,
    vi: usize,
    plan: &Plan,
    out: &mut Outputs,
) -> Result<usize, Fail> {
    let mut line_no = header.lines;
    for e in header.elements[..vi].iter().filter(|e| !e.props.is_empty()) {
        for i in 0..e.count {
            record_line(src, &mut line_no, e, i)?;
        }
    }
    let v = &header.elements[vi];
    for i in 0..v.count {
        let line = record_line(src, &mut line_no, v, i)?;
        let at = || format!("line {line_no}: {}", record_name(v, i));
        out.grow(1);
        let row = out.len() - 1;
        // List items (skipped) are not stored.
        parse_record(line, &at, v, |pi, item, x| {
            if !item {
                out.set(plan.targets[pi], row, x as f32);
            }
        })?;
    }
    Ok(line_no)
}

/// Skips the elements after `vertex` up to `face` (index `fi`), then reads the polygons of the
/// list property `li` of `face` into `faces` (fan-triangulated, indices checked against
/// `vertices`). `line_no` is the last line read so far.
pub(super) fn read_faces<R: Read>(
    src: &mut Source<R>,
    header: &Header,
    (vi, fi, li): (usize, usize, usize),
    mut line_no: usize,
    faces: &mut super::Faces,
) -> Result<(), Fail> {
    for e in header.elements[vi + 1..fi]
        .iter()
        .filter(|e| !e.props.is_empty())
    {
        for i in 0..e.count {
            record_line(src, &mut line_no, e, i)?;
        }
    }
    let f = &header.elements[fi];
    let mut poly: Vec<f64> = Vec::new();
    for i in 0..f.count {
        let line = record_line(src, &mut line_no, f, i)?;
        let at = || format!("line {line_no}: {}", record_name(f, i));
        poly.clear();
        parse_record(line, &at, f, |pi, item, x| {
            if item && pi == li {
                poly.push(x);
            }
        })?;
        faces
            .push(&poly)
            .map_err(|m| Fail::msg(format!("{}: {m}", at())))?;
    }
    Ok(())
}

/// Parses one record of `e` from its line: every value is passed to `value(property index,
/// is a list item, value)` in file order (list lengths are not passed). `at()` names the record
/// in errors: not text, too few or too many values, a token that is not a number, a list length
/// that is not a count. Integers and floats alike are read as f64; `nan`/`inf` are accepted
/// (values are not validated here).
fn parse_record(
    line: &[u8],
    at: &dyn Fn() -> String,
    e: &Element,
    mut value: impl FnMut(usize, bool, f64),
) -> Result<(), Fail> {
    let text = std::str::from_utf8(line)
        .map_err(|_| Fail::msg(format!("{}: not text (binary data?)", at())))?;
    let mut tokens = text.split_ascii_whitespace();
    let next = |tokens: &mut std::str::SplitAsciiWhitespace<'_>, what: &str| {
        let tok = tokens
            .next()
            .ok_or_else(|| Fail::msg(format!("{}: too few values (missing {what})", at())))?;
        tok.parse::<f64>().map_err(|_| {
            let shown = super::header::show(tok);
            Fail::msg(format!("{}: '{shown}' is not a number", at()))
        })
    };
    for (pi, p) in e.props.iter().enumerate() {
        match p.kind {
            PropKind::Scalar(_) => value(pi, false, next(&mut tokens, &p.name)?),
            PropKind::List { .. } => {
                let n = next(&mut tokens, &p.name)?;
                if n < 0.0 || n.fract() != 0.0 {
                    return Err(Fail::msg(format!(
                        "{}: list length {n} of '{}' is not a count",
                        at(),
                        super::header::show(&p.name)
                    )));
                }
                // Each item needs a token, so this loop ends at the end of the line.
                let mut k = 0.0;
                while k < n {
                    value(pi, true, next(&mut tokens, &p.name)?);
                    k += 1.0;
                }
            }
        }
    }
    if tokens.next().is_some() {
        return Err(Fail::msg(format!(
            "{}: more values than the header's {} properties",
            at(),
            e.props.len()
        )));
    }
    Ok(())
}

/// Returns the next non-blank line, the one holding record `i` of `e`.
fn record_line<'s, R: Read>(
    src: &'s mut Source<R>,
    line_no: &mut usize,
    e: &Element,
    i: u64,
) -> Result<&'s [u8], Fail> {
    match src.read_nonblank_line(MAX_LINE, line_no)? {
        Line::Text(t) => Ok(t),
        Line::TooLong => Err(Fail::msg(format!(
            "line {}: longer than {MAX_LINE} bytes ({})",
            *line_no,
            record_name(e, i)
        ))),
        Line::Eof => Err(Fail::msg(format!(
            "line {}: file ends before {} (file truncated?)",
            *line_no + 1,
            record_name(e, i)
        ))),
    }
}
