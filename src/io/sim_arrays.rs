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
//! `i32`, 8·k is k `f64`. Nothing here allocates more than the file's own size.

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

/// Decodes an element-layout file (`u32` n, then n elements). `expect` is the element count
/// the caller knows from the positions, if any: with it, an empty body and a size that is a
/// multiple of several layouts are decided without guessing.
///
/// # Errors
/// A one-line message if the file is shorter than its count, or its size fits no layout.
pub fn decode_elements(bytes: &[u8], expect: Option<usize>) -> Result<SimArray, String> {
    let Some((head, body)) = bytes.split_first_chunk::<4>() else {
        return Err(format!(
            "{} bytes: shorter than its 4-byte count",
            bytes.len()
        ));
    };
    let n = u32::from_le_bytes(*head) as usize;
    if let Some(e) = expect
        && e != n
    {
        return Err(format!(
            "holds {n} elements, but the positions have {e} particles"
        ));
    }
    if n == 0 {
        return if body.is_empty() {
            Ok(SimArray {
                len: 0,
                components: 1,
                stored: "float64",
                values: Vec::new(),
            })
        } else {
            Err(format!("count 0 but {} bytes of data follow", body.len()))
        };
    }
    let have = body.len();
    if have % n != 0 {
        return Err(format!(
            "{have} bytes after the count {n} are not a whole number of elements \
             (truncated or not an array file)"
        ));
    }
    let per = have / n;
    match per {
        4 => Ok(SimArray {
            len: n,
            components: 1,
            stored: "int32",
            values: body
                .chunks_exact(4)
                .map(|c| f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])))
                .collect(),
        }),
        8 | 16 | 24 | 32 | 72 => Ok(SimArray {
            len: n,
            components: per / 8,
            stored: "float64",
            values: body
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                .collect(),
        }),
        _ => Err(format!(
            "{per} bytes an element for count {n}: none of the simulator's layouts \
             (4: int32; 8, 16, 24, 32, 72: 1, 2, 3, 4 or 9 float64)"
        )),
    }
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
        assert!(e.contains("whole number"), "{e}");
        let e = decode_elements(&elements(1, &[0.0; 5]), None).unwrap_err();
        assert!(e.contains("none of"), "{e}");
        let e = decode_elements(&elements(2, &[1.0, 2.0]), Some(3)).unwrap_err();
        assert!(e.contains("3 particles"), "{e}");
        let e = decode_elements(&elements(0, &[1.0]), None).unwrap_err();
        assert!(e.contains("count 0"), "{e}");
        let e = decode_elements(&elements(u32::MAX, &[1.0]), None).unwrap_err();
        assert!(e.contains("whole number"), "{e}");
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
