//! `filmsplat compare`: one scene, two geometries, side by side, with metrics.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::Args;

use super::compare_report::{FrameResult, Side, report};
use super::render_args::RenderArgs;
use super::render_scene::scene_from_args;
use crate::figure::side_by_side;
use crate::image::{RgbImage, ToneMap, metrics::delta_e_map, save_png};
use crate::pipeline::compare::{
    GeometryChoice, MeshOptions, ShellOption, Variant, display_image, metrics, prepare_pair,
};
use crate::pipeline::sequence;
use crate::pointcloud::Transfer;
use crate::render::View;
use crate::{Error, Result};

/// Arguments of `filmsplat compare`: the two geometries, then the scene flags of `render`
/// (its help rewritten where compare differs; the flags compare cannot honour are hidden and
/// refused).
#[derive(Debug, Clone, Args)]
#[command(
    mut_arg("output", |a| a.help(
        "Output figure, PNG only (the two renders and the ΔE heat map side by side). Default: \
         compare.png; with --frames a pattern such as 'cmp/{:04}.png'"
    )),
    mut_arg("frames", |a| a.help(
        "Compare a sequence: frame numbers A..B (B excluded) or A..=B. The input, -o, and a \
         mesh:FILE geometry contain a frame pattern, {} or {:04}, e.g. `compare disk \
         'mesh:surf/{:04}.obj' 'frames/{:04}.ply' -o 'cmp/{:04}.png' --frames 0..48`; also \
         prints the temporal stability of both sides"
    )),
    mut_arg("shard", |a| a.help(
        "Compare only every N-th frame of --frames, starting at the K-th (K/N, 0 <= K < N)"
    )),
    mut_arg("camera", |a| a.help(
        "Camera position x,y,z (scene units); default: auto-framing of each frame"
    )),
    mut_arg("roulette", |a| a.help(
        "Russian roulette below this branch weight (0..1; 0 is off): dim branches of the ray \
         tree are followed at random, unbiased (the balanced and final presets use 0.1 for a \
         sphere geometry)"
    )),
    mut_arg("quiet", |a| a.help("No progress bar or report (--json still prints)")),
    mut_arg("exr", |a| a.hide(true)),
    mut_arg("primitive", |a| a.hide(true)),
    mut_arg("view", |a| a.hide(true)),
    mut_arg("view_range", |a| a.hide(true)),
    mut_arg("frame_all", |a| a.hide(true)),
    mut_arg("resume", |a| a.hide(true)),
    mut_arg("keep_going", |a| a.hide(true)),
    mut_arg("max_memory", |a| a.hide(true)),
)]
pub struct CompareArgs {
    /// First geometry: disk, sphere, mls, mesh:FILE (PLY with faces or OBJ) or reconstructed.
    a: String,
    /// Second geometry (same choices).
    b: String,
    #[command(flatten)]
    render: RenderArgs,
    /// Meshes that are thin closed shells (an iso-surface around one layer of particles
    /// crosses each film twice): auto (warn), all (no check), merge (one film per crossing,
    /// walls detected), merge:DIST (walls closer than DIST scene units merged).
    #[arg(long, default_value = "auto")]
    shell: String,
    /// How a mesh without thickness gets the cloud's: kernel (SPH interpolation over 16
    /// neighbours), kernel:K (over K), or nearest.
    #[arg(long, default_value = "kernel")]
    transfer: String,
    /// ΔE2000 at the top of the heat map's scale (larger differences saturate).
    #[arg(long, default_value_t = 10.0, value_parser = super::parse::finite_f32)]
    heat_max: f32,
    /// Print the metrics as JSON on stdout (notes and warnings go to stderr).
    #[arg(long)]
    json: bool,
}

