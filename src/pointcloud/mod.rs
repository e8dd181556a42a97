//! The particle cloud: what every reader produces and every geometry consumes, plus its
//! validation ([`mod@validate`]), estimation of missing attributes ([`estimate`]) and summary
//! statistics ([`stats`]), and triangle meshes whose vertices carry the same attributes
//! ([`mesh`]).

use glam::Vec3;

pub mod curvature;
pub mod dedupe;
pub mod eigen;
pub mod estimate;
pub mod knn;
pub mod mesh;
pub mod orient;
pub mod stats;
pub mod validate;

pub use estimate::{EstimateOptions, EstimateReport, fill_missing, fill_missing_keeping_table};
pub use mesh::{Transfer, TriangleMesh, transfer_thickness};
pub use stats::{CloudStats, compute_stats};
pub use validate::{RepairReport, repair, validate};

/// A thin-film particle cloud. All per-particle arrays have `positions.len()` entries.
#[derive(Debug, Clone, Default)]
pub struct PointCloud {
    /// Particle centres, in scene units.
    pub positions: Vec<Vec3>,
    /// Surface normals (not necessarily unit length in raw input), if the file has them.
    pub normals: Option<Vec<Vec3>>,
    /// Film thickness in nanometres (already converted from the file's unit), if present.
    pub thickness_nm: Option<Vec<f32>>,
    /// Splat radius in scene units, if present.
    pub radius: Option<Vec<f32>>,
    /// Every other scalar attribute the file holds, by name (for `info` and attribute mapping).
    pub extra: Vec<(String, Vec<f32>)>,
}

impl PointCloud {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True if the cloud has no particles.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The extra attribute called `name`, if present.
    pub fn extra(&self, name: &str) -> Option<&[f32]> {
        self.extra
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_slice())
    }
}
