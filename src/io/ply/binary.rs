//! Binary body decoding (little- and big-endian via the `BE` const parameter).
//!
//! Fast path (vertex element without list properties): records have a fixed stride, so whole
//! chunks of records are decoded one property (column) at a time, each by a loop specialised
//! for the property's type, byte order and destination. Slow path (lists present): record by
//! record, value by value.

use std::io::Read;

use glam::Vec3;

use super::header::{Element, Header, PropKind, Scalar};
use super::source::Source;
use super::{Fail, Outputs, Plan, Target, record_name};

/// Bytes of records decoded per chunk in the fast path.
const CHUNK_BYTES: usize = 1 << 20;

/// Skips the elements before `vertex` (index `vi`) and decodes `vertex` into `out`.
pub(super) fn read<R: Read, const BE: bool>(
    src: &mut Source<R>,
    header: &Header,
    vi: usize,
    plan: &Plan,
    out: &mut Outputs,
) -> Result<(), Fail> {
    for e in &header.elements[..vi] {
        skip_element::<R, BE>(src, e)?;
    }
    let v = &header.elements[vi];
    match v.fixed_stride() {
        Some(stride) => read_fixed::<R, BE>(src, v, stride, plan, out),
        None => read_records::<R, BE>(src, v, plan, out),
    }
}

fn truncated(e: &Element, i: u64) -> Fail {
    Fail::msg(format!(
        "data ends inside {} (file truncated?)",
        record_name(e, i)
    ))
}

/// Decodes one scalar from the front of `b` (which holds at least `s.size()` bytes) as f64.
fn scalar<const BE: bool>(b: &[u8], s: Scalar) -> f64 {
    macro_rules! get {
        ($t:ty) => {{
            let mut a = [0u8; size_of::<$t>()];
            a.copy_from_slice(&b[..size_of::<$t>()]);
            f64::from(if BE {
                <$t>::from_be_bytes(a)
            } else {
                <$t>::from_le_bytes(a)
            })
        }};
    }
    match s {
        Scalar::I8 => get!(i8),
        Scalar::U8 => get!(u8),
        Scalar::I16 => get!(i16),
        Scalar::U16 => get!(u16),
        Scalar::I32 => get!(i32),
        Scalar::U32 => get!(u32),
        Scalar::F32 => get!(f32),
        Scalar::F64 => get!(f64),
    }
}

/// Reads a scalar of record `i` of `e`; `None` target values are discarded.
fn next_scalar<R: Read, const BE: bool>(
    src: &mut Source<R>,
    s: Scalar,
    e: &Element,
    i: u64,
) -> Result<f64, Fail> {
    if !src.fill_to(s.size())? {
        return Err(truncated(e, i));
    }
    let x = scalar::<BE>(src.bytes(), s);
    src.consume(s.size());
    Ok(x)
}

/// Skips a list property of record `i` of `e`.
fn skip_list<R: Read, const BE: bool>(
    src: &mut Source<R>,
    count: Scalar,
    item: Scalar,
    e: &Element,
    i: u64,
) -> Result<(), Fail> {
    let n = next_scalar::<R, BE>(src, count, e, i)?;
    if n < 0.0 {
        return Err(Fail::msg(format!(
            "negative list length {n} in {}",
            record_name(e, i)
        )));
    }
    // n is an integer below 2^32, so the product cannot overflow.
    if !src.skip(n as u64 * item.size() as u64)? {
        return Err(truncated(e, i));
    }
    Ok(())
}

/// Skips all records of an element.
fn skip_element<R: Read, const BE: bool>(src: &mut Source<R>, e: &Element) -> Result<(), Fail> {
    if let Some(stride) = e.fixed_stride() {
        let start = src.position();
        let total = e.count.checked_mul(stride as u64);
        let ok = match total {
            Some(t) => src.skip(t)?,
            None => false,
        };
        if !ok {
            let i = (src.position() - start) / (stride.max(1) as u64);
            return Err(truncated(e, i));
        }
        return Ok(());
    }
    for i in 0..e.count {
        for p in &e.props {
            match p.kind {
                PropKind::Scalar(s) => {
                    if !src.skip(s.size() as u64)? {
                        return Err(truncated(e, i));
                    }
                }
                PropKind::List { count, item } => skip_list::<R, BE>(src, count, item, e, i)?,
            }
        }
    }
    Ok(())
}

/// Skips the elements after `vertex` up to `face` (index `fi`), then reads the polygons of the
/// list property `li` of `face` into `faces` (fan-triangulated, indices checked).
pub(super) fn read_faces<R: Read, const BE: bool>(
    src: &mut Source<R>,
    header: &Header,
    (vi, fi, li): (usize, usize, usize),
    faces: &mut super::Faces,
) -> Result<(), Fail> {
    for e in &header.elements[vi + 1..fi] {
        skip_element::<R, BE>(src, e)?;
    }
    let f = &header.elements[fi];
    let mut poly: Vec<f64> = Vec::new();
    for i in 0..f.count {
        for (pi, p) in f.props.iter().enumerate() {
            match p.kind {
                PropKind::Scalar(s) => {
                    if !src.skip(s.size() as u64)? {
                        return Err(truncated(f, i));
                    }
                }
                PropKind::List { count, item } if pi == li => {
                    let n = next_scalar::<R, BE>(src, count, f, i)?;
                    if n < 0.0 {
                        return Err(Fail::msg(format!(
                            "negative list length {n} in {}",
                            record_name(f, i)
                        )));
                    }
                    poly.clear();
                    // Each item is read from the file, so a huge count ends at end of file.
                    for _ in 0..n as u64 {
                        poly.push(next_scalar::<R, BE>(src, item, f, i)?);
                    }
                }
                PropKind::List { count, item } => skip_list::<R, BE>(src, count, item, f, i)?,
            }
        }
        faces
            .push(&poly)
            .map_err(|m| Fail::msg(format!("{}: {m}", record_name(f, i))))?;
    }
    Ok(())
}

