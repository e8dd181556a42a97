//! PLY header: the data model and a small strict parser.
//!
//! Written by hand rather than with ply-rs-bw's parser because (a) ply-rs-bw keys properties
//! by name in a map, so a repeated property name silently drops a column and shifts every
//! binary offset after it, (b) its errors are multi-line, and (c) we need the exact byte offset
//! where the body starts; the grammar is ~100 lines anyway.

use std::collections::HashSet;
use std::io::Read;

use super::Fail;
use super::source::{Line, Source};

/// Longest header line accepted, in bytes.
const MAX_HEADER_LINE: usize = 64 * 1024;

/// Body encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Encoding {
    Ascii,
    BinaryLe,
    BinaryBe,
}

/// A PLY scalar type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// Parses a type name, including the sized aliases (`int8`, `float32`, ...).
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Size in bytes in a binary body.
    pub(super) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(super) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// Type of a property.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PropKind {
    Scalar(Scalar),
    /// A list: an integer count followed by that many items.
    List {
        count: Scalar,
        item: Scalar,
    },
}

impl Scalar {
    /// The sized type name (`int8` .. `float64`).
    pub(super) fn name(self) -> &'static str {
        match self {
            Scalar::I8 => "int8",
            Scalar::U8 => "uint8",
            Scalar::I16 => "int16",
            Scalar::U16 => "uint16",
            Scalar::I32 => "int32",
            Scalar::U32 => "uint32",
            Scalar::F32 => "float32",
            Scalar::F64 => "float64",
        }
    }
}

impl PropKind {
    /// The stored type as `filmsplat info` prints it: `float32`, `list uint8 int32`, ...
    pub(super) fn name(self) -> String {
        match self {
            PropKind::Scalar(s) => s.name().to_string(),
            PropKind::List { count, item } => format!("list {} {}", count.name(), item.name()),
        }
    }
}

/// One `property` line.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Property {
    pub name: String,
    pub kind: PropKind,
}

/// One `element` line and its properties.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Element {
    pub name: String,
    pub count: u64,
    pub props: Vec<Property>,
}

impl Element {
    /// Record size in a binary body if the element has no list property.
    pub(super) fn fixed_stride(&self) -> Option<usize> {
        self.props
            .iter()
            .map(|p| match p.kind {
                PropKind::Scalar(s) => Some(s.size()),
                PropKind::List { .. } => None,
            })
            .sum()
    }

    /// Fewest bytes one record can occupy: binary, scalars plus list counts (empty lists);
    /// ASCII, one byte per property.
    pub(super) fn min_record_bytes(&self, enc: Encoding) -> u64 {
        self.props
            .iter()
            .map(|p| match (enc, p.kind) {
                (Encoding::Ascii, _) => 1,
                (_, PropKind::Scalar(s)) => s.size() as u64,
                (_, PropKind::List { count, .. }) => count.size() as u64,
            })
            .sum()
    }
}

/// A parsed header.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Header {
    pub encoding: Encoding,
    pub elements: Vec<Element>,
    /// Number of header lines including `ply` and `end_header` (ASCII line numbers continue).
    pub lines: usize,
    /// The header says its vertices are droplets (`comment filmsplat part droplets`, which
    /// [`crate::io::write_droplets_ply`] writes).
    pub droplets: bool,
}

/// Shows untrusted header text in a one-line message: escaped and shortened.
pub(super) fn show(text: &str) -> String {
    let mut s: String = text.chars().take(40).flat_map(char::escape_debug).collect();
    if text.chars().count() > 40 {
        s.push('…');
    }
    s
}

/// The vertex count of a PLY header (`element vertex n`) in a file's first bytes, if any
/// (for size estimates before reading).
pub(crate) fn header_count(head: &[u8]) -> Option<u64> {
    crate::io::num::keyword_count(head, b"element vertex ")
}

