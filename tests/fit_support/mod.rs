//! What the radius-fit tests share: real frames' film clouds, the samples, and a film cloud
//! prepared for the fit as `render` prepares it.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use filmsplat::io::PartKind;
use filmsplat::pipeline::load_parts;
use filmsplat::pointcloud::dedupe::drop_coincident;
use filmsplat::pointcloud::gaps::{FAN_NEIGHBOURS, bound_by_area, own_radii};
use filmsplat::pointcloud::knn::{KnnTable, PointIndex};
use filmsplat::pointcloud::{EstimateOptions, PointCloud, fill_missing};
use filmsplat::samples::{SampleKind, SampleParams};
use filmsplat::scene::SceneDesc;

/// A path under tests/data.
pub fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// The film parts of `input` (under tests/data), as read.
pub fn films(input: &str) -> Vec<PointCloud> {
    let mut desc = SceneDesc::default();
    desc.input.cloud = Some(data(input));
    let parts = load_parts(&desc, Path::new("")).unwrap();
    parts
        .into_iter()
        .filter(|p| p.kind == PartKind::Film)
        .map(|p| p.cloud)
        .collect()
}

/// The built-in sample `name` with `particles` particles.
pub fn sample(name: &str, particles: usize) -> PointCloud {
    let p = SampleParams {
        particles,
        ..SampleParams::default()
    };
    SampleKind::from_name(name).unwrap().generate(&p)
}

/// A film cloud made ready for the fit: coincident copies dropped, what is missing
/// estimated, radii bounded by the particles' own areas, the neighbour index and the fit's
/// 12-neighbour table.
pub struct ForFit {
    pub cloud: PointCloud,
    pub radii: Vec<f32>,
    pub own: Vec<f32>,
    pub normals: Vec<glam::Vec3>,
    pub index: PointIndex,
    pub table: KnnTable,
}

/// `cloud` prepared for the fit as `render` prepares it.
pub fn for_fit(mut cloud: PointCloud) -> ForFit {
    drop_coincident(&mut cloud);
    fill_missing(&mut cloud, &EstimateOptions::default());
    let own = own_radii(&cloud);
    let mut radii = cloud.radius.clone().expect("radii estimated");
    bound_by_area(&mut radii, &own);
    let normals = cloud.normals.clone().expect("normals estimated");
    let index = PointIndex::build(&cloud.positions);
    let table = KnnTable::build_with(&index, &cloud.positions, FAN_NEIGHBOURS);
    ForFit {
        cloud,
        radii,
        own,
        normals,
        index,
        table,
    }
}
