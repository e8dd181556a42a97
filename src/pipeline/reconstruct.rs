//! In-process surface reconstruction (cargo feature `reconstruct`): the cloud is meshed with
//! splashsurf_lib (Löschner et al., the SPH iso-surface reconstruction of splashsurf: SPH
//! density on a sparse grid, marching cubes), as a meshed pipeline would mesh it.
//!
//! Parameters follow splashsurf's usual relative settings, from the cloud's own spacing `d`
//! (median nearest-neighbour distance): particle radius `d/2`, compact support 4 radii, cubes
//! of 0.75 radii. The iso-surface threshold is 0.6 of the rest density for volumes; a single
//! layer of film particles has far less density than a filled volume, so when the median
//! distance to the 12th neighbour says the particles form a sheet (> 1.6 d) the threshold drops
//! to 0.25 (else the surface would vanish or break up). Around a sheet the result is a thin closed shell (see
//! [`crate::geometry::mesh`]).

use glam::Vec3;
use splashsurf_lib::nalgebra::Vector3;
use splashsurf_lib::{Parameters, reconstruct_surface};

use crate::pointcloud::knn::KnnTable;
use crate::pointcloud::{PointCloud, TriangleMesh};
use crate::{Error, Result};

/// Meshes `cloud` (positions only; thickness is transferred afterwards). Returns the mesh and
/// a note on the parameters used.
pub fn reconstruct(cloud: &PointCloud) -> Result<(TriangleMesh, String)> {
    let n = cloud.positions.len();
    if n < 4 {
        return Err(Error::invalid(format!(
            "reconstruction needs at least 4 particles, got {n}"
        )));
    }
    let table = KnnTable::build(&cloud.positions, 12);
    let mut nearest: Vec<f32> = (0..n).filter_map(|i| table.kth_distance(i, 1)).collect();
    if nearest.is_empty() {
        return Err(Error::invalid("reconstruction: no two particles are apart"));
    }
    let mid = nearest.len() / 2;
    let d = *nearest.select_nth_unstable_by(mid, f32::total_cmp).1;
    // Sheet or volume, by the median distance to the 12th neighbour relative to the spacing:
    // on a plane it is √3 d (hexagonal packing) to 2 d (square grid), in a volume d
    // (close packing) to √2 d (cubic grid) — ≈ 1.4 d for the usual SPH fluid.
    let mut twelfth: Vec<f32> = (0..n).filter_map(|i| table.kth_distance(i, 12)).collect();
    let m12 = twelfth.len() / 2;
    let sheet = *twelfth.select_nth_unstable_by(m12, f32::total_cmp).1 > 1.6 * d;
    if !(d > 0.0 && d.is_finite()) {
        return Err(Error::invalid("reconstruction: particles have no spacing"));
    }
    let r = 0.5 * d;
    let mut params = Parameters::new(r, 4.0 * r, 0.75 * r);
    if sheet {
        params.iso_surface_threshold = 0.25;
    }
    let positions: Vec<Vector3<f32>> = cloud
        .positions
        .iter()
        .map(|p| Vector3::new(p.x, p.y, p.z))
        .collect();
    let surface = reconstruct_surface::<i64, f32>(&positions, &params)
        .map_err(|e| Error::invalid(format!("reconstruction failed: {e}")))?;
    let mesh = &surface.mesh;
    if mesh.triangles.is_empty() {
        return Err(Error::invalid("reconstruction produced an empty surface"));
    }
    let vertices = mesh
        .vertices
        .iter()
        .map(|v| Vec3::new(v.x, v.y, v.z))
        .collect();
    let triangles = mesh.triangles.iter().map(|t| t.map(|i| i as u32)).collect();
    let note = format!(
        "reconstruction (splashsurf_lib): spacing {d:.4}, particle radius {r:.4}, support \
         {:.4}, cubes {:.4}, iso-threshold {} ({})",
        4.0 * r,
        0.75 * r,
        params.iso_surface_threshold,
        if sheet {
            "a one-layer sheet"
        } else {
            "a volume"
        }
    );
    let mesh = TriangleMesh {
        vertices: PointCloud {
            positions: vertices,
            ..PointCloud::default()
        },
        triangles,
    };
    Ok((mesh, note))
}