fn transfer(s: &str) -> Result<Transfer> {
    match s {
        "nearest" => Ok(Transfer::Nearest),
        "kernel" => Ok(Transfer::default()),
        _ => match s.strip_prefix("kernel:").map(str::parse::<usize>) {
            Some(Ok(k)) if (1..=256).contains(&k) => Ok(Transfer::Kernel { k }),
            _ => Err(Error::invalid(format!(
                "--transfer: '{s}' is not nearest, kernel or kernel:K (K = 1..256)"
            ))),
        },
    }
}

/// Runs `filmsplat compare`.
pub fn run(a: &CompareArgs, out: &mut dyn Write, err: &mut dyn Write) -> Result<()> {
    let (mesh, output) = checked(a)?;
    let Some(frames) = &a.render.frames else {
        crate::atomic::prepare_output(&output)?;
        let r = compare_one(a, &mesh, None, &output, err)?;
        report(a.json, a.render.quiet, std::slice::from_ref(&r), None, out);
        return Ok(());
    };
    compare_frames(a, &mesh, &frames.0, &output, out, err)
}

/// The mesh options and the output of `a`, after refusing what compare does not take.
fn checked(a: &CompareArgs) -> Result<(MeshOptions, PathBuf)> {
    let mesh = MeshOptions {
        shell: a.shell.parse::<ShellOption>()?,
        transfer: transfer(&a.transfer)?,
    };
    if !(a.heat_max > 0.0 && a.heat_max.is_finite()) {
        return Err(Error::invalid(format!(
            "--heat-max must be > 0, got {}",
            a.heat_max
        )));
    }
    if a.render.exr.is_some() {
        return Err(Error::invalid(
            "compare writes one PNG; --exr is not supported",
        ));
    }
    let r = &a.render;
    if r.primitive.is_some() {
        return Err(Error::invalid(
            "compare takes its two geometries as arguments A and B; --primitive is render's",
        ));
    }
    for (given, flag) in [
        (r.frame_all, "--frame-all"),
        (r.resume, "--resume"),
        (r.keep_going, "--keep-going"),
        (r.max_memory.is_some(), "--max-memory"),
        (r.crf.is_some(), "--crf"),
    ] {
        if given {
            return Err(Error::invalid(format!(
                "{flag} is render's; compare does not support it"
            )));
        }
    }
    let output = a
        .render
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("compare.png"));
    if !output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(Error::invalid(format!(
            "{}: the comparison is written as PNG; give a .png output",
            output.display()
        )));
    }
    Ok((mesh, output))
}

