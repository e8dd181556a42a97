//! Wavefront OBJ reader for triangle meshes: `v` (positions), `vn` (normals) and `f` (polygons,
//! fan-triangulated). Face corners may be `v`, `v/vt`, `v/vt/vn` or `v//vn`, with 1-based or
//! negative (relative) indices. Texture coordinates, groups, materials, smoothing groups,
//! lines and points are ignored. Extra values after `v x y z` (a `w` or vertex colours) are
//! ignored.
//!
//! OBJ normals belong to face corners; a vertex's normal is the normalised sum of the normals
//! of its corners (so a smooth-shaded export keeps its normals exactly). If any face corner
//! has no normal, the mesh has none and the geometry computes them. OBJ has no per-vertex
//! thickness: give a particle cloud to transfer it from, or a default thickness.

use std::path::Path;

use glam::Vec3;

use super::columns::show;
use super::{format_error, read_file};
use crate::error::{Error, Result};
use crate::pointcloud::{PointCloud, TriangleMesh};

/// Name used in error messages.
const FORMAT: &str = "OBJ";

/// Reads the OBJ file at `path` (see the module docs).
///
/// Cost: one pass over the file's text, which is held in memory while reading.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read; [`Error::Format`] naming the file and line for a
/// malformed number, a face with an index out of range, or a file without faces.
pub fn read(path: &Path) -> Result<TriangleMesh> {
    let bytes = read_file(path)?;
    parse(&bytes).map_err(|m| format_error(path, FORMAT, m))
}

/// Parses OBJ text; errors are one-line messages with the line number.
fn parse(bytes: &[u8]) -> std::result::Result<TriangleMesh, String> {
    let mut positions: Vec<Vec3> = Vec::new();
    let mut file_normals: Vec<Vec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    // Per triangle corner: index into `file_normals`, or None.
    let mut corner_normals: Vec<Option<u32>> = Vec::new();
    let mut corners: Vec<(u32, Option<u32>)> = Vec::new();
    for (n, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_no = n + 1;
        let Ok(line) = std::str::from_utf8(raw) else {
            return Err(format!("line {line_no}: not text (binary data?)"));
        };
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_ascii_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let at = |m: String| format!("line {line_no}: {m}");
        let three = |words: &mut std::str::SplitAsciiWhitespace<'_>, what: &str| {
            let mut v = [0.0f32; 3];
            for c in &mut v {
                let w = words
                    .next()
                    .ok_or_else(|| at(format!("'{what}' needs three numbers")))?;
                *c = w
                    .parse::<f32>()
                    .map_err(|_| at(format!("'{}' is not a number", show(w))))?;
            }
            Ok::<Vec3, String>(Vec3::from(v))
        };
        match keyword {
            "v" => positions.push(three(&mut words, "v")?),
            "vn" => file_normals.push(three(&mut words, "vn")?),
            "f" => {
                corners.clear();
                for w in words {
                    corners.push(corner(w, positions.len(), file_normals.len()).map_err(at)?);
                }
                if corners.len() < 3 {
                    return Err(at(format!(
                        "a face needs at least 3 vertices, got {}",
                        corners.len()
                    )));
                }
                for k in 1..corners.len() - 1 {
                    let c = [corners[0], corners[k], corners[k + 1]];
                    triangles.push(c.map(|c| c.0));
                    corner_normals.extend(c.map(|c| c.1));
                }
            }
            "vt" | "vp" | "o" | "g" | "s" | "usemtl" | "mtllib" | "l" | "p" | "cstype" | "deg"
            | "bmat" | "step" | "curv" | "curv2" | "surf" | "parm" | "trim" | "hole" | "scrv"
            | "sp" | "end" | "con" | "mg" | "bevel" | "c_interp" | "d_interp" | "lod"
            | "shadow_obj" | "trace_obj" | "ctech" | "stech" => {}
            other => {
                return Err(at(format!(
                    "unknown keyword '{}' (not an OBJ file?)",
                    show(other)
                )));
            }
        }
    }
    if triangles.is_empty() {
        return Err("no faces (f lines): not a mesh".to_string());
    }
    let normals = corner_normals
        .iter()
        .all(Option::is_some)
        .then(|| vertex_normals(positions.len(), &triangles, &corner_normals, &file_normals));
    Ok(TriangleMesh {
        vertices: PointCloud {
            positions,
            normals,
            ..PointCloud::default()
        },
        triangles,
    })
}

