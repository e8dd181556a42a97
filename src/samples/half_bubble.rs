//! A half bubble on a surface: the hemisphere of radius 1 above the plane y = 0 (y up), as a
//! bubble blown onto a wet table. The film drains toward its foot, so it is thinnest at the
//! apex (with black-film patches) and thickest where it meets the surface. The shape is
//! static; the thickness field evolves with time.

use super::surface::{SampleParams, revolution, to_cloud};
use super::thickness::{Chart, ThicknessField};
use crate::pointcloud::PointCloud;
use glam::DVec2;
use std::f64::consts::FRAC_PI_2;

/// The hemisphere (radius 1, base circle on y = 0, outward normals, y up). The thickness
/// field runs from the apex (top) to the foot (bottom). Deterministic for a seed.
pub fn half_bubble(p: &SampleParams) -> PointCloud {
    let profile = |u: f64| {
        let (s, c) = (u * FRAC_PI_2).sin_cos();
        DVec2::new(s, c)
    };
    let chart = |u: f64, lon: f64| {
        let (s, c) = (u * FRAC_PI_2).sin_cos();
        glam::DVec3::new(s * lon.cos(), s * lon.sin(), c)
    };
    let surfels = revolution(p.particles, p.seed, profile, chart);
    let field = ThicknessField::new(
        p.seed,
        Chart {
            bottom: 0.0,
            angle: FRAC_PI_2,
            vortices: 3, // a bubble's density of vortices on half its area
            ..Chart::sphere()
        },
    );
    to_cloud(&surfels, &field, p.time, |_, h| h)
}