/// Parses the header, leaving `src` at the first body byte.
pub(super) fn parse<R: Read>(src: &mut Source<R>) -> Result<Header, Fail> {
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut n = 0usize;
    // Names seen so far (sets keep huge adversarial headers linear).
    let mut element_names = HashSet::new();
    let mut prop_names = HashSet::new();
    let mut droplets = false;
    loop {
        n += 1;
        let raw = match src.read_line(MAX_HEADER_LINE)? {
            Line::Text(t) => t,
            Line::Eof if n == 1 => return Err(Fail::msg("empty file")),
            Line::Eof => return Err(Fail::msg("header has no end_header line")),
            Line::TooLong if n == 1 => {
                return Err(Fail::msg("not a PLY file (no 'ply' first line)"));
            }
            Line::TooLong => {
                return Err(Fail::msg(format!(
                    "header line {n} is longer than {MAX_HEADER_LINE} bytes (missing end_header?)"
                )));
            }
        };
        let Ok(line) = std::str::from_utf8(raw) else {
            return Err(Fail::msg(if n == 1 {
                "not a PLY file (no 'ply' first line)".to_string()
            } else {
                format!("header line {n} is not text (missing end_header?)")
            }));
        };
        let mut words = line.split_ascii_whitespace();
        let keyword = words.next().unwrap_or("");
        if n == 1 {
            if keyword != "ply" || words.next().is_some() {
                return Err(Fail::msg("not a PLY file (no 'ply' first line)"));
            }
            continue;
        }
        let rest: Vec<&str> = words.collect();
        let bad = |what: &str| Fail::msg(format!("header line {n}: {what}: '{}'", show(line)));
        match keyword {
            "comment" => droplets |= rest == ["filmsplat", "part", "droplets"],
            "obj_info" | "" => {}
            "format" => {
                let enc = match rest.first().copied() {
                    Some("ascii") => Encoding::Ascii,
                    Some("binary_little_endian") => Encoding::BinaryLe,
                    Some("binary_big_endian") => Encoding::BinaryBe,
                    _ => {
                        return Err(bad(
                            "unknown format (expected ascii, binary_little_endian or binary_big_endian)",
                        ));
                    }
                };
                if rest.len() != 2 {
                    return Err(bad("expected 'format <encoding> <version>'"));
                }
                if encoding.is_some_and(|e| e != enc) {
                    return Err(bad("contradicts the earlier format line"));
                }
                encoding = Some(enc);
            }
            "element" => {
                let [name, count] = rest[..] else {
                    return Err(bad("expected 'element <name> <count>'"));
                };
                let count = count
                    .parse::<u64>()
                    .map_err(|_| bad("invalid element count"))?;
                if !element_names.insert(name.to_string()) {
                    return Err(bad("element declared twice"));
                }
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            "property" => {
                let element_index = elements.len();
                let Some(element) = elements.last_mut() else {
                    return Err(bad("property before any element"));
                };
                let (kind, name) = match rest[..] {
                    ["list", count, item, name] => {
                        let (Some(count), Some(item)) = (Scalar::parse(count), Scalar::parse(item))
                        else {
                            return Err(bad("unknown type"));
                        };
                        if !count.is_integer() {
                            return Err(bad("list count type must be an integer type"));
                        }
                        (PropKind::List { count, item }, name)
                    }
                    [ty, name] => match Scalar::parse(ty) {
                        Some(s) => (PropKind::Scalar(s), name),
                        None => return Err(bad("unknown type")),
                    },
                    _ => {
                        return Err(bad(
                            "expected 'property <type> <name>' or 'property list <type> <type> <name>'",
                        ));
                    }
                };
                if !prop_names.insert((element_index, name.to_string())) {
                    return Err(bad("property declared twice in this element"));
                }
                element.props.push(Property {
                    name: name.to_string(),
                    kind,
                });
            }
            "end_header" => break,
            _ => return Err(bad("unknown header keyword (missing end_header?)")),
        }
    }
    let Some(encoding) = encoding else {
        return Err(Fail::msg("header has no format line"));
    };
    Ok(Header {
        encoding,
        elements,
        lines: n,
        droplets,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_str(s: &str) -> Result<(Header, u64), String> {
        let mut src = Source::new(s.as_bytes(), None);
        match parse(&mut src) {
            Ok(h) => Ok((h, src.position())),
            Err(Fail::Msg(m)) => Err(m),
            Err(Fail::Io(e)) => Err(e.to_string()),
        }
    }

    #[test]
    fn full_header() {
        let text = "ply\r\nformat binary_big_endian 1.0\ncomment hi\nobj_info x\n\
            element face 2\nproperty list uint8 int32 vertex_indices\n\
            element vertex 3\nproperty float64 x\nproperty  uchar   red \nend_header\nBODY";
        let (h, pos) = parse_str(text).unwrap();
        assert_eq!(pos as usize, text.len() - 4);
        assert_eq!(h.encoding, Encoding::BinaryBe);
        assert_eq!(h.lines, 10);
        assert_eq!(h.elements.len(), 2);
        let face = &h.elements[0];
        assert_eq!((face.name.as_str(), face.count), ("face", 2));
        assert_eq!(
            face.props[0].kind,
            PropKind::List {
                count: Scalar::U8,
                item: Scalar::I32
            }
        );
        assert_eq!(face.fixed_stride(), None);
        assert_eq!(face.min_record_bytes(Encoding::BinaryBe), 1);
        let v = &h.elements[1];
        assert_eq!(v.props[1].name, "red");
        assert_eq!(v.fixed_stride(), Some(9));
        assert_eq!(v.min_record_bytes(Encoding::Ascii), 2);
    }

    #[test]
    fn header_errors() {
        let cases = [
            ("", "empty file"),
            ("plx\n", "not a PLY file"),
            ("ply\nformat ascii 1.0\nelement vertex 1\n", "no end_header"),
            (
                "ply\nformat binary_middle_endian 1.0\nend_header\n",
                "unknown format",
            ),
            ("ply\nelement vertex 1\nend_header\n", "no format line"),
            (
                "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
                "before any element",
            ),
            (
                "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n",
                "invalid element count",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nproperty flt x\nend_header\n",
                "unknown type",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nproperty list float int a\nend_header\n",
                "integer",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nproperty float x\nproperty int x\nend_header\n",
                "twice",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nelement v 2\nend_header\n",
                "twice",
            ),
            (
                "ply\nformat ascii 1.0\nbogus\nend_header\n",
                "line 3: unknown header keyword",
            ),
            (
                "ply\nformat ascii 1.0\nformat binary_little_endian 1.0\nend_header\n",
                "contradicts",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\n\u{1}\u{2}\u{ff}\n",
                "unknown header keyword",
            ),
        ];
        for (text, want) in cases {
            let e = parse_str(text).expect_err(text);
            assert!(e.contains(want), "{text:?}: got {e:?}, want {want:?}");
            assert!(!e.contains('\n'), "{e:?}");
        }
    }

    #[test]
    fn non_text_header_and_long_lines() {
        let mut bytes = b"ply\nformat ascii 1.0\n".to_vec();
        bytes.extend([0xff, 0xfe, b'\n']);
        let mut src = Source::new(&bytes[..], None);
        assert!(matches!(parse(&mut src), Err(Fail::Msg(m)) if m.contains("line 3 is not text")));
        let long = format!("ply\ncomment {}\n", "a".repeat(MAX_HEADER_LINE + 10));
        assert!(parse_str(&long).unwrap_err().contains("longer than"));
        assert!(show(&"é".repeat(50)).ends_with('…'));
    }
}
