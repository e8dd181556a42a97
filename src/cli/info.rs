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
    /// Unit of the file's thickness values: nm, um, mm or m (default: the format's unit, m for
    /// frame folders, nm otherwise).
    #[arg(long)]
    thickness_unit: Option<String>,
    /// Name of the thickness attribute.
    #[arg(long)]
    thickness_attr: Option<String>,
    /// Prefix of the normal attributes (n for nx ny nz, normal for normal_x ...).
    #[arg(long)]
    normal_attr: Option<String>,
    /// Name of the radius attribute.
    #[arg(long)]
    radius_attr: Option<String>,
}

/// Runs `filmsplat info`.
pub fn run(a: &InfoArgs, out: &mut dyn Write) -> Result<()> {
    let opts = super::convert::read_options(
        a.thickness_unit.as_deref(),
        a.thickness_attr.as_ref(),
        a.normal_attr.as_ref(),
        a.radius_attr.as_ref(),
    )?;
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
