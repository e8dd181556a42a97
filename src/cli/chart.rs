//! `filmsplat chart`: the interference colour chart as a PNG.

use crate::Result;
use crate::figure::{ChartParams, interference_chart};
use crate::image::{ToneMap, save_png};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `filmsplat chart`.
#[derive(Debug, Args)]
pub struct ChartArgs {
    /// Output PNG file.
    #[arg(short, long)]
    output: PathBuf,
    /// Largest film thickness on the x axis, nanometres.
    #[arg(long, default_value_t = 1500.0, value_parser = super::parse::finite_f32)]
    max_thickness: f32,
    /// Film index of refraction.
    #[arg(long, default_value_t = 1.33, value_parser = super::parse::finite_f32)]
    ior: f32,
    /// Largest angle of incidence on the y axis, degrees (1..=89.9).
    #[arg(long, default_value_t = 89.0, value_parser = super::parse::finite_f32)]
    max_angle: f32,
    /// Image size as WIDTHxHEIGHT, pixels.
    #[arg(long, default_value = "1600x900", value_parser = super::parse::size)]
    size: (usize, usize),
}

/// Runs `filmsplat chart`.
pub fn run(a: &ChartArgs, out: &mut dyn Write) -> Result<()> {
    let (width, height) = a.size;
    let params = ChartParams {
        max_thickness_nm: a.max_thickness,
        ior: a.ior,
        max_angle_deg: a.max_angle,
        width,
        height,
    };
    params.check()?;
    let img = interference_chart(&params);
    save_png(&a.output, &img, 0.0, ToneMap::Clamp)?;
    let _ = writeln!(out, "wrote {}", a.output.display());
    Ok(())
}