/// One face corner `v`, `v/vt` or `v/vt/vn`: its vertex and normal indices (0-based), checked
/// against the `vertices` and `normals` read so far.
fn corner(
    w: &str,
    vertices: usize,
    normals: usize,
) -> std::result::Result<(u32, Option<u32>), String> {
    let mut parts = w.split('/');
    let v = index(parts.next().unwrap_or(""), vertices)
        .map_err(|m| format!("face corner '{}': vertex {m}", show(w)))?;
    let _texture = parts.next();
    let vn = match parts.next() {
        Some(s) if !s.is_empty() => {
            Some(index(s, normals).map_err(|m| format!("face corner '{}': normal {m}", show(w)))?)
        }
        _ => None,
    };
    Ok((v, vn))
}

/// Per-vertex normals: the normalised sum of the file's normals at each vertex's corners.
fn vertex_normals(
    vertices: usize,
    triangles: &[[u32; 3]],
    corner_normals: &[Option<u32>],
    file_normals: &[Vec3],
) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; vertices];
    for (t, c) in triangles.iter().zip(corner_normals.chunks_exact(3)) {
        for (v, vn) in t.iter().zip(c) {
            let vn = file_normals[vn.expect("checked") as usize];
            sum[*v as usize] += vn.normalize_or_zero();
        }
    }
    sum.into_iter().map(Vec3::normalize_or_zero).collect()
}

/// A 1-based (or negative, relative) OBJ index into a list of `len` items, as 0-based.
fn index(s: &str, len: usize) -> std::result::Result<u32, String> {
    let i: i64 = s
        .parse()
        .map_err(|_| format!("index '{}' is not an integer", show(s)))?;
    let zero_based = if i > 0 { i - 1 } else { len as i64 + i };
    if i == 0 || zero_based < 0 || zero_based >= len as i64 {
        return Err(format!("index {i} is out of range (1..={len} so far)"));
    }
    Ok(zero_based as u32)
}

/// Reads a triangle mesh: PLY (by its first bytes or `.ply`, see
/// [`super::ply::read_mesh`]) or OBJ (`.obj`, see [`read`]). `opts` apply to PLY attributes.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read; [`Error::Format`] for a malformed file or an
/// unknown format.
pub fn read_mesh(path: &Path, opts: &super::ReadOptions) -> Result<TriangleMesh> {
    let is_ply = matches!(super::detect_format(path), Ok(super::CloudFormat::Ply));
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if is_ply {
        super::ply::read_mesh(path, opts)
    } else if ext.as_deref() == Some("obj") {
        read(path)
    } else {
        // Surface the read error (missing file, directory) before the format complaint.
        read_file(path)?;
        Err(Error::Format {
            path: path.to_path_buf(),
            format: "mesh",
            message: "unrecognised mesh format (supported: PLY with faces, OBJ)".into(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_fan_and_relative_indices() {
        let m = parse(b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf -4 -2 -1\n").unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
        assert!(m.vertices.normals.is_none());
        assert_eq!(m.vertices.positions[2], Vec3::new(1.0, 1.0, 0.0));
    }

    #[test]
    fn corner_normals_become_vertex_normals() {
        let text = "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvt 0 0\n\
                    f 1/1/1 2//1 3/1/1 # tri\n";
        let m = parse(text.as_bytes()).unwrap();
        assert_eq!(m.vertices.normals.unwrap(), vec![Vec3::Z; 3]);
    }

    #[test]
    fn malformed_lines_give_one_line_errors() {
        let cases: [(&str, &str); 7] = [
            ("v 0 0\n", "line 1: 'v' needs three numbers"),
            ("v 0 0 x\n", "'x' is not a number"),
            ("v 0 0 0\nf 1 2 3\n", "index 2 is out of range"),
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3 vertices"),
            ("v 0 0 0\nf 1 1 1/1/4\n", "normal index 4"),
            ("v 0 0 0\n", "no faces"),
            ("ply\nformat ascii 1.0\n", "unknown keyword 'ply'"),
        ];
        for (text, want) in cases {
            let e = parse(text.as_bytes()).unwrap_err();
            assert!(e.contains(want), "{text:?}: {e}");
            assert!(!e.contains('\n'));
        }
        assert!(index("0", 3).is_err() && index("-4", 3).is_err() && index("1.5", 3).is_err());
    }
}