/// Slow path: record by record (the element has list properties).
fn read_records<R: Read, const BE: bool>(
    src: &mut Source<R>,
    v: &Element,
    plan: &Plan,
    out: &mut Outputs,
) -> Result<(), Fail> {
    for i in 0..v.count {
        out.grow(1);
        let row = out.len() - 1;
        for (p, &t) in v.props.iter().zip(&plan.targets) {
            match p.kind {
                PropKind::Scalar(s) => {
                    let x = next_scalar::<R, BE>(src, s, v, i)?;
                    out.set(t, row, x as f32);
                }
                PropKind::List { count, item } => skip_list::<R, BE>(src, count, item, v, i)?,
            }
        }
    }
    Ok(())
}

/// Fast path: fixed-stride records, decoded column by column in chunks.
fn read_fixed<R: Read, const BE: bool>(
    src: &mut Source<R>,
    v: &Element,
    stride: usize,
    plan: &Plan,
    out: &mut Outputs,
) -> Result<(), Fail> {
    // (byte offset in record, type, target) for every property.
    let mut columns = Vec::with_capacity(v.props.len());
    let mut off = 0;
    for (p, &t) in v.props.iter().zip(&plan.targets) {
        if let PropKind::Scalar(s) = p.kind {
            columns.push((off, s, t));
            off += s.size();
        }
    }
    let per_chunk = (CHUNK_BYTES / stride).max(1);
    let mut done: u64 = 0;
    while done < v.count {
        let want = (v.count - done).min(per_chunk as u64) as usize;
        src.fill_to(want * stride)?;
        let k = (src.bytes().len() / stride).min(want);
        if k == 0 {
            return Err(truncated(v, done));
        }
        let base = out.len();
        out.grow(k);
        let chunk = &src.bytes()[..k * stride];
        for &(off, s, t) in &columns {
            decode_column::<BE>(chunk, stride, off, s, t, out, base);
        }
        src.consume(k * stride);
        done += k as u64;
    }
    Ok(())
}

/// Decodes one property of every record in `chunk` into rows `base..` of its target column.
fn decode_column<const BE: bool>(
    chunk: &[u8],
    stride: usize,
    off: usize,
    s: Scalar,
    t: Target,
    out: &mut Outputs,
    base: usize,
) {
    let v3 = |v: &mut Vec<Vec3>, c: usize| {
        let dst = &mut v[base..];
        match c {
            0 => column::<BE, _>(chunk, stride, off, s, dst, |p, x| p.x = x),
            1 => column::<BE, _>(chunk, stride, off, s, dst, |p, x| p.y = x),
            _ => column::<BE, _>(chunk, stride, off, s, dst, |p, x| p.z = x),
        }
    };
    let f1 =
        |v: &mut Vec<f32>| column::<BE, _>(chunk, stride, off, s, &mut v[base..], |p, x| *p = x);
    match t {
        Target::Pos(c) => v3(&mut out.positions, c),
        Target::Normal(c) => out.normals.as_mut().into_iter().for_each(|v| v3(v, c)),
        Target::Thickness => out.thickness.as_mut().into_iter().for_each(f1),
        Target::Radius => out.radius.as_mut().into_iter().for_each(f1),
        Target::Extra(k) => out.extra.get_mut(k).into_iter().for_each(f1),
        Target::Ignore => {}
    }
}

/// The inner loop: for each record, decode the `s` at byte `off` and `set` it into `dst`.
#[inline(always)]
fn column<const BE: bool, T>(
    chunk: &[u8],
    stride: usize,
    off: usize,
    s: Scalar,
    dst: &mut [T],
    set: impl Fn(&mut T, f32),
) {
    macro_rules! run {
        ($t:ty) => {{
            const N: usize = size_of::<$t>();
            for (d, rec) in dst.iter_mut().zip(chunk.chunks_exact(stride)) {
                let mut a = [0u8; N];
                a.copy_from_slice(&rec[off..off + N]);
                let x = if BE {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                };
                set(d, x as f32);
            }
        }};
    }
    match s {
        Scalar::I8 => run!(i8),
        Scalar::U8 => run!(u8),
        Scalar::I16 => run!(i16),
        Scalar::U16 => run!(u16),
        Scalar::I32 => run!(i32),
        Scalar::U32 => run!(u32),
        Scalar::F32 => run!(f32),
        Scalar::F64 => run!(f64),
    }
}
