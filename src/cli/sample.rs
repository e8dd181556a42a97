//! `filmsplat sample`: write a built-in thin-film particle cloud, or a sequence of them.

use super::parse::{self as frame_parse, FrameList};
use crate::io::{write_mesh_ply, write_ply};
use crate::pipeline::check_sample_params;
use crate::pipeline::sequence;
use crate::pipeline::stages::{Progress, stage_line};
use crate::samples::{SampleKind, SampleParams, icosphere, sparse};
use crate::{Error, Result};
use clap::Args;
use std::io::{IsTerminal, Write};
use std::path::PathBuf;

/// Frames a second of a generated sequence (as `render --frames` animates samples).
pub const FPS: f32 = 24.0;

/// What `sample NAME` writes: a generated cloud, or the bubble's analytic surface as a mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    Cloud(SampleKind),
    BubbleMesh,
}

fn sample_target(s: &str) -> std::result::Result<Target, String> {
    if s == "bubble-mesh" {
        return Ok(Target::BubbleMesh);
    }
    SampleKind::from_name(s)
        .map(Target::Cloud)
        .map_err(|e| format!("{e}, bubble-mesh"))
}

/// Arguments of `filmsplat sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// Which sample: bubble, irregular-bubble, catenoid, half-bubble, square-film,
    /// circle-film, drip, oscillating-bubble; or bubble-mesh, the bubble's analytic surface as a
    /// triangle mesh (subdivided icosahedron about the origin, radius --radius, outward normals,
    /// no thickness) to compare against with `compare ... mesh:FILE`.
    #[arg(value_parser = sample_target)]
    name: Target,
    /// Output PLY (binary little-endian, with x y z nx ny nz rh radius; rh in nm); with
    /// --frames a pattern such as 'out/{:04}.ply'.
    #[arg(short, long)]
    output: PathBuf,
    /// Number of particles.
    #[arg(long, default_value_t = 200_000, value_parser = super::parse::int_in::<usize>(1, 50_000_000))]
    particles: usize,
    /// Seed of the particle jitter and the thickness field.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Time of the animation, seconds (with --frames: of frame 0).
    #[arg(long, default_value_t = 0.0, value_parser = super::parse::finite_f32)]
    time: f32,
    /// Write a sequence: frame f at time --time + f/24 s (A..B, A..=B or A).
    #[arg(long, value_parser = frame_parse::frame_list)]
    frames: Option<FrameList>,
    /// Radius of bubble-mesh, scene units (the bubble sample's is 1).
    #[arg(long, default_value_t = 1.0, value_parser = super::parse::finite_f32)]
    radius: f32,
    /// Subdivisions of the icosahedron for bubble-mesh (20·4^N triangles, 0..=9).
    #[arg(long, default_value_t = 5, value_parser = super::parse::int_in::<u32>(0, 9))]
    subdivisions: u32,
    /// Keep only a random fraction F in (0, 1] of the particles (splats widened by 1/√F), to
    /// test sparse data.
    #[arg(long, value_parser = super::parse::finite_f64)]
    sparse: Option<f64>,
}

/// Runs `filmsplat sample`.
pub fn run(a: &SampleArgs, out: &mut dyn Write) -> Result<()> {
    let kind = match a.name {
        Target::Cloud(k) => k,
        Target::BubbleMesh => return write_bubble_mesh(a, out),
    };
    let base = SampleParams {
        particles: a.particles,
        seed: a.seed,
        time: a.time,
    };
    check_sample_params(&base, a.sparse, "sample: --")?;
    let pattern = a.output.to_string_lossy().to_string();
    let jobs: Vec<(PathBuf, f32)> = match &a.frames {
        None => vec![(a.output.clone(), a.time)],
        Some(frames) => {
            if sequence::expand(&pattern, 0)?.is_none() {
                return Err(Error::invalid(format!(
                    "{pattern}: --frames needs a frame pattern ({{}} or {{:04}}) in -o"
                )));
            }
            frames
                .0
                .iter()
                .map(|&f| {
                    let path = sequence::expand(&pattern, f)?.expect("checked");
                    Ok((PathBuf::from(path), a.time + f as f32 / FPS))
                })
                .collect::<Result<_>>()?
        }
    };
    // Fail before the work: every folder the frames go in exists and takes files.
    let mut ready = std::collections::BTreeSet::new();
    for (path, _) in &jobs {
        if ready.insert(path.parent()) {
            crate::atomic::prepare_output(path)?;
        }
    }
    // A spinner while a frame is generated and written, in a terminal; the line per frame
    // below is the log's.
    let progress = Progress::bar_if(std::io::stderr().is_terminal());
    for (path, time) in jobs {
        let p = SampleParams {
            time,
            ..base.clone()
        };
        let stage = progress.start(&format!("generating {} (t = {time} s)", kind.name()));
        let mut cloud = kind.generate(&p);
        if let Some(f) = a.sparse.filter(|f| *f < 1.0) {
            cloud = sparse(&cloud, f, a.seed);
        }
        write_ply(&path, &cloud)?;
        let took = stage.finish_silently();
        let _ = writeln!(
            out,
            "{}",
            stage_line(
                &format!(
                    "wrote {} particles ({}, t = {time} s) to {}",
                    cloud.len(),
                    kind.name(),
                    path.display()
                ),
                took
            )
        );
    }
    Ok(())
}

/// `sample bubble-mesh`: the bubble's sphere as a triangle mesh.
fn write_bubble_mesh(a: &SampleArgs, out: &mut dyn Write) -> Result<()> {
    if a.subdivisions > 9 {
        return Err(Error::invalid(format!(
            "sample: --subdivisions must be 0..=9, got {}",
            a.subdivisions
        )));
    }
    if !(a.radius > 0.0 && a.radius.is_finite()) {
        return Err(Error::invalid(format!(
            "sample: --radius must be > 0, got {}",
            a.radius
        )));
    }
    crate::atomic::prepare_output(&a.output)?;
    let mesh = icosphere(a.radius, a.subdivisions);
    write_mesh_ply(&a.output, &mesh)?;
    let _ = writeln!(
        out,
        "wrote {} triangles to {}",
        mesh.len(),
        a.output.display()
    );
    Ok(())
}
