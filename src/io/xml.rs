//! A tiny XML tag scanner, enough for VTK XML files: start/end/empty tags with attributes,
//! skipping comments, processing instructions and declarations. Text between tags is left to
//! the caller (by byte offsets), so binary appended data after a tag is never scanned.

/// One tag.
#[derive(Debug)]
pub(crate) struct Tag<'a> {
    /// Element name.
    pub name: &'a str,
    /// Attributes in file order, values unescaped.
    pub attrs: Vec<(&'a str, String)>,
    /// `</name>`.
    pub end: bool,
    /// `<name ... />`.
    pub empty: bool,
    /// Offset of the `<`.
    pub start: usize,
    /// Offset just after the `>`.
    pub after: usize,
}

impl Tag<'_> {
    /// The attribute `key`, if present.
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// Scans tags from a byte position.
pub(crate) struct Scanner<'a> {
    pub b: &'a [u8],
    pub pos: usize,
}

fn find(hay: &[u8], from: usize, needle: &[u8]) -> Option<usize> {
    hay.get(from..)?
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|i| from + i)
}

fn unescape(s: &str) -> String {
    if !s.contains('&') {
        return s.to_string();
    }
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

impl<'a> Scanner<'a> {
    /// The next tag, `None` at the end of input. Errors name the byte offset.
    pub fn next_tag(&mut self) -> Result<Option<Tag<'a>>, String> {
        let b = self.b;
        loop {
            let Some(lt) = b
                .get(self.pos..)
                .and_then(|r| r.iter().position(|&c| c == b'<'))
            else {
                self.pos = b.len();
                return Ok(None);
            };
            let start = self.pos + lt;
            let skip_to = |close: &[u8]| {
                find(b, start, close)
                    .map(|i| i + close.len())
                    .ok_or_else(|| format!("byte offset {start}: unterminated XML markup"))
            };
            if b[start..].starts_with(b"<!--") {
                self.pos = skip_to(b"-->")?;
                continue;
            }
            if b[start..].starts_with(b"<?") {
                self.pos = skip_to(b"?>")?;
                continue;
            }
            if b[start..].starts_with(b"<!") {
                self.pos = skip_to(b">")?;
                continue;
            }
            return self.parse_tag(start).map(Some);
        }
    }

    fn parse_tag(&mut self, start: usize) -> Result<Tag<'a>, String> {
        let b = self.b;
        let bad = |at: usize, what: &str| format!("byte offset {at}: malformed XML tag ({what})");
        let mut i = start + 1;
        let end = b.get(i) == Some(&b'/');
        if end {
            i += 1;
        }
        let is_name = |c: u8| c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-' | b'.' | b':');
        let n0 = i;
        while i < b.len() && is_name(b[i]) {
            i += 1;
        }
        if i == n0 {
            return Err(bad(start, "no element name"));
        }
        let name = std::str::from_utf8(&b[n0..i]).map_err(|_| bad(start, "name"))?;
        let mut attrs = Vec::new();
        loop {
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            // `>` ends the tag; `/>` ends an empty element.
            let empty = match (b.get(i), b.get(i + 1)) {
                (None, _) => return Err(bad(start, "file ends inside the tag")),
                (Some(b'>'), _) => Some(false),
                (Some(b'/'), Some(b'>')) => Some(true),
                _ => None,
            };
            if let Some(empty) = empty {
                let after = i + 1 + usize::from(empty);
                self.pos = after;
                return Ok(Tag {
                    name,
                    attrs,
                    end,
                    empty,
                    start,
                    after,
                });
            }
            let k0 = i;
            while i < b.len() && is_name(b[i]) {
                i += 1;
            }
            if i == k0 {
                return Err(bad(i, "unexpected character"));
            }
            let key = std::str::from_utf8(&b[k0..i]).map_err(|_| bad(k0, "attribute"))?;
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            if b.get(i) != Some(&b'=') {
                return Err(bad(i, "expected '=' after an attribute name"));
            }
            i += 1;
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            let q = match b.get(i) {
                Some(&q @ (b'"' | b'\'')) => q,
                _ => return Err(bad(i, "expected a quoted attribute value")),
            };
            let v0 = i + 1;
            let v1 = b[v0..]
                .iter()
                .position(|&c| c == q)
                .map(|k| v0 + k)
                .ok_or_else(|| bad(v0, "unterminated attribute value"))?;
            let val = std::str::from_utf8(&b[v0..v1]).map_err(|_| bad(v0, "attribute value"))?;
            attrs.push((key, unescape(val)));
            i = v1 + 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Scanner;

    #[test]
    fn tags_attributes_and_skips() {
        let x = b"<?xml version='1.0'?><!-- c < > --><A k=\"1 &amp; 2\" j = 'x'>text<B/></A>";
        let mut s = Scanner { b: x, pos: 0 };
        let a = s.next_tag().unwrap().unwrap();
        assert_eq!((a.name, a.end, a.empty), ("A", false, false));
        assert_eq!(a.attr("k"), Some("1 & 2"));
        assert_eq!(a.attr("j"), Some("x"));
        assert_eq!(&x[a.after..a.after + 4], b"text");
        let b = s.next_tag().unwrap().unwrap();
        assert!(b.empty && b.name == "B");
        let e = s.next_tag().unwrap().unwrap();
        assert!(e.end && e.name == "A");
        assert!(s.next_tag().unwrap().is_none());
        for bad in [&b"<A k=1>"[..], b"<A k=\"1>", b"< A>", b"<A", b"<!-- x"] {
            assert!(Scanner { b: bad, pos: 0 }.next_tag().is_err(), "{bad:?}");
        }
    }
}
