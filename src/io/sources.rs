//! Byte sources for VTK XML binary data: raw bytes and base64 text decoded on demand.

use std::borrow::Cow;

/// A byte stream an array's (header +) data is read from.
pub(crate) trait Source<'a> {
    /// The next `n` bytes, or a message saying where the data ran out.
    fn take(&mut self, n: usize) -> Result<Cow<'a, [u8]>, String>;
    /// An upper bound on the bytes left.
    fn left(&self) -> u64;
}

pub(crate) struct Raw<'a> {
    pub b: &'a [u8],
    pub pos: usize,
}

impl<'a> Source<'a> for Raw<'a> {
    fn take(&mut self, n: usize) -> Result<Cow<'a, [u8]>, String> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.b.len());
        let end = end.ok_or_else(|| {
            format!(
                "data runs out: needs {n} bytes at byte {} of the data, {} left",
                self.pos,
                self.b.len() - self.pos.min(self.b.len())
            )
        })?;
        let s = &self.b[self.pos..end];
        self.pos = end;
        Ok(Cow::Borrowed(s))
    }
    fn left(&self) -> u64 {
        (self.b.len() - self.pos.min(self.b.len())) as u64
    }
}

/// Base64 text decoded on demand; padded quanta may occur mid-stream (VTK encodes headers and
/// data separately when compressing).
pub(crate) struct Base64<'a> {
    pub s: Cow<'a, [u8]>,
    pub pos: usize,
    /// Decoded bytes not yet taken.
    pub pending: Vec<u8>,
}

fn b64(c: u8) -> Option<u8> {
    Some(match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => return None,
    })
}

impl<'a> Source<'a> for Base64<'a> {
    fn take(&mut self, n: usize) -> Result<Cow<'a, [u8]>, String> {
        if n as u64 > self.left() {
            return Err(format!(
                "data runs out: needs {n} bytes, the base64 text holds at most {}",
                self.left()
            ));
        }
        let mut out = std::mem::take(&mut self.pending);
        out.reserve(n.saturating_sub(out.len()) + 3);
        let s = &self.s;
        while out.len() < n {
            let mut q = [0u8; 4];
            let mut got = 0;
            let mut pad = 0;
            while got < 4 {
                let Some(&c) = s.get(self.pos) else {
                    return Err(format!(
                        "data runs out: the base64 text ends after {} of {n} bytes",
                        out.len()
                    ));
                };
                self.pos += 1;
                if c.is_ascii_whitespace() {
                    continue;
                }
                if c == b'=' && got >= 2 {
                    pad += 1;
                    q[got] = 0;
                } else if let (Some(v), 0) = (b64(c), pad) {
                    q[got] = v;
                } else {
                    return Err(format!(
                        "invalid base64 character {:?} at character {} of the data",
                        char::from(c),
                        self.pos - 1
                    ));
                }
                got += 1;
            }
            let w = (u32::from(q[0]) << 18)
                | (u32::from(q[1]) << 12)
                | (u32::from(q[2]) << 6)
                | u32::from(q[3]);
            let bytes = [(w >> 16) as u8, (w >> 8) as u8, w as u8];
            out.extend_from_slice(&bytes[..3 - pad]);
        }
        self.pending = out.split_off(n);
        Ok(Cow::Owned(out))
    }
    fn left(&self) -> u64 {
        (self.s.len() - self.pos.min(self.s.len())) as u64 / 4 * 3 + self.pending.len() as u64 + 3
    }
}
