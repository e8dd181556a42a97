//! `filmsplat convert`: any particle file filmsplat reads, out as binary PLY.

use crate::io::{PartKind, write_droplets_ply, write_ply};
use crate::pipeline::read_input_parts;
use crate::pointcloud::PointCloud;
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
    /// attributes, all float): the film particles. An input that also holds droplets (a
    /// ruptured thin-film SPH frame) writes them to STEM.droplets.ply beside it.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    attributes: super::attributes::AttributeArgs,
    /// Keep only these extra attributes (comma-separated names); default: all.
    #[arg(long, value_delimiter = ',')]
    keep: Option<Vec<String>>,
}

/// Runs `filmsplat convert`: every film part of the input into `-o` (one cloud), and the
/// droplets, when the input holds any, into `STEM.droplets.ply` beside it; says on `out` (the
/// CLI's messages) what went where.
pub fn run(a: &ConvertArgs, out: &mut dyn Write) -> Result<()> {
    let opts = a.attributes.read_options()?;
    // Droplets sized as a render sizes them (from the run's stored volume).
    let parts = read_input_parts(&a.input, &opts)?;
    let of = |kind: PartKind| -> PointCloud {
        let clouds: Vec<PointCloud> = parts
            .iter()
            .filter(|p| p.kind == kind)
            .map(|p| p.cloud.clone())
            .collect();
        PointCloud::concat(&clouds)
    };
    let (mut film, mut droplets) = (of(PartKind::Film), of(PartKind::Droplets));
    if let Some(keep) = &a.keep {
        if let Some(missing) = keep
            .iter()
            .find(|k| !film.extra.iter().any(|(n, _)| n == *k))
        {
            return Err(Error::invalid(format!(
                "{}: no attribute '{missing}' to keep",
                a.input.display()
            )));
        }
        film.extra.retain(|(n, _)| keep.contains(n));
        droplets.extra.retain(|(n, _)| keep.contains(n));
    }
    let droplet_path =
        (!droplets.is_empty()).then(|| crate::pipeline::beside::droplets_path(&a.output));
    if let Some(p) = &droplet_path {
        write_droplets_ply(p, &droplets)?;
    }
    write_ply(&a.output, &film)?;
    let _ = writeln!(
        out,
        "wrote {} particles to {}",
        film.len(),
        a.output.display()
    );
    if let Some(p) = droplet_path {
        let _ = writeln!(
            out,
            "wrote {} droplets (the input's other part: radius = each droplet's, scene units) to {}",
            droplets.len(),
            p.display()
        );
    }
    Ok(())
}
