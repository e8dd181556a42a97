//! The binary arrays the thin-film simulators write (wang-mengdi/sph-thin-film and
//! wang-mengdi/melp-thin-film share the writers of `src/common/ArrayIO.h` and the float
//! "fast IO" of `src/reservoir/Particles.cpp` / `src/geometry/RenderFunc.cpp`).
//!
//! Two layouts, both little-endian:
//!
//! | layout | header | body | writers |
//! |---|---|---|---|
//! | [`Layout::Elements`] | `u32` n = number of **elements** | n × k `f64` (k = 1 scalar, 2 or 3 vector, 4 = 2×2 or 9 = 3×3 matrix, column-major as Eigen stores it), or n × `i32` | `Write_Scalar_Array`, `Write_Vector_Array(_3D)`, `Write_Matrix_Array` |
//! | [`Layout::Floats`] | `i32` m = number of **floats** | m × `f32`: 4 a point (x y z 0) or 8 a segment/circle (x y z 0, x' y' z' 0) | `Write_To_File_3d_Fast`, `Write_Points_Float`, `Write_Vectors_Float`, `Write_Segments_To_File_3d_Fast` |
//!
//! In the element layout the type is decided by the bytes per element, `body / n`: 4 is
//! `i32`, 8·k is k `f64`. [`decode_layout`] is the one decoder of that layout (frame,
//! snapshot and MELP folders; each names the types it accepts). Nothing here allocates more
//! than the file's own size.

/// How a simulator array file is laid out (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// `u32` element count, then `f64` (or `i32`) values.
    Elements,
    /// `i32` float count, then `f32` values.
    Floats,
}

/// A decoded array: `components` values an element, all as f64.
#[derive(Debug, Clone, PartialEq)]
pub struct SimArray {
    /// Number of elements (particles).
    pub len: usize,
    /// Values per element: 1, 2, 3, 4, 9 (f64 layouts), 1 for `i32`, 4 or 8 for float files.
    pub components: usize,
    /// The stored type: `float64`, `int32` or `float32`.
    pub stored: &'static str,
    /// `len × components` values, element by element.
    pub values: Vec<f64>,
}

impl SimArray {
    /// Component `c` of element `i`.
    #[inline]
    pub fn get(&self, i: usize, c: usize) -> f64 {
        self.values[i * self.components + c]
    }

    /// Components `c..c + 3` of every element as vectors (positions at 0, the normal of a
    /// float circle file at 4). Needs `c + 3 <= components`.
    pub fn vec3s(&self, c: usize) -> Vec<glam::Vec3> {
        (0..self.len)
            .map(|i| {
                let f = |k: usize| self.get(i, c + k) as f32;
                glam::Vec3::new(f(0), f(1), f(2))
            })
            .collect()
    }

    /// Components `c..c + 3` of every element, flat (x y z x y z ...), as f32.
    pub fn flat3(&self, c: usize) -> Vec<f32> {
        self.vec3s(c).iter().flat_map(|v| v.to_array()).collect()
    }
}

/// One element type of the element layout: its size, what it decodes to, and its name in
/// messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ElementType {
    /// Bytes an element.
    pub bytes: u64,
    /// Values an element.
    pub components: usize,
    /// The stored type: `float64` or `int32`.
    pub stored: &'static str,
    /// What messages call it (`scalars`, `3 float64`, ...).
    pub name: &'static str,
}

/// Shorthand for an `f64` element type of `k` values.
const fn f64s(k: usize, name: &'static str) -> ElementType {
    ElementType {
        bytes: 8 * k as u64,
        components: k,
        stored: "float64",
        name,
    }
}

/// Every element type the simulators' `Write_Array` family writes: 1, 2, 3, 4 (2×2) or 9 (3×3)
/// `f64`, or one `i32` (snapshot and MELP folders). An empty file is `float64` scalars.
pub const ANY_ELEMENT: &[ElementType] = &[
    f64s(1, "float64"),
    f64s(2, "2 float64"),
    f64s(3, "3 float64"),
    f64s(4, "4 float64"),
    f64s(9, "9 float64"),
    ElementType {
        bytes: 4,
        components: 1,
        stored: "int32",
        name: "int32",
    },
];

/// The `*_bin` files of a frame folder: `f64` scalars or 3-vectors.
pub const SCALAR_OR_VECTOR: &[ElementType] = &[f64s(1, "scalars"), f64s(3, "vectors")];

/// An element-layout file checked and typed, its values not yet converted (so a reader that
/// keeps `f32` never holds an `f64` copy).
#[derive(Debug, Clone, Copy)]
pub struct Elements<'a> {
    /// Number of elements (particles).
    pub len: usize,
    /// The elements' type.
    pub kind: ElementType,
    /// The `len × kind.bytes` bytes after the count.
    body: &'a [u8],
}