/// Compares the frames of `--frames` (this shard's), each figure at `output`'s pattern; then
/// reports them with the flicker between consecutive frames.
fn compare_frames(
    a: &CompareArgs,
    mesh: &MeshOptions,
    frames: &[u64],
    output: &Path,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<()> {
    let out_pattern = output.to_string_lossy().into_owned();
    if sequence::expand(&out_pattern, 0)?.is_none() {
        return Err(Error::invalid(format!(
            "{out_pattern}: --frames needs a frame pattern ({{}} or {{:04}}) in -o"
        )));
    }
    let mine = sequence::sharded(frames, a.render.shard);
    // Fail before the work: every folder the figures go in exists and takes files.
    let mut ready = std::collections::BTreeSet::new();
    for &f in &mine {
        let target = PathBuf::from(sequence::expand(&out_pattern, f)?.expect("checked"));
        if ready.insert(target.parent().map(Path::to_path_buf)) {
            crate::atomic::prepare_output(&target)?;
        }
    }
    let mut results: Vec<FrameResult> = Vec::new();
    let mut flicker = [0.0f64; 2];
    for &f in &mine {
        let target = PathBuf::from(sequence::expand(&out_pattern, f)?.expect("checked"));
        let r = compare_one(a, mesh, Some(f), &target, err)
            .map_err(|e| Error::invalid(format!("frame {f}: {e}")))?;
        if let Some(prev) = results.last() {
            for (k, fl) in flicker.iter_mut().enumerate() {
                let d = delta_e_map(&prev.images[k], &r.images[k])?;
                *fl += d.iter().map(|&v| f64::from(v)).sum::<f64>() / d.len() as f64;
            }
        }
        // Only the last frame's pictures are needed for the next difference.
        if let Some(prev) = results.last_mut() {
            prev.images = [RgbImage::new(0, 0), RgbImage::new(0, 0)];
        }
        results.push(r);
    }
    let pairs = results.len().saturating_sub(1);
    let temporal = (pairs > 0).then(|| flicker.map(|s| s / pairs as f64));
    report(a.json, a.render.quiet, &results, temporal, out);
    Ok(())
}

/// Prepares, renders and compares one frame (`frame` = `None` outside a sequence); writes the
/// figure to `output`.
fn compare_one(
    a: &CompareArgs,
    mesh: &MeshOptions,
    frame: Option<u64>,
    output: &Path,
    err: &mut dyn Write,
) -> Result<FrameResult> {
    let mut ra = a.render.clone();
    ra.frames = None;
    let choice = |s: &str| -> Result<GeometryChoice> {
        match frame {
            Some(f) => sequence::expand(s, f).map(|e| e.unwrap_or_else(|| s.to_string())),
            None => Ok(s.to_string()),
        }?
        .parse()
    };
    let choices = [choice(&a.a)?, choice(&a.b)?];
    if let Some(f) = frame {
        ra.frame = Some(f);
        ra.seed = Some(a.render.seed.unwrap_or(0).wrapping_add(f));
    }
    let (desc, base) = scene_from_args(&ra)?;
    if let Some(v) = &desc.render.view
        && v.parse::<View>().ok() != Some(View::Shaded)
    {
        return Err(Error::invalid(format!(
            "compare renders the shaded view only (got view '{v}')"
        )));
    }
    let progress = !a.render.quiet && !a.json && std::io::stderr().is_terminal();
    let variants = prepare_pair(&desc, &base, [&choices[0], &choices[1]], mesh, progress)?;
    let mut notes: Vec<&crate::pipeline::Note> = Vec::new();
    for v in &variants {
        for n in &v.prepared.notes {
            if n.shown(a.render.quiet) && !notes.iter().any(|m| m.text == n.text) {
                notes.push(n);
            }
        }
    }
    for n in notes {
        let _ = writeln!(err, "{}", n.message());
    }
    let mut images = Vec::with_capacity(2);
    let mut sides = Vec::with_capacity(2);
    for v in &variants {
        let t = Instant::now();
        let rendered = crate::pipeline::render(&v.prepared, &v.prepared.shot)?;
        let render = t.elapsed();
        images.push(display_image(&v.prepared, &rendered)?);
        sides.push(side(v, render));
    }
    let [ia, ib]: [RgbImage; 2] = images.try_into().expect("two");
    let m = metrics(&ia, &ib)?;
    let [sa, sb]: [Side; 2] = sides.try_into().expect("two");
    let caption = |s: &Side| format!("{} · {:.2} s", s.label, s.render.as_secs_f64());
    let title = format!("ΔE00 mean {:.2}, p95 {:.2}", m.delta_e.mean, m.delta_e.p95);
    let fig = side_by_side(
        &ia,
        &ib,
        [&caption(&sa), &caption(&sb)],
        &m.delta_e_map,
        a.heat_max,
        &title,
    );
    save_png(output, &fig, 0.0, ToneMap::Clamp)?;
    Ok(FrameResult {
        frame,
        sides: [sa, sb],
        metrics: m,
        images: [ia, ib],
        output: output.to_path_buf(),
    })
}

fn side(v: &Variant, render: Duration) -> Side {
    let p = &v.prepared;
    Side {
        label: v.choice.to_string(),
        elements: p.particles,
        prepare: p.load_time + p.estimate_time + p.build_time,
        mesh: v.mesh_time,
        meshing: v.meshing_time,
        render,
    }
}
