//! One particle set of an input, and what it is. Inputs that hold several sets: a thin-film
//! SPH frame folder holds the film and, once it has ruptured, the droplets it shed; a MELP
//! foam frame holds one film per bubble; a `.pvd` collection names several files.
//! [`super::read_parts`] reads any input into its parts.

use super::{ReadOptions, StoredAttribute};
use crate::pointcloud::PointCloud;

/// What the particles of a part are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartKind {
    /// A thin film sampled by the particles (rendered with the thin-film optics).
    Film,
    /// Bulk fluid droplets (3D fluid particles the film turned into when it ruptured),
    /// rendered as clear water spheres. The readers give them as stored, with no radius unless
    /// the file names one; [`crate::pipeline::read_input_parts`] sizes them from the run's
    /// stored masses and volumes ([`crate::pointcloud::droplet_size`]).
    Droplets,
}

impl std::fmt::Display for PartKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            PartKind::Film => "film",
            PartKind::Droplets => "droplets",
        })
    }
}

/// One particle set of an input.
#[derive(Debug, Clone)]
pub struct CloudPart {
    /// Where it came from, for messages: the file or folder, and which of its sets
    /// (e.g. `frame 100/ (x_bin)` or `region 2`).
    pub label: String,
    /// Film or droplets.
    pub kind: PartKind,
    /// The particles (thickness in nm; droplets: radius in scene units).
    pub cloud: PointCloud,
    /// What the files stored and how each attribute or file is used (skipped ones included).
    pub stored: Vec<StoredAttribute>,
    /// How missing values were derived (e.g. the droplet radius), for the user.
    pub notes: Vec<String>,
}

impl CloudPart {
    /// A film part read from one file.
    pub fn film(label: String, cloud: PointCloud, stored: Vec<StoredAttribute>) -> Self {
        CloudPart {
            label,
            kind: PartKind::Film,
            cloud,
            stored,
            notes: Vec::new(),
        }
    }
}

/// The film parts of `parts` as one cloud (see [`PointCloud::concat`]), and their stored
/// attributes (the first part's, with the other parts' additions).
pub(crate) fn film_of(parts: Vec<CloudPart>) -> (PointCloud, Vec<StoredAttribute>) {
    let mut stored: Vec<StoredAttribute> = Vec::new();
    let mut clouds = Vec::new();
    for p in parts.into_iter().filter(|p| p.kind == PartKind::Film) {
        for s in p.stored {
            if !stored.iter().any(|t| t.name == s.name) {
                stored.push(s);
            }
        }
        clouds.push(p.cloud);
    }
    let cloud = if clouds.len() == 1 {
        clouds.pop().unwrap_or_default()
    } else {
        PointCloud::concat(&clouds)
    };
    (cloud, stored)
}

/// Gives `cloud` the radius of a disk of each particle's area, r = √(A/π), from its extra
/// attribute `area` (m², the simulators' `SA`), when it has no radius yet and `opts` names
/// none; marks the stored attribute as the radius. The simulators' own disk glyphs use this
/// radius (MELP's `OutputCircleDisksAsVTP`).
pub(crate) fn radius_from_area(
    cloud: &mut PointCloud,
    stored: &mut [StoredAttribute],
    area: &str,
    opts: &ReadOptions,
) {
    if cloud.radius.is_some() || opts.radius_attr.is_some() {
        return;
    }
    let Some(a) = cloud.extra(area) else {
        return;
    };
    cloud.radius = Some(
        a.iter()
            .map(|a| (a.max(0.0) / std::f32::consts::PI).sqrt())
            .collect(),
    );
    stored
        .iter_mut()
        .filter(|s| s.name == area)
        .for_each(|s| s.role = super::AttributeRole::Radius);
}