impl Elements<'_> {
    /// The values, element by element, as `f64`.
    pub fn values(&self) -> impl Iterator<Item = f64> + '_ {
        let int = self.kind.stored == "int32";
        self.body
            .chunks_exact(if int { 4 } else { 8 })
            .map(move |c| {
                if int {
                    f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                } else {
                    f64::from_le_bytes(c.try_into().unwrap_or([0; 8]))
                }
            })
    }

    /// The values as `f32` (what a point cloud keeps).
    pub fn values_f32(&self) -> Vec<f32> {
        self.values().map(|v| v as f32).collect()
    }

    /// All values as a [`SimArray`].
    pub fn to_array(&self) -> SimArray {
        SimArray {
            len: self.len,
            components: self.kind.components,
            stored: self.kind.stored,
            values: self.values().collect(),
        }
    }
}

/// The one decoder of the element layout (`u32` n, then n elements of one of `types`, the
/// type told by the size): checks the count against the file's size before anything is
/// allocated. `expect` is the element count the caller knows from the positions, if any.
/// Never panics, whatever the bytes.
///
/// # Errors
/// A one-line message: shorter than the count; a count other than `expect`; data after a
/// count of 0; a size that fits none of `types` (saying where a truncated file's data runs
/// out, as the smallest type it is too short for).
pub fn decode_layout<'a>(
    bytes: &'a [u8],
    expect: Option<usize>,
    types: &[ElementType],
) -> Result<Elements<'a>, String> {
    let Some((head, body)) = bytes.split_first_chunk::<4>() else {
        return Err(format!(
            "{} bytes: shorter than its 4-byte count",
            bytes.len()
        ));
    };
    let n = u32::from_le_bytes(*head);
    if let Some(e) = expect
        && e as u64 != u64::from(n)
    {
        return Err(format!(
            "holds {n} elements, but the positions have {e} particles"
        ));
    }
    let (n, have) = (u64::from(n), body.len() as u64);
    if n == 0 && have > 0 {
        return Err(format!("count 0 but {have} bytes of data follow"));
    }
    let Some(first) = types.first() else {
        return Err("no element type to read".to_string());
    };
    if n == 0 {
        return Ok(Elements {
            len: 0,
            kind: *first,
            body,
        });
    }
    if let Some(t) = types.iter().find(|t| t.bytes * n == have) {
        return Ok(Elements {
            len: n as usize,
            kind: *t,
            body,
        });
    }
    Err(size_mismatch(bytes.len() as u64, n, types))
}

/// The message for an element file of `size` bytes whose count `n` fits none of `types`.
fn size_mismatch(size: u64, n: u64, types: &[ElementType]) -> String {
    let have = size - 4;
    let needs = or_list(types.iter().enumerate().map(|(i, t)| {
        let unit = if i == 0 { " bytes" } else { "" };
        format!("{}{unit} ({})", t.bytes * n, t.name)
    }));
    let Some(t) = types
        .iter()
        .filter(|t| t.bytes * n > have)
        .min_by_key(|t| t.bytes)
    else {
        let sizes = types
            .iter()
            .map(|t| format!("4 + {}n = {} ({})", t.bytes, 4 + t.bytes * n, t.name));
        let sizes: Vec<String> = sizes.collect();
        let fits = if let [a, b] = sizes.as_slice() {
            format!("neither {a} nor {b}")
        } else {
            format!("none of {}", sizes.join(", "))
        };
        return format!("size {size} bytes matches {fits} for its count n = {n}");
    };
    let what = if types.iter().any(|u| u.bytes * n < have) {
        "truncated or malformed"
    } else {
        "truncated"
    };
    format!(
        "{what}: count {n} needs {needs} after the count, the file has {have}: as {} the data \
         runs out at particle {} (byte offset {})",
        t.name,
        have / t.bytes,
        4 + have / t.bytes * t.bytes
    )
}

/// `a`, `a or b`, `a, b or c`.
fn or_list(items: impl Iterator<Item = String>) -> String {
    let items: Vec<String> = items.collect();
    match items.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        Some((last, _)) => last.clone(),
        None => String::new(),
    }
}

/// Decodes an element-layout file of any of the simulators' types ([`ANY_ELEMENT`]) into
/// `f64` values: [`decode_layout`] collected.
///
/// # Errors
/// As [`decode_layout`].
pub fn decode_elements(bytes: &[u8], expect: Option<usize>) -> Result<SimArray, String> {
    decode_layout(bytes, expect, ANY_ELEMENT).map(|e| e.to_array())
}

