//! [`TriangleMesh`]: a triangle mesh whose vertices carry the same attributes as particles, and
//! [`transfer_thickness`], which gives a mesh without thickness the film thickness of a cloud.

use glam::Vec3;
use rayon::prelude::*;

use super::PointCloud;
use super::knn::PointIndex;

/// A triangle mesh (e.g. a meshed render's surface). `vertices` holds positions and the optional
/// per-vertex normals and thickness (nm) exactly as a [`PointCloud`] holds them for particles;
/// `triangles` index into it (counter-clockwise seen from the side the normals face).
#[derive(Debug, Clone, Default)]
pub struct TriangleMesh {
    /// Vertex positions (scene units) and attributes.
    pub vertices: PointCloud,
    /// Vertex indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// True if the mesh has no triangle.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The first triangle that names a vertex beyond the vertex list, as
    /// `(triangle, vertex index)`.
    pub fn first_bad_index(&self) -> Option<(usize, u32)> {
        let n = self.vertices.len();
        self.triangles
            .iter()
            .enumerate()
            .find_map(|(i, t)| t.iter().find(|&&v| v as usize >= n).map(|&v| (i, v)))
    }
}

/// How [`transfer_thickness`] carries a cloud's thickness to mesh vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transfer {
    /// The thickness of the nearest particle.
    Nearest,
    /// SPH interpolation: the Shepard-normalised mean over the `k` nearest particles weighted by
    /// the Wendland C2 kernel with support 1.5 × the distance to the `k`-th of them, so the
    /// support adapts to the local spacing. A constant field is reproduced exactly, a linear
    /// one to first order where the neighbours surround the vertex.
    Kernel {
        /// Neighbours per vertex (at least 1).
        k: usize,
    },
}

impl Default for Transfer {
    /// Kernel interpolation over 16 neighbours.
    fn default() -> Self {
        Transfer::Kernel { k: 16 }
    }
}

/// Wendland C2 kernel shape, `(1 − q)⁴ (1 + 4q)` for `q = r/support < 1`, unnormalised (the
/// Shepard sum divides the normalisation out).
fn wendland(q: f32) -> f32 {
    if q >= 1.0 {
        0.0
    } else {
        let a = 1.0 - q;
        a * a * a * a * (1.0 + 4.0 * q)
    }
}

/// The thickness (nm) at each of `points` from the particles of `positions` carrying
/// `thickness_nm`, by `how`. Points with no finite particle get `fallback_nm`. Cost: one k-d
/// tree build over the particles plus one k-NN query per point, parallel.
pub fn transfer_thickness(
    positions: &[Vec3],
    thickness_nm: &[f32],
    points: &[Vec3],
    how: Transfer,
    fallback_nm: f32,
) -> Vec<f32> {
    let index = PointIndex::build(positions);
    let k = match how {
        Transfer::Nearest => 1,
        Transfer::Kernel { k } => k.max(1),
    };
    points
        .par_iter()
        .with_min_len(256)
        .map(|&p| {
            let nb = index.nearest_excluding(p, k, u32::MAX);
            let Some(&(first, _)) = nb.first() else {
                return fallback_nm;
            };
            let support = 1.5 * nb.last().map_or(0.0, |&(_, d)| d);
            if k == 1 || support <= 0.0 {
                return thickness_nm[first as usize];
            }
            let (mut sw, mut st) = (0.0f64, 0.0f64);
            for &(j, d) in &nb {
                let w = f64::from(wendland(d / support));
                sw += w;
                st += w * f64::from(thickness_nm[j as usize]);
            }
            if sw > 0.0 {
                (st / sw) as f32
            } else {
                thickness_nm[first as usize]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Vec<Vec3> {
        let mut p = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                p.push(Vec3::new(i as f32 * 0.1, j as f32 * 0.1, 0.0));
            }
        }
        p
    }

    #[test]
    fn nearest_takes_the_nearest_particle() {
        let pos = grid();
        let t: Vec<f32> = (0..pos.len()).map(|i| i as f32).collect();
        let q = [Vec3::new(0.51, 0.29, 0.02), Vec3::new(0.0, 0.0, 0.0)];
        let out = transfer_thickness(&pos, &t, &q, Transfer::Nearest, -1.0);
        assert_eq!(out, vec![(5 * 20 + 3) as f32, 0.0]);
    }

    #[test]
    fn kernel_reproduces_constant_and_linear_fields_inside() {
        let pos = grid();
        let c = vec![420.0f32; pos.len()];
        let lin: Vec<f32> = pos
            .iter()
            .map(|p| 300.0 + 100.0 * p.x + 50.0 * p.y)
            .collect();
        let q: Vec<Vec3> = (0..10)
            .map(|i| Vec3::new(0.6 + 0.07 * i as f32, 0.9 - 0.03 * i as f32, 0.01))
            .collect();
        let how = Transfer::Kernel { k: 16 };
        for v in transfer_thickness(&pos, &c, &q, how, 0.0) {
            assert!((v - 420.0).abs() < 1e-3, "{v}");
        }
        for (p, v) in q.iter().zip(transfer_thickness(&pos, &lin, &q, how, 0.0)) {
            let want = 300.0 + 100.0 * p.x + 50.0 * p.y;
            // First-order exact only for symmetric neighbourhoods: a few nm on a 0.1 grid.
            assert!((v - want).abs() < 3.0, "{p}: {v} vs {want}");
        }
    }

    #[test]
    fn empty_cloud_gives_the_fallback_and_bad_indices_are_found() {
        let out = transfer_thickness(&[], &[], &[Vec3::ZERO], Transfer::default(), 77.0);
        assert_eq!(out, vec![77.0]);
        let mut m = TriangleMesh {
            vertices: PointCloud {
                positions: vec![Vec3::ZERO; 3],
                ..PointCloud::default()
            },
            triangles: vec![[0, 1, 2]],
        };
        assert_eq!(m.first_bad_index(), None);
        m.triangles.push([0, 3, 1]);
        assert_eq!(m.first_bad_index(), Some((1, 3)));
    }
}
