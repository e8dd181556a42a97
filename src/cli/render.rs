//! `filmsplat render`: render a particle cloud or a scene file.

pub use super::render_args::RenderArgs;
use super::{glob, sequence};
use crate::pipeline;
use crate::pipeline::{Prepared, memory};
use crate::scene::SceneDesc;
use crate::{Error, Result};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// " and N droplets" when there are any.
fn droplet_note(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(" and {n} droplets")
    }
}

/// The scene description: from the TOML file, or a default one around the particle files;
/// then the flags on top (a flag wins over its scene-file key, and is checked with it by
/// [`SceneDesc::resolve`]). Returns it with the folder its paths are relative to.
pub(super) fn scene_from_args(a: &RenderArgs) -> Result<(SceneDesc, PathBuf)> {
    let (mut d, base) = read_scene(a)?;
    if let Some(p) = &a.preset {
        // A preset given here replaces the scene file's knobs it fills.
        let r = &mut d.render;
        (r.spp, r.max_depth, r.min_weight, r.shading, r.wavelengths) =
            (None, None, None, None, None);
        r.roulette = None;
        r.preset = Some(p.clone());
    }
    film_flags(&mut d, a);
    render_flags(&mut d, a);
    view_flags(&mut d, a);
    if let Some(f) = a.frame {
        crate::pipeline::sequence::at_frame(&mut d, f, super::sample::FPS)?;
    }
    if let Some(env) = &a.env {
        environment_flag(&mut d, env)?;
    }
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
    over(&mut f.default_thickness_nm, &a.default_thickness);
    over(&mut f.radius_scale, &a.radius_scale);
    let off = |flag: bool| flag.then_some(false);
    over(&mut i.repair, &a.repair.then_some(true));
    over(&mut f.fit_radii, &off(a.raw_radii));
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

/// Runs `filmsplat render`: one image, or a sequence with --frames.
pub fn run(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    if let [only] = a.inputs.as_slice()
        && a.frames.is_none()
        && glob::is_glob(only)
        && !only.exists()
    {
        return run_glob(a, out);
    }
    let Some(frames) = &a.frames else {
        if a.frame_all {
            return Err(Error::invalid(
                "--frame-all frames a whole sequence; it needs --frames",
            ));
        }
        return render_one(a, out, None);
    };
    sequence::render_sequence(a, &frames.0, out)
}

/// The image a render writes: -o, else the scene file's output.path, else render.png.
fn output_path(a: &RenderArgs, desc: &SceneDesc, base: &Path) -> PathBuf {
    match (&a.output, &desc.output.path) {
        (Some(o), _) => match a.inputs.first() {
            Some(i) => glob::with_stem(o, i),
            None => o.clone(),
        },
        (None, Some(p)) => base.join(p),
        (None, None) => PathBuf::from("render.png"),
    }
}

/// Renders every match of a quoted glob input (`'frames/*.ply'`), sorted by name, as a sequence:
/// `{stem}` in -o (and --exr) names each output after its input; the n-th match's seed is the
/// seed plus n.
fn run_glob(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    let pattern = a.inputs.first().cloned().unwrap_or_default();
    let inputs = glob::expand(&pattern)?;
    let output = a.output.as_ref().ok_or_else(|| {
        Error::invalid(format!(
            "{}: a glob input needs -o with {{stem}}, e.g. -o 'out/{{stem}}.png'",
            pattern.display()
        ))
    })?;
    for p in std::iter::once(output).chain(a.exr.as_ref()) {
        if inputs.len() > 1 && !p.to_string_lossy().contains("{stem}") {
            return Err(Error::invalid(format!(
                "{}: {} files match {}; the output needs {{stem}} (e.g. 'out/{{stem}}.png') so \
                 they do not overwrite each other",
                p.display(),
                inputs.len(),
                pattern.display()
            )));
        }
    }
    let mut failed = Vec::new();
    for (n, input) in inputs.iter().enumerate() {
        let mut one = a.clone();
        one.inputs = vec![input.clone()];
        one.output = Some(glob::with_stem(output, input));
        one.exr = a.exr.as_ref().map(|e| glob::with_stem(e, input));
        one.seed = Some(a.seed.unwrap_or(0).wrapping_add(n as u64));
        let target = one.output.clone().expect("set");
        if a.resume
            && std::iter::once(&target)
                .chain(one.exr.as_ref())
                .all(|p| p.exists())
        {
            if !a.quiet {
                let _ = writeln!(
                    out,
                    "{}: {} exists, skipped",
                    input.display(),
                    target.display()
                );
            }
            continue;
        }
        if !a.quiet {
            let _ = writeln!(out, "{} ({}/{}):", input.display(), n + 1, inputs.len());
        }
        match render_one(&one, out, None) {
            Ok(()) => {}
            Err(e) if a.keep_going => {
                eprintln!("filmsplat: error: {e}");
                failed.push(input.display().to_string());
            }
            Err(e) => return Err(e),
        }
    }
    if !failed.is_empty() {
        return Err(Error::invalid(format!(
            "{} of {} inputs failed: {}",
            failed.len(),
            inputs.len(),
            failed.join(", ")
        )));
    }
    Ok(())
}

/// Renders `a` (whose output is `-`) to a spool file, then copies the finished PNG to standard
/// output, so standard output receives the whole image or nothing; messages go to stderr.
fn render_to_stdout(a: &RenderArgs) -> Result<()> {
    static SPOOLS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = SPOOLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let spool =
        std::env::temp_dir().join(format!("filmsplat-{}-{n}-stdout.png", std::process::id()));
    let mut one = a.clone();
    one.output = Some(spool.clone());
    let mut said = Vec::new();
    let result = render_one(&one, &mut said, None);
    let said =
        String::from_utf8_lossy(&said).replace(&spool.display().to_string(), "standard output");
    eprint!("{said}");
    let result = result.and_then(|()| {
        let bytes = std::fs::read(&spool).map_err(|e| Error::io(&spool, e))?;
        let mut stdout = std::io::stdout().lock();
        stdout
            .write_all(&bytes)
            .and_then(|()| stdout.flush())
            .map_err(|e| Error::io("-", e))
    });
    let _ = std::fs::remove_file(&spool);
    result
}

/// Checks everything that can be checked before loading: output names, the estimated peak
/// memory against --max-memory or the machine's available memory, the output folders
/// (created); then prepares the scene. `progress` shows the render's progress bar.
pub(super) fn prepare_frame(a: &RenderArgs, progress: bool) -> Result<Prepared> {
    let (desc, base) = scene_from_args(a)?;
    let output = output_path(a, &desc, &base);
    let outputs: Vec<&PathBuf> = std::iter::once(&output).chain(a.exr.as_ref()).collect();
    for p in &outputs {
        pipeline::check_extension(p)?;
    }
    if let Some(bytes) = a.max_memory {
        crate::budget::set_allowance(bytes);
    }
    if let Some(limit) = memory::Limit::new(a.max_memory) {
        let exr = outputs
            .iter()
            .any(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")));
        match memory::estimate_scene(&desc, &base, exr) {
            Ok(estimate) => limit
                .check(&estimate)
                .map_err(|m| Error::invalid(format!("{}: {m}", a.first_input())))?,
            // Without a limit of the user's, an input the estimate cannot read is left to the
            // reader, which names the problem better.
            Err(_) if matches!(limit, memory::Limit::Available(_)) => {}
            Err(e) => return Err(e),
        }
    }
    for p in &outputs {
        crate::atomic::prepare_output(p)?;
    }
    pipeline::prepare(&desc, &base, progress)
}

/// Renders one image; `ready` is its scene if the caller already prepared it.
pub(super) fn render_one(
    a: &RenderArgs,
    out: &mut dyn Write,
    ready: Option<Prepared>,
) -> Result<()> {
    let (desc, base) = scene_from_args(a)?;
    let output = output_path(a, &desc, &base);
    if output.as_os_str() == "-" {
        return render_to_stdout(a);
    }
    let progress = !a.quiet && std::io::stderr().is_terminal();
    let prepared = match ready {
        Some(mut p) => {
            p.settings.progress = progress;
            p
        }
        None => prepare_frame(a, progress).map_err(|e| desc.locate(e))?,
    };
    if !a.quiet {
        for note in prepared
            .notes
            .iter()
            .filter(|n| !n.text.is_empty() && !n.routine)
        {
            let _ = writeln!(out, "{note}");
        }
    }
    if let Some(view) = pipeline::render_view(&prepared)? {
        pipeline::write_view(&view, &output)?;
        if let Some(exr) = &a.exr {
            pipeline::write_view(&view, exr)?;
        }
        if !a.quiet {
            let _ = writeln!(
                out,
                "{} particles: {} view; wrote {}",
                prepared.particles,
                prepared.view,
                output.display()
            );
        }
        return Ok(());
    }
    let t = Instant::now();
    let result = pipeline::render(&prepared)?;
    let render_time = t.elapsed();
    pipeline::write_image(&prepared, &result, &output)?;
    if let Some(exr) = &a.exr {
        pipeline::write_image(&prepared, &result, exr)?;
    }
    if !a.quiet {
        let s = &prepared.settings;
        let front = crate::image::pinholes::missing_front_layer(&result.depth, s.width, s.height);
        let _ = writeln!(
            out,
            "{} particles ({}){}: load {:.3} s, estimate {:.3} s, build {:.3} s; render {}x{} at {} spp: {:.3} s ({:.2} Mrays/s); front layer missing at {:.3} % of the film's interior; wrote {}",
            prepared.particles,
            prepared.scene.geometry,
            droplet_note(prepared.droplets),
            prepared.load_time.as_secs_f64(),
            prepared.estimate_time.as_secs_f64(),
            prepared.build_time.as_secs_f64(),
            s.width,
            s.height,
            s.spp,
            render_time.as_secs_f64(),
            result.rays as f64 / render_time.as_secs_f64() / 1e6,
            front.percent(),
            output.display()
        );
    }
    Ok(())
}
