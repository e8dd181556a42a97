//! `filmsplat info`: what a particle file holds and what the renderer would make of it.

use crate::Result;
use crate::io::{AttributeRole, CloudPart, PartKind, StoredAttribute, peek_count};
use crate::pipeline::memory::{MemoryEstimate, human_bytes};
use crate::pipeline::read_input_parts;
use crate::pointcloud::PointCloud;
use crate::pointcloud::estimate::estimate_radii;
use crate::pointcloud::gaps::{bound_by_area, own_radii};
use crate::pointcloud::knn::PointIndex;
use crate::pointcloud::screen::screen_fit;
use crate::pointcloud::{EstimateOptions, compute_stats};
use crate::render::{DEFAULT_HEIGHT, DEFAULT_WIDTH};
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

/// Runs `filmsplat info`: every particle set of the input (a simulator frame: its film and
/// droplets; a foam: each bubble), each with its stored attributes and what the renderer would
/// do with it.
pub fn run(a: &InfoArgs, out: &mut dyn Write) -> Result<()> {
    let opts = a.attributes.read_options()?;
    let hint = peek_count(&a.input)?;
    let parts = read_input_parts(&a.input, &opts)?;
    let io = |e: std::io::Error| crate::Error::invalid(format!("info: writing output: {e}"));
    writeln!(out, "{}", a.input.display()).map_err(io)?;
    // A single film needs no heading; droplets always say what they are.
    let many = parts.len() > 1 || parts.iter().any(|p| p.kind != PartKind::Film);
    for (k, part) in parts.iter().enumerate() {
        if many {
            writeln!(
                out,
                "\n== part {} of {} ({}): {}, {} particles",
                k + 1,
                parts.len(),
                part.kind,
                part.label,
                part.cloud.len()
            )
            .map_err(io)?;
        }
        describe(out, part).map_err(io)?;
    }
    let total: usize = parts.iter().map(|p| p.cloud.len()).sum();
    let (w, h) = a.size.unwrap_or((DEFAULT_WIDTH, DEFAULT_HEIGHT));
    let file = if hint.reads_whole_file {
        hint.file_bytes
    } else {
        0
    };
    let estimate = MemoryEstimate::new(total as u64, w, h, false, file);
    let exr = MemoryEstimate::new(total as u64, w, h, true, file);
    writeln!(
        out,
        "estimated peak memory of a {w}x{h} render: {estimate}; {} with an EXR output",
        human_bytes(exr.total())
    )
    .map_err(io)?;
    Ok(())
}

/// One part: its statistics, stored attributes and what the renderer would do with it.
fn describe(out: &mut dyn Write, part: &CloudPart) -> std::io::Result<()> {
    let cloud = &part.cloud;
    writeln!(out, "{}", compute_stats(cloud))?;
    write_stored(out, cloud, &part.stored)?;
    writeln!(out, "renderer would:")?;
    for note in &part.notes {
        writeln!(out, "  {note}")?;
    }
    if part.kind == PartKind::Droplets {
        return writeln!(
            out,
            "  draw them as clear water spheres (n = 1.33) of the radius above"
        );
    }
    if cloud.is_empty() {
        return writeln!(out, "  draw no film: this set has no particles (left)");
    }
    let defaults = EstimateOptions::default();
    if cloud.normals.is_none() {
        writeln!(
            out,
            "  estimate normals by PCA over {} nearest neighbours",
            defaults.k_normals
        )?;
    }
    if cloud.radius.is_none() {
        let mut r = estimate_radii(&cloud.positions, defaults.k_radius, defaults.radius_scale);
        let mid = r.len() / 2;
        let median = *r.select_nth_unstable_by(mid, f32::total_cmp).1;
        writeln!(
            out,
            "  estimate splat radii from spacing: median {median:.6} (scene units)"
        )?;
    }
    writeln!(out, "  {}", fit_choice(cloud))?;
    match cloud.thickness_nm.as_deref() {
        None => writeln!(
            out,
            "  use a constant thickness of {} nm (set --default-thickness)",
            defaults.default_thickness_nm
        )?,
        Some(t) => {
            if let Some(h) = crate::pipeline::thickness_unit_hint(t) {
                writeln!(out, "  warning: {h}")?;
            }
        }
    }
    if cloud.normals.is_some() && cloud.radius.is_some() && cloud.thickness_nm.is_some() {
        writeln!(out, "  use the file's normals, radii and thickness")?;
    }
    Ok(())
}

