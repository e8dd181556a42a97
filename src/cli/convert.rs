//! `filmsplat convert`: any particle file filmsplat reads, out as binary PLY.

use crate::io::{ReadOptions, read_cloud, write_ply};
use crate::pipeline::thickness_unit_factor;
use crate::{Error, Result};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `filmsplat convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Input particle file or frame folder (any format `render` reads).
    input: PathBuf,
    /// Output PLY (binary little-endian; x y z, nx ny nz, rh in nm, radius, then the other
    /// attributes, all float).
    #[arg(short, long)]
    output: PathBuf,
    /// Unit of the input's thickness values: nm, um, mm or m (default: the format's unit).
    #[arg(long)]
    thickness_unit: Option<String>,
    /// Name of the thickness attribute (written as rh, in nm).
    #[arg(long)]
    thickness_attr: Option<String>,
    /// Prefix of the normal attributes (e.g. n for nx ny nz, normal for normal_x ...).
    #[arg(long)]
    normal_attr: Option<String>,
    /// Name of the radius attribute.
    #[arg(long)]
    radius_attr: Option<String>,
    /// Keep only these extra attributes (comma-separated names); default: all.
    #[arg(long, value_delimiter = ',')]
    keep: Option<Vec<String>>,
}

/// Read options from the attribute flags shared by `convert`, `info` and `render`.
pub fn read_options(
    thickness_unit: Option<&str>,
    thickness_attr: Option<&String>,
    normal_attr: Option<&String>,
    radius_attr: Option<&String>,
) -> Result<ReadOptions> {
    let mut opts = ReadOptions {
        thickness_attr: thickness_attr.cloned(),
        normal_attr: normal_attr.cloned(),
        radius_attr: radius_attr.cloned(),
        ..ReadOptions::default()
    };
    if let Some(unit) = thickness_unit {
        opts.thickness_scale_to_nm = thickness_unit_factor(unit)?;
        opts.thickness_unit_explicit = true;
    }
    Ok(opts)
}

/// Runs `filmsplat convert`.
pub fn run(a: &ConvertArgs, out: &mut dyn Write) -> Result<()> {
    let opts = read_options(
        a.thickness_unit.as_deref(),
        a.thickness_attr.as_ref(),
        a.normal_attr.as_ref(),
        a.radius_attr.as_ref(),
    )?;
    let mut cloud = read_cloud(&a.input, &opts)?;
    if let Some(keep) = &a.keep {
        if let Some(missing) = keep
            .iter()
            .find(|k| !cloud.extra.iter().any(|(n, _)| n == *k))
        {
            return Err(Error::invalid(format!(
                "{}: no attribute '{missing}' to keep",
                a.input.display()
            )));
        }
        cloud.extra.retain(|(n, _)| keep.contains(n));
    }
    write_ply(&a.output, &cloud)?;
    let _ = writeln!(
        out,
        "wrote {} particles to {}",
        cloud.len(),
        a.output.display()
    );
    Ok(())
}
