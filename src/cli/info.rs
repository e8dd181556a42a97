//! `filmsplat info`: what a particle file holds and what the renderer would make of it.

use crate::Result;
use crate::io::{peek_count, read_cloud};
use crate::pipeline::memory::{MemoryEstimate, human_bytes};
use crate::pointcloud::estimate::estimate_radii;
use crate::pointcloud::{EstimateOptions, compute_stats};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `filmsplat info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The particle file.
    input: PathBuf,
    #[command(flatten)]
    attributes: super::attributes::AttributeArgs,
    /// Image size WIDTHxHEIGHT the peak-memory estimate is for (default 960x540, as render).
    #[arg(long, value_parser = super::parse::size)]
    size: Option<(usize, usize)>,
}

/// Runs `filmsplat info`.
pub fn run(a: &InfoArgs, out: &mut dyn Write) -> Result<()> {
    let opts = a.attributes.read_options()?;
    let hint = peek_count(&a.input)?;
    let cloud = read_cloud(&a.input, &opts)?;
    let stats = compute_stats(&cloud);
    let io = |e: std::io::Error| crate::Error::invalid(format!("info: writing output: {e}"));
    writeln!(out, "{}", a.input.display()).map_err(io)?;
    writeln!(out, "{stats}").map_err(io)?;
    // What the renderer would estimate.
    let defaults = EstimateOptions::default();
    writeln!(out, "renderer would:").map_err(io)?;
    if cloud.normals.is_none() {
        writeln!(
            out,
            "  estimate normals by PCA over {} nearest neighbours",
            defaults.k_normals
        )
        .map_err(io)?;
    }
    if cloud.radius.is_none() && !cloud.is_empty() {
        let mut r = estimate_radii(&cloud.positions, defaults.k_radius, defaults.radius_scale);
        let mid = r.len() / 2;
        let median = *r.select_nth_unstable_by(mid, f32::total_cmp).1;
        writeln!(
            out,
            "  estimate splat radii from spacing: median {median:.6} (scene units)"
        )
        .map_err(io)?;
    }
    if cloud.thickness_nm.is_none() {
        writeln!(
            out,
            "  use a constant thickness of {} nm (set --default-thickness)",
            defaults.default_thickness_nm
        )
        .map_err(io)?;
    }
    if cloud.normals.is_some() && cloud.radius.is_some() && cloud.thickness_nm.is_some() {
        writeln!(
            out,
            "  use the file's normals, radii and thickness as they are"
        )
        .map_err(io)?;
    }
    let (w, h) = a.size.unwrap_or((960, 540));
    let file = if hint.reads_whole_file {
        hint.file_bytes
    } else {
        0
    };
    let estimate = MemoryEstimate::new(cloud.len() as u64, w, h, false, file);
    let exr = MemoryEstimate::new(cloud.len() as u64, w, h, true, file);
    writeln!(
        out,
        "estimated peak memory of a {w}x{h} render: {estimate}; {} with an EXR output",
        human_bytes(exr.total())
    )
    .map_err(io)?;
    Ok(())
}