/// What the radius fit would do: with normals and radii in the file, the screen's choice
/// (`pointcloud::screen`, as `render` runs it with `--fit-radii auto`, before duplicates are
/// dropped); else the fit, on radii or normals yet to be estimated.
fn fit_choice(cloud: &PointCloud) -> String {
    let what = "fit disk radii to the sampling (grown where disks would leave pinholes, \
                trimmed at open edges; --raw-radii keeps them)";
    let (Some(normals), Some(radii)) = (&cloud.normals, &cloud.radius) else {
        return what.to_string();
    };
    let own = own_radii(cloud);
    let mut radii = radii.clone();
    bound_by_area(&mut radii, &own);
    let index = PointIndex::build(&cloud.positions);
    let screen = screen_fit(&index, &cloud.positions, normals, &radii, &own);
    if screen.keeps_radii() {
        screen.to_string()
    } else {
        format!("{what}: {screen}")
    }
}

/// The file's attributes as stored: name, type, components, what filmsplat reads each as, and
/// the range of the values read (thickness after conversion to nm).
fn write_stored(
    out: &mut dyn Write,
    cloud: &PointCloud,
    stored: &[StoredAttribute],
) -> std::io::Result<()> {
    writeln!(
        out,
        "stored attributes (pick with --thickness-attr/--normal-attr/--radius-attr):"
    )?;
    writeln!(
        out,
        "  {:<14} {:<18} {:<10} range",
        "name", "type", "read as"
    )?;
    // Single-component position/normal attributes (PLY's x, nx, ...) come in x, y, z order.
    let (mut pos_c, mut nrm_c) = (0usize, 0usize);
    for s in stored {
        let ty = if s.components <= 1 {
            s.stored.clone()
        } else {
            format!("{} x{}", s.stored, s.components)
        };
        let vec_range = |v: &[glam::Vec3], c: &mut usize, k: usize| {
            if k == 3 {
                range_text((0..3).flat_map(|j| v.iter().map(move |p| p[j])))
            } else {
                let j = (*c).min(2);
                *c += 1;
                range_text(v.iter().map(|p| p[j]))
            }
        };
        let range = match s.role {
            AttributeRole::Position => vec_range(&cloud.positions, &mut pos_c, s.components),
            AttributeRole::Normal => match &cloud.normals {
                Some(n) => vec_range(n, &mut nrm_c, s.components),
                None => String::new(),
            },
            AttributeRole::Thickness => cloud
                .thickness_nm
                .as_deref()
                .map(|t| format!("{} nm", range_text(t.iter().copied())))
                .unwrap_or_default(),
            AttributeRole::Radius => cloud
                .radius
                .as_deref()
                .map(|r| range_text(r.iter().copied()))
                .unwrap_or_default(),
            AttributeRole::Extra => {
                let cols = crate::io::component_names(&s.name, s.components);
                range_text(
                    cols.iter()
                        .filter_map(|c| cloud.extra(c))
                        .flat_map(|v| v.iter().copied()),
                )
            }
            AttributeRole::Skipped => "(not read)".to_string(),
        };
        if s.role == AttributeRole::Skipped && s.components == 0 {
            // A whole file the reader knows and leaves: say what it holds.
            writeln!(
                out,
                "  {:<14} skipped: {}",
                crate::io::show_name(&s.name),
                s.stored
            )?;
            continue;
        }
        writeln!(
            out,
            "  {:<14} {:<18} {:<10} {range}",
            crate::io::show_name(&s.name),
            ty,
            s.role.to_string()
        )?;
    }
    Ok(())
}

/// "min .. max" of the finite values, with the count of non-finite ones if any.
fn range_text(values: impl Iterator<Item = f32>) -> String {
    let (mut lo, mut hi, mut bad, mut n) = (f32::INFINITY, f32::NEG_INFINITY, 0usize, 0usize);
    for v in values {
        n += 1;
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        } else {
            bad += 1;
        }
    }
    let mut t = if n == 0 {
        "(empty)".to_string()
    } else if lo > hi {
        "no finite values".to_string()
    } else {
        let n = |v: f32| crate::pointcloud::stats::number(v, 6);
        format!("{} .. {}", n(lo), n(hi))
    };
    if bad > 0 {
        t.push_str(&format!(" ({bad} non-finite)"));
    }
    t
}
