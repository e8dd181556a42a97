//! The film particles a prepared scene keeps for the render summary's data-aware pinhole
//! figure (`super::pinholes::front_layer_of`), up to a cap.

use crate::pointcloud::PointCloud;
use crate::pointcloud::area::own_radii;
use glam::Vec3;

/// Most film particles a [`super::Prepared`] keeps for the render summary's data-aware pinhole
/// figure ([`FilmData`]: 28 bytes a particle, 56 MB at the cap); above it the summary prints
/// the interior figure and says why.
pub const FILM_DATA_CAP: usize = 2_000_000;

/// The film particles as loaded (after checks and repairs, before any geometry), kept so a
/// render's summary can tell the renderer's pinholes from gaps the particles themselves have
/// ([`super::pinholes::front_layer_of`]).
#[derive(Debug, Clone, Default)]
pub struct FilmData {
    /// Positions, scene units.
    pub positions: Vec<Vec3>,
    /// Unit normals (as loaded or estimated), one a particle.
    pub normals: Vec<Vec3>,
    /// Own radii √(A/π) where the simulator stores an area A (scene units; 0 unknown; empty
    /// when none is stored).
    pub own: Vec<f32>,
}

impl FilmData {
    /// The film particles of `cloud`; `None` above [`FILM_DATA_CAP`] particles or without
    /// normals.
    pub fn of(cloud: &PointCloud) -> Option<FilmData> {
        if cloud.len() > FILM_DATA_CAP {
            return None;
        }
        let normals = cloud.normals.as_ref()?;
        Some(FilmData {
            positions: cloud.positions.clone(),
            normals: normals.iter().map(|n| n.normalize_or_zero()).collect(),
            own: own_radii(cloud),
        })
    }
}
