//! `filmsplat render`'s scene: the scene file (or a default scene around the particle
//! files) with the flags on top.

use super::render_args::RenderArgs;
use crate::scene::{FitRadiiKey, SceneDesc};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The scene description: from the TOML file, or a default one around the particle files;
/// then the flags on top (a flag wins over its scene-file key, and is checked with it by
/// [`SceneDesc::resolve`]). Returns it with the folder its paths are relative to.
pub(super) fn scene_from_args(a: &RenderArgs) -> Result<(SceneDesc, PathBuf)> {
    let (mut d, base) = read_scene(a)?;
    if let Some(p) = &a.preset {
        // A preset given here replaces the scene file's knobs it fills.
        d.set_preset(p);
    }
    film_flags(&mut d, a);
    render_flags(&mut d, a);
    view_flags(&mut d, a);
    if let Some(f) = a.frame {
        let fps = a.fps.map_or(super::sample::FPS, |v| v as f32);
        crate::pipeline::sequence::at_frame(&mut d, f, fps)?;
    }
    if let Some(env) = &a.env {
        environment_flag(&mut d, env)?;
    }
    d.environment.turn_deg = a.turn_deg;
    Ok((d, base))
}

/// The scene file's description and folder, or a default description around the inputs.
fn read_scene(a: &RenderArgs) -> Result<(SceneDesc, PathBuf)> {
    let Some(file) = a.scene_file()? else {
        let mut d = SceneDesc::default();
        d.input.cloud = a.inputs.first().cloned();
        if a.inputs.len() > 1 {
            d.input.clouds = Some(a.inputs[1..].to_vec());
        }
        return Ok((d, PathBuf::new()));
    };
    // Scene files are small: at most 16 MiB, never a device.
    let bytes = crate::io::input::read_small(file, 16 << 20)?;
    let text = String::from_utf8(bytes).map_err(|_| Error::Format {
        path: file.clone(),
        format: "scene TOML",
        message: "not UTF-8 text".into(),
    })?;
    let d = SceneDesc::from_toml(&text, &file.display().to_string())?;
    Ok((d, file.parent().map(Path::to_path_buf).unwrap_or_default()))
}

/// `field` = the flag's value, if the flag is given.
fn over<T: Clone>(field: &mut Option<T>, flag: &Option<T>) {
    if let Some(v) = flag {
        *field = Some(v.clone());
    }
}

/// The flags of `[input]` and `[film]`.
fn film_flags(d: &mut SceneDesc, a: &RenderArgs) {
    let (i, f) = (&mut d.input, &mut d.film);
    over(&mut f.primitive, &a.primitive);
    over(&mut f.ior, &a.ior);
    over(&mut f.thickness_unit, &a.thickness_unit);
    over(&mut f.thickness_scale, &a.thickness_scale);
    over(&mut i.thickness_attr, &a.thickness_attr);
    over(&mut i.normal_attr, &a.normal_attr);
    over(&mut i.radius_attr, &a.radius_attr);
    over(&mut i.melp_set, &a.melp_set);
    over(&mut f.default_thickness_nm, &a.default_thickness);
    over(&mut f.radius_scale, &a.radius_scale);
    let off = |flag: bool| flag.then_some(false);
    over(&mut i.repair, &a.repair.then_some(true));
    over(&mut i.liquid, &a.liquid);
    over(&mut i.liquid_field, &a.liquid_field);
    let fit = a.fit_radii.clone().map(FitRadiiKey::Name);
    over(
        &mut f.fit_radii,
        &off(a.raw_radii).map(FitRadiiKey::Flag).or(fit),
    );
    over(&mut f.curvature, &off(a.flat_splats));
    over(&mut f.blend, &off(a.no_blend));
}

/// The flags of `[render]` (sampling), `[environment]`'s numbers and `[camera]`.
fn render_flags(d: &mut SceneDesc, a: &RenderArgs) {
    let r = &mut d.render;
    over(&mut r.spp, &a.spp);
    over(&mut r.seed, &a.seed);
    over(&mut r.shading, &a.shading);
    over(&mut r.wavelengths, &a.wavelengths);
    over(&mut r.strategy, &a.strategy);
    over(&mut r.max_depth, &a.max_depth);
    over(&mut r.roulette, &a.roulette);
    over(&mut r.light_samples, &a.light_samples);
    over(&mut r.shutter, &a.shutter);
    over(&mut r.frame_time, &a.frame_time);
    over(&mut r.shutter_slices, &a.shutter_slices);
    if let Some((w, h)) = a.size {
        (r.width, r.height) = (Some(w), Some(h));
    }
    over(&mut d.environment.rotation, &a.env_rotation);
    over(&mut d.environment.intensity, &a.env_intensity);
    let c = &mut d.camera;
    over(&mut c.position, &a.camera);
    over(&mut c.look_at, &a.look_at);
    over(&mut c.fov, &a.fov);
    over(&mut c.aperture, &a.aperture);
    over(&mut c.focus_distance, &a.focus_distance);
    over(&mut c.orbit, &a.orbit);
}

/// The flags of `[output]` and the view.
fn view_flags(d: &mut SceneDesc, a: &RenderArgs) {
    let o = &mut d.output;
    over(&mut o.exposure, &a.exposure);
    over(&mut o.white_balance, &a.white_balance);
    over(&mut o.contrast, &a.contrast);
    over(&mut o.saturation, &a.saturation);
    over(&mut o.tonemap, &a.tonemap);
    over(&mut d.render.view, &a.view);
    over(&mut d.render.view_range, &a.view_range);
}

/// `--env`: studio, white (uniform white), or a map's path (relative to the working
/// directory).
fn environment_flag(d: &mut SceneDesc, env: &str) -> Result<()> {
    let e = &mut d.environment;
    match env {
        "studio" => e.kind = Some("studio".into()),
        "white" => {
            e.kind = Some("uniform".into());
            e.colour = Some([1.0; 3]);
        }
        path => {
            e.kind = Some("map".into());
            e.map = Some(std::path::absolute(path).map_err(|x| Error::io(path, x))?);
        }
    }
    Ok(())
}
