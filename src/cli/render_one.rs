//! One image of `filmsplat render`: checks before loading (outputs, memory), prepare, render,
//! write, report.

use super::glob;
use super::render_args::RenderArgs;
use super::render_scene::scene_from_args;
use crate::image::Srgb8Image;
use crate::pipeline;
use crate::pipeline::pinholes::PinholeFigure;
use crate::pipeline::{Prepared, Progress, Shot, memory};
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

/// The image a render writes: -o, else the scene file's output.path, else render.png.
pub(super) fn output_path(a: &RenderArgs, desc: &SceneDesc, base: &Path) -> PathBuf {
    match (&a.output, &desc.output.path) {
        (Some(o), _) => match a.inputs.first() {
            Some(i) => glob::with_stem(o, i),
            None => o.clone(),
        },
        (None, Some(p)) => base.join(p),
        (None, None) => PathBuf::from("render.png"),
    }
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

/// Checks everything that can be checked before loading: the scene and flags (resolved),
/// output names, the estimated peak memory against --max-memory or the machine's available
/// memory, the output folders (created); then prepares the scene, reporting its stages as
/// `progress` says.
pub(super) fn prepare_frame(a: &RenderArgs, progress: Progress) -> Result<Prepared> {
    let (desc, base) = scene_from_args(a)?;
    // The whole configuration first (against the allowance `render::run` set from
    // --max-memory): the memory estimate below reads the inputs' headers.
    desc.resolve(&base)?;
    let output = output_path(a, &desc, &base);
    // A movie's frame writes no file of its own (`--exr` is refused with a movie).
    let outputs: Vec<&PathBuf> = if a.in_memory {
        Vec::new()
    } else {
        std::iter::once(&output).chain(a.exr.as_ref()).collect()
    };
    for p in &outputs {
        pipeline::check_extension(p)?;
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
    pipeline::prepare_staged(&desc, &base, progress, None)
}

/// How a render reports its stages: nothing with -q, a spinner and bar in a terminal, a line
/// per stage in a log.
pub(super) fn progress_of(a: &RenderArgs) -> Progress {
    if a.quiet {
        Progress::Off
    } else if std::io::stderr().is_terminal() {
        Progress::Bar
    } else {
        Progress::Lines
    }
}

/// Where a rendered frame goes.
#[derive(Debug, Clone, Copy)]
pub(super) enum Target<'a> {
    /// Its image file (and `--exr`, if given).
    File(&'a Path),
    /// Its 8-bit sRGB pixels, returned (for a movie); no file is written.
    Pixels,
}

impl Target<'_> {
    /// What the summary line says was written.
    fn label(&self) -> String {
        match self {
            Target::File(p) => p.display().to_string(),
            Target::Pixels => "the frame to the movie".into(),
        }
    }
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
    if a.frame.is_none() && (desc.camera.orbit.is_some() || !desc.camera.key.is_empty()) {
        let _ = writeln!(
            out,
            "note: camera.orbit and [[camera.key]] move the camera over a sequence (render \
             --frames); this single image is rendered from [camera] alone"
        );
    }
    let prepared = ready_or_prepare(a, &desc, ready)?;
    let shot = prepared.shot.clone();
    render_prepared(
        a,
        &prepared,
        shot,
        Target::File(&output),
        Fresh::Prepared,
        out,
    )
    .map(|_| ())
}

/// `ready`, or the frame prepared now.
pub(super) fn ready_or_prepare(
    a: &RenderArgs,
    desc: &SceneDesc,
    ready: Option<Prepared>,
) -> Result<Prepared> {
    match ready {
        Some(p) => Ok(p),
        None => prepare_frame(a, progress_of(a)).map_err(|e| desc.locate(e)),
    }
}

/// Whether the scene a render draws was prepared for it, or prepared once before and
/// re-aimed (a turntable's later frames).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Fresh {
    /// Prepared for this image: its notes and stage times are reported.
    Prepared,
    /// Prepared for an earlier frame and re-aimed: neither is repeated.
    Reaimed,
}

