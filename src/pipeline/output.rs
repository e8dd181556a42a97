//! Output: the rendered buffers as image files (PNG tone-mapped, EXR linear with its layers),
//! and the scientific views with their colour bars.

use super::prepared::Prepared;
use super::shot::Shot;
use crate::image::{
    ExrLayers, Grade, RgbImage, Srgb8Image, ToneMap, to_srgb8, write_exr, write_png,
};
use crate::render::{RenderOutput, View, ViewImage};
use crate::{Error, Result};
use glam::Vec3;
use std::path::Path;

/// Width / height of the part of a `width`×`height` image that `view` fills with the scene:
/// all of it, or what its colour bar leaves.
pub fn scene_aspect(view: &View, width: usize, height: usize) -> f32 {
    scene_width(view, width, height) as f32 / height as f32
}

/// Columns of a `width`×`height` image that `view` fills with the scene (the rest is its
/// colour bar).
pub(super) fn scene_width(view: &View, width: usize, height: usize) -> usize {
    if view.has_legend() {
        width - crate::figure::colour_bar_width(width, height)
    } else {
        width
    }
}

/// Writes `out` to `path`: PNG (exposure + tone curve + sRGB) or EXR (linear RGBA plus depth,
/// normal, thickness and hit-count layers), by extension, with `shot`'s grading, exposure and
/// tone curve. Written atomically.
pub fn write_image(shot: &Shot, out: &RenderOutput, path: &Path) -> Result<()> {
    write_output(out, &shot.grade, shot.exposure, shot.tonemap, path)
}

/// [`write_image`] with the grading, exposure (EV) and tone curve given directly.
pub fn write_output(
    out: &RenderOutput,
    grade: &Grade,
    exposure: f32,
    tonemap: ToneMap,
    path: &Path,
) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => {
            let px = output_srgb8(out, grade, exposure, tonemap)?;
            write_png(path, px.width, px.height, &px.data)
        }
        Some("exr") => {
            let rgba = out
                .rgb
                .iter()
                .zip(&out.alpha)
                .map(|(c, a)| [c.x, c.y, c.z, *a])
                .collect();
            let mut layers = ExrLayers::rgba(out.width, out.height, rgba);
            layers.depth = Some(out.depth.clone());
            layers.normal = Some(out.normal.iter().map(|n| n.to_array()).collect());
            layers.thickness = Some(out.thickness.clone());
            layers.hit_count = Some(out.hits.clone());
            layers.droplets = Some(out.droplets.clone());
            write_exr(path, &layers)
        }
        _ => Err(Error::invalid(format!(
            "{}: output must end in .png or .exr",
            path.display()
        ))),
    }
}

/// The 8-bit sRGB pixels of `out` that its PNG holds (graded, exposed, tone mapped): what
/// [`write_image`] writes to a .png, and what a movie is fed.
pub fn image_srgb8(shot: &Shot, out: &RenderOutput) -> Result<Srgb8Image> {
    output_srgb8(out, &shot.grade, shot.exposure, shot.tonemap)
}

/// [`image_srgb8`] with the grading, exposure (EV) and tone curve given directly.
fn output_srgb8(
    out: &RenderOutput,
    grade: &Grade,
    exposure: f32,
    tonemap: ToneMap,
) -> Result<Srgb8Image> {
    let data = out.rgb.iter().map(|c| c.to_array()).collect();
    let img = RgbImage::from_data(out.width, out.height, data)?;
    Ok(Srgb8Image {
        width: out.width,
        height: out.height,
        data: to_srgb8(&grade.apply(&img), exposure, tonemap),
    })
}

/// The 8-bit sRGB pixels of a view (colour bar included) that its PNG holds (clamp tone
/// curve, 0 EV): what [`write_view`] writes to a .png, and what a movie is fed.
pub fn view_srgb8(v: &ViewImage) -> Result<Srgb8Image> {
    let data: Vec<[f32; 3]> = v.rgb.iter().map(|c| c.to_array()).collect();
    let img = RgbImage::from_data(v.width, v.height, data)?;
    Ok(Srgb8Image {
        width: v.width,
        height: v.height,
        data: to_srgb8(&img, 0.0, ToneMap::Clamp),
    })
}

/// Renders `shot`'s scientific view (see [`View`]) of a prepared scene, reading `p` only;
/// `None` for the shaded view.
/// The picture is exactly the settings' width × height: a view with a colour bar renders the
/// scene in the columns the bar leaves (see [`crate::figure::colour_bar_width`]) and draws the
/// bar, its labels matching [`crate::render::Legend::colour`], in the rest.
pub fn render_view(p: &Prepared, shot: &Shot) -> Result<Option<ViewImage>> {
    if shot.view == View::Shaded {
        return Ok(None);
    }
    let (width, height) = (shot.settings.width, shot.settings.height);
    let scene_w = scene_width(&shot.view, width, height);
    let world = crate::render::WorldRef {
        camera: &shot.camera,
        ..(&p.scene).into()
    };
    let mut v = crate::render::render_view_of(
        world,
        shot.view.clone(),
        scene_w,
        height,
        p.attribute.as_ref(),
    )?;
    if let Some(l) = &v.legend {
        let data: Vec<[f32; 3]> = v.rgb.iter().map(|c| c.to_array()).collect();
        let img = RgbImage::from_data(v.width, v.height, data)?;
        let ramp = |t: f32| l.colour(l.min + t * (l.max - l.min)).to_array();
        let img =
            crate::figure::add_colour_bar(&img, width - scene_w, &l.title, l.min, l.max, &ramp);
        v.width = img.width;
        v.rgb = img.data.iter().map(|c| Vec3::from(*c)).collect();
    }
    Ok(Some(v))
}

/// Writes a view (from [`render_view`], colour bar included): PNG (clamp tone curve, 0 EV), or
/// EXR holding the same picture in linear RGB.
pub fn write_view(v: &ViewImage, path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => {
            let px = view_srgb8(v)?;
            write_png(path, px.width, px.height, &px.data)
        }
        Some("exr") => {
            let data: Vec<[f32; 3]> = v.rgb.iter().map(|c| c.to_array()).collect();
            let img = RgbImage::from_data(v.width, v.height, data)?;
            let rgba = img.data.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
            write_exr(path, &ExrLayers::rgba(v.width, v.height, rgba))
        }
        _ => Err(Error::invalid(format!(
            "{}: output must end in .png or .exr",
            path.display()
        ))),
    }
}

/// Refuses an output that is neither .png nor .exr.
///
/// # Errors
/// [`Error::Invalid`] naming the path.
pub fn check_extension(p: &Path) -> Result<()> {
    let ext = p
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if matches!(ext.as_deref(), Some("png" | "exr")) {
        Ok(())
    } else {
        Err(Error::invalid(format!(
            "{}: output must end in .png or .exr",
            p.display()
        )))
    }
}
