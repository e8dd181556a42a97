//! A buffered byte source with contiguous look-ahead, line reading and skipping.
//!
//! Unlike `std::io::BufReader`, [`Source::fill_to`] guarantees `n` contiguous buffered bytes
//! (growing the buffer if needed), so the binary decoder can decode many whole records straight
//! from one slice.

use std::io::{self, Read};
use std::ops::Range;

/// Default buffer size: large enough that per-refill overhead vanishes, small enough to stay in L2/L3.
const BUF_SIZE: usize = 1 << 20;

/// Result of [`Source::read_line`].
pub(super) enum Line<'a> {
    /// One line without its `\n` (a trailing `\r` is kept; callers trim whitespace).
    Text(&'a [u8]),
    /// The line is longer than the caller's limit.
    TooLong,
    /// No bytes left.
    Eof,
}

/// Buffered reader over `R`; `buf[pos..end]` holds the unread buffered bytes.
pub(super) struct Source<R> {
    inner: R,
    buf: Vec<u8>,
    pos: usize,
    end: usize,
    eof: bool,
    /// Bytes of the stream that lie before `buf[0]`.
    base: u64,
}

impl<R: Read> Source<R> {
    /// Wraps `inner` with a 1 MiB buffer, or less if `len` (the stream length) is known smaller.
    pub(super) fn new(inner: R, len: Option<u64>) -> Self {
        let cap = len.map_or(BUF_SIZE, |l| {
            l.saturating_add(1).clamp(4096, BUF_SIZE as u64) as usize
        });
        Self::with_capacity(inner, cap)
    }

    /// Wraps `inner` with a buffer of `cap` bytes (at least 1).
    pub(super) fn with_capacity(inner: R, cap: usize) -> Self {
        Source {
            inner,
            buf: vec![0; cap.max(1)],
            pos: 0,
            end: 0,
            eof: false,
            base: 0,
        }
    }

    /// Stream offset of the next unread byte.
    pub(super) fn position(&self) -> u64 {
        self.base + self.pos as u64
    }

    /// The unread buffered bytes (possibly fewer than asked for by [`Self::fill_to`]).
    pub(super) fn bytes(&self) -> &[u8] {
        &self.buf[self.pos..self.end]
    }

    /// Marks `n` buffered bytes as read. `n` must not exceed `bytes().len()`.
    pub(super) fn consume(&mut self, n: usize) {
        self.pos = (self.pos + n).min(self.end);
    }

    /// Tries to make at least `n` unread bytes contiguous in the buffer, growing it if `n` exceeds
    /// its size. Returns false if the stream ends first (the bytes that exist stay buffered).
    /// Callers bound `n` (record size, chunk size), never by an untrusted count alone.
    pub(super) fn fill_to(&mut self, n: usize) -> io::Result<bool> {
        if self.end - self.pos >= n {
            return Ok(true);
        }
        if self.pos + n > self.buf.len() {
            // Move the unread tail to the front, then grow if still too small.
            self.buf.copy_within(self.pos..self.end, 0);
            self.base += self.pos as u64;
            self.end -= self.pos;
            self.pos = 0;
            if n > self.buf.len() {
                self.buf.resize(n.max(2 * self.buf.len()), 0);
            }
        }
        while self.end - self.pos < n && !self.eof {
            match self.inner.read(&mut self.buf[self.end..]) {
                Ok(0) => self.eof = true,
                Ok(k) => self.end += k,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(self.end - self.pos >= n)
    }

    /// Discards `n` bytes. Returns false if the stream ends first.
    pub(super) fn skip(&mut self, mut n: u64) -> io::Result<bool> {
        loop {
            let have = (self.end - self.pos) as u64;
            if have >= n {
                self.pos += n as usize;
                return Ok(true);
            }
            n -= have;
            self.pos = self.end;
            let want = n.min(self.buf.len() as u64) as usize;
            if !self.fill_to(want)? && self.end == self.pos {
                return Ok(false);
            }
        }
    }

    /// Reads one line of at most `max` bytes (excluding the `\n`). The last line of the stream
    /// need not end with `\n`.
    pub(super) fn read_line(&mut self, max: usize) -> io::Result<Line<'_>> {
        Ok(match self.line_range(max)? {
            Some(Ok(r)) => Line::Text(&self.buf[r]),
            Some(Err(())) => Line::TooLong,
            None => Line::Eof,
        })
    }

    /// Like [`Self::read_line`] but skips lines holding only ASCII whitespace; adds the number
    /// of lines read (blank or not) to `line_no`.
    pub(super) fn read_nonblank_line(
        &mut self,
        max: usize,
        line_no: &mut usize,
    ) -> io::Result<Line<'_>> {
        loop {
            let r = self.line_range(max)?;
            if r.is_some() {
                *line_no += 1;
            }
            match r {
                Some(Ok(r)) if self.buf[r.clone()].iter().all(u8::is_ascii_whitespace) => {}
                Some(Ok(r)) => return Ok(Line::Text(&self.buf[r])),
                Some(Err(())) => return Ok(Line::TooLong),
                None => return Ok(Line::Eof),
            }
        }
    }