/// Renders `shot` of `prepared` (with this render's progress setting) to `target` (its file and
/// --exr: returns `None`; or its pixels: `Some`) and reports it.
pub(super) fn render_prepared(
    a: &RenderArgs,
    prepared: &Prepared,
    mut shot: Shot,
    target: Target<'_>,
    fresh: Fresh,
    out: &mut dyn Write,
) -> Result<Option<Srgb8Image>> {
    let shown = |n: &&pipeline::Note| fresh == Fresh::Prepared && n.shown(a.quiet);
    for note in prepared.notes.iter().filter(shown) {
        let _ = writeln!(out, "{}", note.message());
    }
    shot.settings.progress = progress_of(a) == Progress::Bar;
    if let Some(view) = pipeline::render_view(prepared, &shot)? {
        let pixels = match target {
            Target::File(output) => {
                pipeline::write_view(&view, output)?;
                if let Some(exr) = &a.exr {
                    pipeline::write_view(&view, exr)?;
                }
                None
            }
            Target::Pixels => Some(pipeline::view_srgb8(&view)?),
        };
        if !a.quiet {
            let (n, v, to) = (prepared.particles, &shot.view, target.label());
            let _ = writeln!(out, "{n} particles: {v} view; wrote {to}");
        }
        return Ok(pixels);
    }
    let t = Instant::now();
    let result = pipeline::render(prepared, &shot)?;
    let render_time = t.elapsed();
    let pixels = match target {
        Target::File(output) => {
            pipeline::write_image(&shot, &result, output)?;
            if let Some(exr) = &a.exr {
                pipeline::write_image(&shot, &result, exr)?;
            }
            None
        }
        Target::Pixels => Some(pipeline::image_srgb8(&shot, &result)?),
    };
    // The pinhole figure, once, for the warning after a skipped fit and the summary.
    let figure = (prepared.fit_screened || !a.quiet)
        .then(|| pipeline::pinholes::front_layer_of(prepared, &shot, &result));
    if let Some(warning) = figure.and_then(|f| screened_pinholes(prepared, f)) {
        let _ = writeln!(out, "{warning}");
    }
    if let (false, Some(figure)) = (a.quiet, figure) {
        let line = summary(
            prepared,
            (&shot, &result, figure),
            render_time,
            fresh,
            &target.label(),
        );
        let _ = writeln!(out, "{line}");
    }
    Ok(pixels)
}

/// Pinholes above [`SCREENED_PINHOLES`] % where the particles hold film.
const SCREENED_PINHOLES: f64 = 0.02;

/// A warning (shown with `-q` too) when the radius fit was skipped on a sample's word and the
/// render then finds pinholes where the particles hold film: the sample missed what the fit
/// would have closed.
fn screened_pinholes(prepared: &Prepared, figure: PinholeFigure) -> Option<String> {
    if !prepared.fit_screened {
        return None;
    }
    let d = figure.in_data.ok()?;
    (d.percent() > SCREENED_PINHOLES).then(|| {
        format!(
            "warning: pinholes at {:.3} % of the film's interior where the particles hold film, with the radius fit skipped because a sample of the particles needed none: --fit-radii always fits every particle",
            d.percent()
        )
    })
}

/// The summary's pinhole figure: the renderer's pinholes (the front layer missing where the
/// particles hold film), with the share that counts the data's own gaps beside it; without the
/// particles, the missing share of the interior and why.
fn pinhole_figure(f: PinholeFigure) -> String {
    match f.in_data {
        Ok(d) => format!(
            "pinholes at {:.3} % of the film's interior (front layer missing where the particles hold film; {:.3} % counting the gaps in the data)",
            d.percent(),
            f.interior.percent()
        ),
        Err(why) => format!(
            "front layer missing at {:.3} % of the film's interior (gaps in the data counted too: {})",
            f.interior.percent(),
            match why {
                pipeline::pinholes::NoDataFigure::NotKept => format!(
                    "the particles were not kept: more than {}",
                    pipeline::film_data::FILM_DATA_CAP
                ),
                pipeline::pinholes::NoDataFigure::Moving =>
                    "the films move during the shutter".to_string(),
            }
        ),
    }
}

/// The summary line of a shaded render: counts, stage times, speed, the pinhole figure.
fn summary(
    prepared: &Prepared,
    (shot, result, figure): (&Shot, &crate::render::RenderOutput, PinholeFigure),
    render_time: std::time::Duration,
    fresh: Fresh,
    wrote: &str,
) -> String {
    let s = &shot.settings;
    let front = pinhole_figure(figure);
    let stages = match fresh {
        Fresh::Prepared => format!(
            "load {:.3} s, estimate {:.3} s, build {:.3} s",
            prepared.load_time.as_secs_f64(),
            prepared.estimate_time.as_secs_f64(),
            prepared.build_time.as_secs_f64()
        ),
        Fresh::Reaimed => "prepared once, camera re-aimed".to_string(),
    };
    format!(
        "{} particles ({}){}: {stages}; render {}x{} at {} spp: {:.3} s ({:.2} Mrays/s); {front}; wrote {}",
        prepared.particles,
        prepared.scene.geometry,
        droplet_note(prepared.droplets),
        s.width,
        s.height,
        s.spp,
        render_time.as_secs_f64(),
        result.rays as f64 / render_time.as_secs_f64() / 1e6,
        wrote
    )
}