/// The number of elements of `per` floats a float-layout file holds, from its 4-byte header
/// `head` and the byte length of the rest, `body_bytes`: the checks of [`decode_floats`]
/// without the body (so a header alone can be checked).
///
/// # Errors
/// As [`decode_floats`].
pub fn float_count(head: [u8; 4], body_bytes: u64, per: usize) -> Result<usize, String> {
    let m = i32::from_le_bytes(head);
    let Ok(m) = usize::try_from(m) else {
        return Err(format!("negative float count {m}"));
    };
    if body_bytes != 4 * m as u64 {
        return Err(format!(
            "float count {m} needs {} bytes after the count, the file has {body_bytes}",
            4 * m as u64,
        ));
    }
    if m % per != 0 {
        return Err(format!(
            "float count {m} is not a multiple of {per} floats an element"
        ));
    }
    Ok(m / per)
}

/// Decodes a float-layout file (`i32` m floats, then m `f32`) into elements of `per` floats
/// (4 for points, 8 for segments and circles).
///
/// # Errors
/// A one-line message if the count is negative, does not match the size, or is not a
/// multiple of `per`.
pub fn decode_floats(bytes: &[u8], per: usize) -> Result<SimArray, String> {
    let Some((head, body)) = bytes.split_first_chunk::<4>() else {
        return Err(format!(
            "{} bytes: shorter than its 4-byte count",
            bytes.len()
        ));
    };
    let m = float_count(*head, body.len() as u64, per)? * per;
    Ok(SimArray {
        len: m / per,
        components: per,
        stored: "float32",
        values: body
            .chunks_exact(4)
            .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn elements(n: u32, vals: &[f64]) -> Vec<u8> {
        let mut b = n.to_le_bytes().to_vec();
        vals.iter().for_each(|v| b.extend(v.to_le_bytes()));
        b
    }

    #[test]
    fn element_layouts_by_bytes_per_element() {
        let a = decode_elements(&elements(2, &[1.0, 2.0]), None).unwrap();
        assert_eq!((a.len, a.components, a.stored), (2, 1, "float64"));
        let a = decode_elements(&elements(1, &[0.0; 9]), Some(1)).unwrap();
        assert_eq!(a.components, 9);
        let a = decode_elements(&elements(2, &[0.5; 4]), None).unwrap();
        assert_eq!(a.components, 2);
        let mut ints = 3u32.to_le_bytes().to_vec();
        for v in [7i32, -1, 0] {
            ints.extend(v.to_le_bytes());
        }
        let a = decode_elements(&ints, None).unwrap();
        assert_eq!(
            (a.stored, a.values.clone()),
            ("int32", vec![7.0, -1.0, 0.0])
        );
        assert_eq!(decode_elements(&elements(0, &[]), None).unwrap().len, 0);
    }

    #[test]
    fn element_errors() {
        assert!(
            decode_elements(&[1, 0], None)
                .unwrap_err()
                .contains("4-byte")
        );
        let e = decode_elements(&elements(5, &[1.0, 2.0, 3.0]), None).unwrap_err();
        assert!(
            e.contains("truncated or malformed") && e.contains("at particle 3"),
            "{e}"
        );
        let e = decode_elements(&elements(1, &[0.0; 5]), None).unwrap_err();
        assert!(e.contains("as 9 float64 the data runs out"), "{e}");
        let e = decode_elements(&elements(1, &[0.0; 10]), None).unwrap_err();
        assert!(e.contains("none of 4 + 8n = 12 (float64),"), "{e}");
        let e = decode_elements(&elements(2, &[1.0, 2.0]), Some(3)).unwrap_err();
        assert!(e.contains("3 particles"), "{e}");
        let e = decode_elements(&elements(0, &[1.0]), None).unwrap_err();
        assert!(e.contains("count 0"), "{e}");
        let e = decode_elements(&elements(u32::MAX, &[1.0]), None).unwrap_err();
        assert!(e.contains("truncated:") && e.contains("as int32"), "{e}");
    }

    #[test]
    fn float_layout_counts_floats() {
        let mut b = 8i32.to_le_bytes().to_vec();
        for v in [1.0f32, 2.0, 3.0, 0.0, 4.0, 5.0, 6.0, 0.0] {
            b.extend(v.to_le_bytes());
        }
        let a = decode_floats(&b, 4).unwrap();
        assert_eq!((a.len, a.get(1, 2)), (2, 6.0));
        assert_eq!(decode_floats(&b, 8).unwrap().len, 1);
        let mut bad = b.clone();
        bad[..4].copy_from_slice(&9i32.to_le_bytes());
        assert!(decode_floats(&bad, 4).unwrap_err().contains("needs 36"));
        bad[..4].copy_from_slice(&(-4i32).to_le_bytes());
        assert!(decode_floats(&bad, 4).unwrap_err().contains("negative"));
        let mut six = 6i32.to_le_bytes().to_vec();
        six.extend([0u8; 24]);
        assert!(decode_floats(&six, 4).unwrap_err().contains("multiple"));
    }
}
