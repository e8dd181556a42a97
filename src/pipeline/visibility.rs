//! How much of a render's film shows its colours ([`crate::image::visibility`]), measured on a
//! prepared scene and its render.

use super::Prepared;
use crate::image::visibility::{ColourVisibility, colour_visibility};
use crate::render::RenderOutput;

/// The share of `out`'s (a render of `p`'s default shot, [`Prepared::shot`]) film pixels (covered, with a film thickness) whose colour is visible
/// (see [`crate::image::visibility`]). The backdrop of each pixel is the environment along the
/// camera ray through its centre (props and area lights are not counted: the measure is of
/// the environment's lighting). The display is the exposure and tone curve of the PNG.
/// Cost: one environment lookup per pixel.
pub fn colour_visibility_of(p: &Prepared, out: &RenderOutput) -> ColourVisibility {
    let (w, h) = (out.width, out.height);
    let aspect = w as f32 / h.max(1) as f32;
    let shot = &p.shot;
    let camera = &shot.camera;
    let environment = p.environment_of(shot);
    let backdrop: Vec<[f32; 3]> = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let ray = camera.ray(
                (x as f32 + 0.5) / w as f32,
                (y as f32 + 0.5) / h as f32,
                aspect,
            );
            environment.radiance(ray.dir).to_array()
        })
        .collect();
    let gain = shot.exposure.exp2();
    let pixel: Vec<[f32; 3]> = out.rgb.iter().map(|c| c.to_array()).collect();
    let display: Vec<[f32; 3]> = pixel
        .iter()
        .map(|c| c.map(|v| shot.tonemap.apply(v * gain)))
        .collect();
    // Film pixels only: a droplet (water, no interference) may cover a pixel but holds no
    // film thickness.
    let coverage: Vec<f32> = out
        .alpha
        .iter()
        .zip(&out.thickness)
        .map(|(&a, &t)| if t > 0.0 { a } else { 0.0 })
        .collect();
    colour_visibility(&pixel, &backdrop, &coverage, &display)
}
