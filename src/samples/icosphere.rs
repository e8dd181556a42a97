//! A triangulated sphere (subdivided icosahedron), e.g. the analytic surface of the bubble
//! sample for comparisons with meshed renders.

use std::collections::HashMap;

use glam::Vec3;

use crate::pointcloud::{PointCloud, TriangleMesh};

/// The sphere of `radius` about the origin as an icosahedron subdivided `subdivisions` times
/// (each step splits every triangle into four; 20·4^s triangles, 10·4^s + 2 vertices), with
/// outward unit normals and counter-clockwise winding seen from outside. No thickness.
/// `subdivisions` is capped at 9 (5.2M triangles).
pub fn icosphere(radius: f32, subdivisions: u32) -> TriangleMesh {
    let g = (1.0 + 5f32.sqrt()) / 2.0;
    let mut verts: Vec<Vec3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|v| Vec3::from(*v).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions.min(9) {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut split = |a: u32, b: u32, verts: &mut Vec<Vec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                verts.push((verts[a as usize] + verts[b as usize]).normalize());
                (verts.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let ab = split(a, b, &mut verts);
            let bc = split(b, c, &mut verts);
            let ca = split(c, a, &mut verts);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    TriangleMesh {
        vertices: PointCloud {
            positions: verts.iter().map(|v| *v * radius).collect(),
            normals: Some(verts),
            ..PointCloud::default()
        },
        triangles: tris,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_radius_and_outward_winding() {
        let m = icosphere(2.0, 2);
        assert_eq!(m.triangles.len(), 320);
        assert_eq!(m.vertices.len(), 162);
        let p = &m.vertices.positions;
        assert!(p.iter().all(|v| (v.length() - 2.0).abs() < 1e-5));
        let mut volume = 0.0;
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| p[i as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0, "inward triangle");
            volume += a.dot(b.cross(c)) / 6.0;
        }
        let sphere = 4.0 / 3.0 * std::f32::consts::PI * 8.0;
        assert!(volume < sphere && volume > 0.95 * sphere, "{volume}");
    }
}
