//! Wavefront OBJ triangle meshes (for props): `v x y z` vertices and `f` faces (`i`, `i/t`,
//! `i/t/n`, `i//n`; 1-based or negative = relative), polygons split into fans. Other
//! statements (normals, texture coordinates, groups, materials) are ignored.

use crate::{Error, Result};
use std::path::Path;

/// Vertices and triangles of an OBJ mesh.
#[derive(Debug, Clone, Default)]
pub struct ObjMesh {
    /// Vertex positions.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, 0-based vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

/// Reads an OBJ file. Errors name the file and line.
pub fn read_obj(path: &Path) -> Result<ObjMesh> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_obj(&text).map_err(|(line, message)| Error::Format {
        path: path.into(),
        format: "OBJ",
        message: format!("line {line}: {message}"),
    })
}

fn parse_obj(text: &str) -> std::result::Result<ObjMesh, (usize, String)> {
    let mut m = ObjMesh::default();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let mut parts = line.split_whitespace();
        match parts.next() {
            Some("v") => {
                let mut v = [0.0f32; 3];
                for c in &mut v {
                    *c = parts
                        .next()
                        .and_then(|s| s.parse().ok())
                        .filter(|x: &f32| x.is_finite())
                        .ok_or_else(|| (line_no, "vertex needs three finite numbers".into()))?;
                }
                m.vertices.push(v);
            }
            Some("f") => {
                let n = m.vertices.len() as i64;
                let idx: Vec<u32> = parts
                    .map(|p| {
                        let first = p.split('/').next().unwrap_or("");
                        let k: i64 = first
                            .parse()
                            .map_err(|_| (line_no, format!("bad face index '{p}'")))?;
                        let k = if k < 0 { n + k } else { k - 1 };
                        if k < 0 || k >= n {
                            return Err((
                                line_no,
                                format!("face index {first} out of range (1..={n})"),
                            ));
                        }
                        Ok(k as u32)
                    })
                    .collect::<std::result::Result<_, _>>()?;
                if idx.len() < 3 {
                    return Err((line_no, "a face needs at least 3 vertices".into()));
                }
                for k in 1..idx.len() - 1 {
                    m.triangles.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if m.triangles.is_empty() {
        return Err((text.lines().count().max(1), "no faces".into()));
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_split_into_fans_and_bad_lines_are_named() {
        let m = parse_obj(
            "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 -1//1\n",
        )
        .unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(parse_obj("v 0 0\n").unwrap_err().0, 1);
        let e = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap_err();
        assert!(e.0 == 4 && e.1.contains("out of range"), "{e:?}");
    }
}
