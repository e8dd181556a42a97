//! Decoding a VTK XML file's arrays: ASCII text, inline base64 and appended raw or base64
//! data, each binary block plain or zlib-compressed, every size checked against the bytes left
//! before allocating.

use std::borrow::Cow;

use super::{Array, Encoding, MAX_ZLIB_RATIO, Piece, Settings};
use crate::io::columns::show;
use crate::io::sources::{Base64, Raw, Source};

/// Bounds the whole file's work before decoding anything: no two appended arrays may start at
/// the same offset (many `Piece`s pointing at one block would decode it again and again), the
/// appended arrays together cannot declare more bytes than the appended data holds (times the
/// best zlib ratio when compressed). (Each array's decoded values are checked against the
/// memory allowance by [`block`] once its sizes are known to fit the file.)
pub(super) fn check_total_work(pieces: &[Piece], set: &Settings<'_>) -> Result<(), String> {
    let arrays = pieces
        .iter()
        .flat_map(|p| p.points.iter().chain(&p.data).map(move |a| (p.n, a)));
    let mut offsets = Vec::new();
    let mut appended_bytes = 0u64;
    for (n, a) in arrays {
        let count = n.saturating_mul(a.k);
        if a.enc == Encoding::Appended {
            offsets.push((a.offset, show(&a.name)));
            appended_bytes =
                appended_bytes.saturating_add(count.saturating_mul(a.ty.size() as u64));
        }
    }
    offsets.sort();
    if let Some(w) = offsets.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(format!(
            "arrays '{}' and '{}' both point at appended offset {} (each array needs its own data)",
            w[0].1, w[1].1, w[0].0
        ));
    }
    if let Some((data, base64)) = set.appended {
        let mut room = data.len() as u64;
        if base64 {
            room = room / 4 * 3;
        }
        if set.zlib {
            room = room.saturating_mul(MAX_ZLIB_RATIO).saturating_add(1024);
        }
        if appended_bytes > room {
            return Err(format!(
                "the appended arrays declare {appended_bytes} bytes, more than the {} bytes of \
                 appended data can hold",
                data.len()
            ));
        }
    }
    Ok(())
}

/// Decodes one array of `n` tuples to f32.
pub(super) fn decode(b: &[u8], a: &Array, n: u64, set: &Settings<'_>) -> Result<Vec<f32>, String> {
    let name = show(&a.name);
    let count = n.saturating_mul(a.k);
    let nbytes = count.saturating_mul(a.ty.size() as u64);
    let ctx = |m: String| format!("array '{name}': {m}");
    match a.enc {
        Encoding::Ascii => ascii(b, a, count).map_err(ctx),
        Encoding::Binary => {
            let text: Vec<u8> = a.text.iter().flat_map(|r| &b[r.clone()]).copied().collect();
            let mut src = Base64 {
                s: Cow::Owned(text),
                pos: 0,
                pending: Vec::new(),
            };
            block(&mut src, nbytes, a, set).map_err(ctx)
        }
        Encoding::Appended => {
            let (data, base64) = set
                .appended
                .ok_or_else(|| ctx("appended array but no AppendedData".into()))?;
            let off = usize::try_from(a.offset)
                .ok()
                .filter(|&o| o <= data.len())
                .ok_or_else(|| {
                    ctx(format!(
                        "offset {} lies beyond the {} bytes of appended data",
                        a.offset,
                        data.len()
                    ))
                })?;
            if base64 {
                let mut src = Base64 {
                    s: Cow::Borrowed(&data[off..]),
                    pos: 0,
                    pending: Vec::new(),
                };
                block(&mut src, nbytes, a, set)
            } else {
                block(
                    &mut Raw {
                        b: &data[off..],
                        pos: 0,
                    },
                    nbytes,
                    a,
                    set,
                )
            }
            .map_err(|m| ctx(format!("{m} (appended offset {off})")))
        }
    }
}

/// Parses `count` ASCII numbers from the array's text.
fn ascii(b: &[u8], a: &Array, count: u64) -> Result<Vec<f32>, String> {
    let len: usize = a.text.iter().map(|r| r.len()).sum();
    if count > (len as u64).div_ceil(2) {
        return Err(format!(
            "{count} values cannot fit in its {len} bytes of text"
        ));
    }
    let mut out = Vec::with_capacity(count as usize);
    for r in &a.text {
        for tok in b[r.clone()].split(u8::is_ascii_whitespace) {
            if tok.is_empty() {
                continue;
            }
            let s = std::str::from_utf8(tok).unwrap_or("\u{fffd}");
            let v = s.parse::<f32>().map_err(|_| {
                format!(
                    "expected a number, found '{}' at byte offset {}",
                    show(s),
                    tok.as_ptr() as usize - b.as_ptr() as usize
                )
            })?;
            if out.len() as u64 == count {
                return Err(format!("more than the {count} values expected"));
            }
            out.push(v);
        }
    }
    if (out.len() as u64) < count {
        return Err(format!("data runs out: {} of {count} values", out.len()));
    }
    Ok(out)
}

