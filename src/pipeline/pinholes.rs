//! The pinhole metric on the film the data holds: [`crate::image::pinholes`] finds the interior
//! pixels whose first film layer is missing; of these, only those whose ray crosses the film
//! the particles themselves span ([`FilmSpan`]) before the hit it found are pinholes. The rest
//! are holes, torn rims or open edges of the data, drawn as such.

use crate::image::pinholes::{FrontLayer, missing_pixels};
use crate::pointcloud::span::FilmSpan;
use crate::render::RenderOutput;
use rayon::prelude::*;

use super::Prepared;

/// The pinhole counts of a render `out` of `p` whose film particles `span` describes:
/// interior pixels (droplets' pixels left out, as the render's own summary does), and the
/// missing ones where the data holds film in front of whatever the ray found (the front layer
/// at least a spacing before the hit). Cost: the metric plus one [`FilmSpan::crosses`] per
/// missing pixel.
pub fn front_layer_in_data(p: &Prepared, out: &RenderOutput, span: &FilmSpan) -> FrontLayer {
    let (w, h) = (p.settings.width, p.settings.height);
    let droplets: Vec<bool> = out.droplets.iter().map(|c| *c > 0.0).collect();
    let (interior, missing) = missing_pixels(&out.depth, w, h, &droplets);
    let aspect = w as f32 / h as f32;
    let camera = &p.scene.camera;
    let missing = missing
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
        .count();
    FrontLayer { interior, missing }
}
