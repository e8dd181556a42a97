//! The particle cloud: what every reader produces and every geometry consumes, plus its
//! validation ([`mod@validate`]), estimation of missing attributes ([`estimate`]) and summary
//! statistics ([`stats`]), and triangle meshes whose vertices carry the same attributes
//! ([`mesh`]).

use glam::Vec3;

pub mod adrift;
pub mod area;
pub mod cell;
pub mod clip;
pub mod curvature;
pub mod cut;
pub mod dedupe;
pub mod droplet_size;
pub mod eigen;
pub mod estimate;
mod fan;
pub mod gaps;
pub mod knn;
pub mod liquid;
mod looks;
pub mod mesh;
pub mod orient;
pub mod screen;
pub mod span;
pub mod stats;
pub mod validate;
pub mod walls;

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

impl PointCloud {
    /// The clouds one after the other. Normals, thickness and radius are kept where every cloud
    /// has them (else `None`, to be estimated); an extra attribute is kept where every cloud has
    /// one of that name. Cost: one copy of every array.
    pub fn concat(clouds: &[PointCloud]) -> PointCloud {
        fn all<T: Clone>(
            clouds: &[PointCloud],
            f: impl Fn(&PointCloud) -> Option<&Vec<T>>,
        ) -> Option<Vec<T>> {
            let mut out = Vec::new();
            for c in clouds {
                out.extend_from_slice(f(c)?);
            }
            Some(out)
        }
        let Some(first) = clouds.first() else {
            return PointCloud::default();
        };
        let extra = first
            .extra
            .iter()
            .filter_map(|(name, _)| {
                all(clouds, |c| {
                    c.extra.iter().find(|(k, _)| k == name).map(|(_, v)| v)
                })
                .map(|v| (name.clone(), v))
            })
            .collect();
        PointCloud {
            positions: all(clouds, |c| Some(&c.positions)).unwrap_or_default(),
            normals: all(clouds, |c| c.normals.as_ref()),
            thickness_nm: all(clouds, |c| c.thickness_nm.as_ref()),
            radius: all(clouds, |c| c.radius.as_ref()),
            extra,
        }
    }
}
