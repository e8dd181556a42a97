//! Writing particle clouds (and triangle meshes) as binary little-endian PLY (what
//! `filmsplat sample` writes).

use crate::error::{Error, Result};
use crate::pointcloud::{PointCloud, TriangleMesh};
use std::io::Write;
use std::path::Path;

/// Writes `cloud` to `path` as binary little-endian PLY: `x y z`, then `nx ny nz`, `rh`
/// (thickness in nm) and `radius` when present, then every extra attribute, all `float`.
/// Written to a temporary file and renamed, so a failure never leaves a partial file.
pub fn write_ply(path: &Path, cloud: &PointCloud) -> Result<()> {
    write_with_faces(path, cloud, &[], "")
}

/// Writes droplets (`cloud` with each droplet's `radius`, scene units) as [`write_ply`] does,
/// marked as droplets in the header (`comment filmsplat part droplets`), so that reading the
/// file back ([`crate::io::read_parts`]) gives a droplets part, not a film.
pub fn write_droplets_ply(path: &Path, cloud: &PointCloud) -> Result<()> {
    write_with_faces(path, cloud, &[], "comment filmsplat part droplets\n")
}

/// Writes `mesh` to `path` as binary little-endian PLY: its vertices as [`write_ply`] writes a
/// cloud, then element `face` with `property list uchar int vertex_indices`. Atomic.
pub fn write_mesh_ply(path: &Path, mesh: &TriangleMesh) -> Result<()> {
    write_with_faces(path, &mesh.vertices, &mesh.triangles, "")
}

/// Writes `cloud` and `faces`, with `comments` (whole header lines) after the first comment.
fn write_with_faces(
    path: &Path,
    cloud: &PointCloud,
    faces: &[[u32; 3]],
    comments: &str,
) -> Result<()> {
    let mut columns: Vec<(&str, &[f32])> = Vec::new();
    let n = cloud.len();
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by filmsplat\n{comments}element vertex {n}\n"
    );
    for name in ["x", "y", "z"] {
        header.push_str(&format!("property float {name}\n"));
    }
    if cloud.normals.is_some() {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if let Some(t) = &cloud.thickness_nm {
        columns.push(("rh", t));
    }
    if let Some(r) = &cloud.radius {
        columns.push(("radius", r));
    }
    for (name, v) in &cloud.extra {
        columns.push((name, v));
    }
    for (name, v) in &columns {
        if v.len() != n {
            return Err(Error::Internal(format!(
                "attribute {name} has {} values for {n} particles",
                v.len()
            )));
        }
        header.push_str(&format!("property float {name}\n"));
    }
    if !faces.is_empty() {
        header.push_str(&format!(
            "element face {}\nproperty list uchar int vertex_indices\n",
            faces.len()
        ));
    }
    header.push_str("end_header\n");
    let stride = 3 + if cloud.normals.is_some() { 3 } else { 0 } + columns.len();
    let mut body = Vec::with_capacity(header.len() + n * stride * 4);
    body.extend_from_slice(header.as_bytes());
    for i in 0..n {
        let mut put = |v: f32| body.extend_from_slice(&v.to_le_bytes());
        let p = cloud.positions[i];
        [p.x, p.y, p.z].into_iter().for_each(&mut put);
        if let Some(nrm) = &cloud.normals {
            let q = nrm[i];
            [q.x, q.y, q.z].into_iter().for_each(&mut put);
        }
        for (_, v) in &columns {
            put(v[i]);
        }
    }
    for f in faces {
        body.push(3);
        for &v in f {
            body.extend_from_slice(&(v as i32).to_le_bytes());
        }
    }
    crate::atomic::write_atomic(path, |w| w.write_all(&body).map_err(|e| Error::io(path, e)))
}
