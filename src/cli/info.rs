//! `filmsplat info`: what a particle file holds and what the renderer would make of it.

use crate::Result;
use crate::io::read_cloud;
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
}

/// Runs `filmsplat info`.
pub fn run(a: &InfoArgs, out: &mut dyn Write) -> Result<()> {
    let opts = a.attributes.read_options()?;
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
    Ok(())
}