    /// Next line as a buffer range: `None` at end of stream, `Some(Err(()))` if too long.
    fn line_range(&mut self, max: usize) -> io::Result<Option<Result<Range<usize>, ()>>> {
        let mut searched = 0;
        loop {
            let unread = &self.buf[self.pos..self.end];
            if let Some(i) = unread[searched..].iter().position(|&b| b == b'\n') {
                let start = self.pos;
                let len = searched + i;
                if len > max {
                    return Ok(Some(Err(())));
                }
                self.pos += len + 1;
                return Ok(Some(Ok(start..start + len)));
            }
            searched = unread.len();
            if searched > max {
                return Ok(Some(Err(())));
            }
            // Ask for one byte more (the read fills all free space); failing means end of stream.
            if !self.fill_to(searched + 1)? {
                if searched == 0 {
                    return Ok(None);
                }
                let start = self.pos;
                self.pos = self.end;
                return Ok(Some(Ok(start..start + searched)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reader that returns at most 3 bytes per call, to exercise refills.
    struct Trickle<'a>(&'a [u8]);
    impl Read for Trickle<'_> {
        fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
            let k = self.0.len().min(out.len()).min(3);
            out[..k].copy_from_slice(&self.0[..k]);
            self.0 = &self.0[k..];
            Ok(k)
        }
    }

    fn text(l: Line<'_>) -> Option<Vec<u8>> {
        match l {
            Line::Text(t) => Some(t.to_vec()),
            _ => None,
        }
    }

    #[test]
    fn lines_across_refills_and_growth() {
        let data = b"ply\nformat ascii 1.0\n\nlast-without-newline";
        let mut s = Source::with_capacity(Trickle(data), 4);
        assert_eq!(text(s.read_line(100).unwrap()).unwrap(), b"ply");
        assert_eq!(s.position(), 4);
        assert_eq!(
            text(s.read_line(100).unwrap()).unwrap(),
            b"format ascii 1.0"
        );
        assert_eq!(text(s.read_line(100).unwrap()).unwrap(), b"");
        assert_eq!(
            text(s.read_line(100).unwrap()).unwrap(),
            b"last-without-newline"
        );
        assert!(matches!(s.read_line(100).unwrap(), Line::Eof));
        assert_eq!(s.position(), data.len() as u64);
    }

    #[test]
    fn nonblank_lines_count_blank_ones() {
        let mut s = Source::with_capacity(Trickle(b"a\n \t\r\n\nb c\n\n"), 4);
        let mut n = 0;
        assert_eq!(
            text(s.read_nonblank_line(100, &mut n).unwrap()).unwrap(),
            b"a"
        );
        assert_eq!(n, 1);
        assert_eq!(
            text(s.read_nonblank_line(100, &mut n).unwrap()).unwrap(),
            b"b c"
        );
        assert_eq!(n, 4);
        assert!(matches!(
            s.read_nonblank_line(100, &mut n).unwrap(),
            Line::Eof
        ));
        assert_eq!(n, 5);
    }

    #[test]
    fn line_limit() {
        let mut s = Source::with_capacity(Trickle(b"abcdefgh\nx"), 2);
        assert!(matches!(s.read_line(5).unwrap(), Line::TooLong));
        let mut s = Source::with_capacity(Trickle(b"abcdefgh"), 2);
        assert!(matches!(s.read_line(5).unwrap(), Line::TooLong));
    }

    #[test]
    fn fill_skip_consume() {
        let data: Vec<u8> = (0..=255).collect();
        let mut s = Source::with_capacity(Trickle(&data), 8);
        assert!(s.fill_to(20).unwrap()); // grows past the 8-byte buffer
        assert_eq!(&s.bytes()[..20], &data[..20]);
        s.consume(10);
        assert!(s.skip(100).unwrap());
        assert_eq!(s.position(), 110);
        assert!(s.fill_to(1).unwrap());
        assert_eq!(s.bytes()[0], 110);
        assert!(s.skip(146).unwrap());
        assert_eq!(s.position(), 256);
        assert!(!s.fill_to(1).unwrap());
        assert!(!s.skip(1).unwrap());
        let mut s = Source::with_capacity(Trickle(&data), 8);
        assert!(!s.fill_to(300).unwrap());
        assert_eq!(s.bytes(), &data[..]);
    }
}