/// Reads one binary block (header + data, possibly zlib-compressed) of `nbytes` decoded bytes.
fn block<'a>(
    src: &mut dyn Source<'a>,
    nbytes: u64,
    a: &Array,
    set: &Settings<'_>,
) -> Result<Vec<f32>, String> {
    if set.zlib {
        return zlib_blocks(src, nbytes, a, set);
    }
    let len = header_word(src, set)?;
    if len != nbytes {
        return Err(format!(
            "its header says {len} bytes, NumberOfPoints × components × size is {nbytes}"
        ));
    }
    if len > src.left() {
        return Err(format!(
            "data runs out: needs {len} bytes, at most {} left",
            src.left()
        ));
    }
    let d = src.take(len as usize)?;
    let mut out = Vec::with_capacity(d.len() / a.ty.size());
    a.ty.decode(&d, set.big_endian, &mut out);
    Ok(out)
}

/// One word of a block header (`UInt32` or `UInt64`, the file's byte order).
fn header_word<'a>(src: &mut dyn Source<'a>, set: &Settings<'_>) -> Result<u64, String> {
    let h = src.take(set.header.size())?;
    set.header
        .read_uint(&h, set.big_endian)
        .ok_or_else(|| "bad block header".to_string())
}

/// A zlib-compressed block: its header (block count, sizes) checked against the bytes left and
/// the best zlib ratio, then each block inflated to exactly its size.
fn zlib_blocks<'a>(
    src: &mut dyn Source<'a>,
    nbytes: u64,
    a: &Array,
    set: &Settings<'_>,
) -> Result<Vec<f32>, String> {
    let hs = set.header.size();
    let word = |src: &mut dyn Source<'a>| header_word(src, set);
    let blocks = word(src)?;
    if blocks.saturating_add(2).saturating_mul(hs as u64) > src.left() {
        return Err(format!(
            "data runs out: {blocks} compressed blocks cannot fit in {} bytes",
            src.left()
        ));
    }
    let bs = word(src)?;
    let last = word(src)?;
    let mut sizes = Vec::with_capacity(blocks as usize);
    for _ in 0..blocks {
        sizes.push(word(src)?);
    }
    let total = match blocks {
        0 => 0,
        m => (m - 1)
            .checked_mul(bs)
            .and_then(|t| t.checked_add(if last == 0 { bs } else { last }))
            .ok_or("absurd compressed block sizes")?,
    };
    if total != nbytes {
        return Err(format!(
            "its compression header says {total} bytes, NumberOfPoints × components × size is \
             {nbytes}"
        ));
    }
    let csum = sizes.iter().try_fold(0u64, |s, &c| s.checked_add(c));
    let csum = csum.ok_or("absurd compressed block sizes")?;
    if csum > src.left() {
        return Err(format!(
            "data runs out: compressed blocks need {csum} bytes, at most {} left",
            src.left()
        ));
    }
    if total > csum.saturating_mul(MAX_ZLIB_RATIO).saturating_add(1024) {
        return Err(format!(
            "{csum} compressed bytes cannot inflate to the {total} bytes expected"
        ));
    }
    // The inflated bytes and their f32 values.
    let values = total / a.ty.size() as u64;
    crate::budget::check(total.saturating_add(values.saturating_mul(4)), || {
        format!("inflating {values} values")
    })?;
    let mut raw: Vec<u8> = Vec::with_capacity(total as usize);
    for (i, &c) in sizes.iter().enumerate() {
        let want = if i + 1 == sizes.len() && last != 0 {
            last
        } else {
            bs
        } as usize;
        let input = src.take(c as usize)?;
        inflate_block(&input, want, &mut raw)
            .map_err(|m| format!("compressed block {i} of {blocks} is corrupt ({m})"))?;
    }
    let mut out = Vec::with_capacity(raw.len() / a.ty.size());
    a.ty.decode(&raw, set.big_endian, &mut out);
    Ok(out)
}

/// Inflates one zlib stream onto the end of `raw`: exactly `want` bytes, ending the stream.
fn inflate_block(input: &[u8], want: usize, raw: &mut Vec<u8>) -> Result<(), String> {
    let before = raw.len();
    raw.resize(before + want, 0);
    let mut z = flate2::Decompress::new(true);
    // Exactly `want` bytes of room: the stream must end there.
    let st = z.decompress(input, &mut raw[before..], flate2::FlushDecompress::Finish);
    let got = z.total_out() as usize;
    if matches!(st, Ok(flate2::Status::StreamEnd)) && got == want {
        return Ok(());
    }
    Err(format!(
        "zlib {}; {got} of {want} bytes",
        match st {
            Ok(s) => format!("{s:?}"),
            Err(e) => e.to_string(),
        }
    ))
}
