//! The pinhole metric on the film the data holds: [`crate::image::pinholes`] finds the interior
//! pixels whose first film layer is missing; of these, only those whose ray crosses the film
//! the particles themselves span ([`FilmSpan`]) before the hit it found are pinholes. The rest
//! are holes, torn rims or open edges of the data, drawn as such.

use crate::Result;
use crate::image::pinholes::{FrontLayer, missing_pixels};
use crate::io::PartKind;
use crate::pointcloud::area::own_radii;
use crate::pointcloud::eigen::sym_eigen3;
use crate::pointcloud::estimate::estimate_normals;
use crate::pointcloud::span::FilmSpan;
use crate::render::RenderOutput;
use crate::scene::SceneDesc;
use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;
use std::path::Path;

use super::{Prepared, Shot};

/// The render summary's pinhole figure: the front layer's missing share of the film's
/// interior, and, where the particles are at hand, the share missing where they hold film.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PinholeFigure {
    /// Every interior pixel whose first film layer is missing (the data's own gaps too).
    pub interior: FrontLayer,
    /// Of those, the renderer's pinholes: where the particles hold film in front of what the
    /// ray found ([`front_layer_in_data`]), or why there is no such figure.
    pub in_data: std::result::Result<FrontLayer, NoDataFigure>,
}

/// Why a [`PinholeFigure`] has no figure where the data holds film.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoDataFigure {
    /// More film particles than [`super::film_data::FILM_DATA_CAP`]: they were not kept.
    NotKept,
    /// The films move during the shutter.
    Moving,
}

/// The interior pixels of `shot`'s render `out` (droplets' pixels left out) and the missing
/// ones among them (row-major indices).
fn interior_and_missing(shot: &Shot, out: &RenderOutput) -> (usize, Vec<usize>) {
    let (w, h) = (shot.settings.width, shot.settings.height);
    let droplets: Vec<bool> = out.droplets.iter().map(|c| *c > 0.0).collect();
    missing_pixels(&out.depth, w, h, &droplets)
}

/// The pinhole figures of a render `out` of `p` as `shot`: interior pixels (droplets' pixels
/// left out), the missing ones, and of these the ones where the data holds film (when `p`
/// kept its particles, [`Prepared::film_data`], and its films stand still). Cost: the metric,
/// plus, when a pixel is missing, one k-d tree build over the particles and one
/// [`FilmSpan::crosses`] per missing pixel.
pub fn front_layer_of(p: &Prepared, shot: &Shot, out: &RenderOutput) -> PinholeFigure {
    let (interior, missing) = interior_and_missing(shot, out);
    let all = FrontLayer {
        interior,
        missing: missing.len(),
    };
    let in_data = match &p.film_data {
        _ if !p.motion.is_empty() => Err(NoDataFigure::Moving),
        None => Err(NoDataFigure::NotKept),
        Some(_) if missing.is_empty() => Ok(all),
        Some(d) => {
            let span = FilmSpan::new(&d.positions, &d.normals).with_own_radii(d.own.clone());
            Ok(FrontLayer {
                interior,
                missing: crossing(shot, out, &span, &missing),
            })
        }
    };
    PinholeFigure {
        interior: all,
        in_data,
    }
}

/// The pinhole counts of a render `out` of `p`'s default shot ([`Prepared::shot`]) whose film particles `span` describes:
/// interior pixels (droplets' pixels left out, as the render's own summary does), and the
/// missing ones where the data holds film in front of whatever the ray found (the front layer
/// at least a spacing before the hit). Cost: the metric plus one [`FilmSpan::crosses`] per
/// missing pixel.
pub fn front_layer_in_data(p: &Prepared, out: &RenderOutput, span: &FilmSpan) -> FrontLayer {
    let (interior, missing) = interior_and_missing(&p.shot, out);
    FrontLayer {
        interior,
        missing: crossing(&p.shot, out, span, &missing),
    }
}

/// How many of the `missing` pixels (row-major indices of `shot`'s picture) have a ray that
/// crosses the film `span` holds at least a spacing before the depth `out` found (or anywhere,
/// where it found nothing).
fn crossing(shot: &Shot, out: &RenderOutput, span: &FilmSpan, missing: &[usize]) -> usize {
    let (w, h) = (shot.settings.width, shot.settings.height);
    let aspect = w as f32 / h as f32;
    let camera = &shot.camera;
    missing
        .par_iter()
        .filter(|&&k| {
            let ray = camera.ray(
                ((k % w) as f32 + 0.5) / w as f32,
                ((k / w) as f32 + 0.5) / h as f32,
                aspect,
            );
            let t_max = match out.depth[k] {
                d if d > 0.0 => d - span.spacing(),
                _ => f32::INFINITY,
            };
            span.crosses(ray.origin, ray.dir, t_max)
        })
        .count()
}

/// The film particles of the scene's input as read (droplets and liquid left out): positions,
/// unit normals (estimated from 12 neighbours where the file has none) and own radii √(A/π)
/// (0 where no area is stored), for [`FilmSpan`].
///
/// # Errors
/// As [`super::load_parts`].
pub fn film_particles(desc: &SceneDesc, base: &Path) -> Result<(Vec<Vec3>, Vec<Vec3>, Vec<f32>)> {
    let (mut positions, mut normals, mut own) = (Vec::new(), Vec::new(), Vec::new());
    for part in super::load_parts(desc, base)? {
        if part.kind != PartKind::Film {
            continue;
        }
        let c = part.cloud;
        let n = match &c.normals {
            Some(n) => n.iter().map(|v| v.normalize_or_zero()).collect(),
            None => estimate_normals(&c.positions, 12),
        };
        let mut o = own_radii(&c);
        o.resize(c.len(), 0.0);
        own.extend(o);
        normals.extend(n);
        positions.extend_from_slice(&c.positions);
    }
    Ok((positions, normals, own))
}

/// A `camera.from` direction that sees the film edge-on: 5° above the plane of the cloud's two
/// longest axes (principal components), on the side of the default camera.
pub fn edge_on(positions: &[Vec3]) -> [f32; 3] {
    let n = positions.len().max(1) as f64;
    let c = positions.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / n;
    let mut m = DMat3::ZERO;
    for p in positions {
        let d = p.as_dvec3() - c;
        m += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let axis = sym_eigen3(&(m / n)).vectors[0]
        .as_vec3()
        .normalize_or(Vec3::Y);
    let from = Vec3::from(super::framing::DEFAULT_FROM).normalize();
    let flat = (from - from.dot(axis) * axis).normalize_or(axis.any_orthonormal_vector());
    let up = if from.dot(axis) < 0.0 { -axis } else { axis };
    let a = 5f32.to_radians();
    (a.cos() * flat + a.sin() * up).to_array()
}
