//! `filmsplat convert`: any particle file filmsplat reads, out as binary PLY.

use crate::io::{read_cloud, write_ply};
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
    #[command(flatten)]
    attributes: super::attributes::AttributeArgs,
    /// Keep only these extra attributes (comma-separated names); default: all.
    #[arg(long, value_delimiter = ',')]
    keep: Option<Vec<String>>,
}

/// Runs `filmsplat convert`.
pub fn run(a: &ConvertArgs, out: &mut dyn Write) -> Result<()> {
    let opts = a.attributes.read_options()?;
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
