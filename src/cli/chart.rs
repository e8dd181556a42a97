//! `filmsplat chart`: the interference colour chart as a PNG.

use crate::figure::{ChartParams, interference_chart};
use crate::image::{ToneMap, save_png};
use crate::optics::check_film_params;
use crate::{Error, Result};
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
    check_film_params(a.ior as f64, a.max_thickness as f64)
        .map_err(|m| Error::invalid(format!("chart: {m}")))?;
    if a.max_thickness <= 0.0 {
        return Err(Error::invalid("chart: --max-thickness must be > 0 nm"));
    }
    if !(1.0..=89.9).contains(&a.max_angle) {
        return Err(Error::invalid(format!(
            "chart: --max-angle must be 1..89.9 degrees, got {}",
            a.max_angle
        )));
    }
    let (width, height) = a.size;
    if !(400..=16_384).contains(&width) || !(300..=16_384).contains(&height) {
        return Err(Error::invalid(
            "chart: --size must be between 400x300 and 16384x16384",
        ));
    }
    // The chart, its 8-bit copy and the encoder: ~40 bytes a pixel.
    crate::budget::check((width * height) as u64 * 40, || {
        format!("chart: a {width}x{height} chart")
    })
    .map_err(Error::invalid)?;
    let params = ChartParams {
        max_thickness_nm: a.max_thickness,
        ior: a.ior,
        max_angle_deg: a.max_angle,
        width,
        height,
    };
    let img = interference_chart(&params);
    save_png(&a.output, &img, 0.0, ToneMap::Clamp)?;
    let _ = writeln!(out, "wrote {}", a.output.display());
    Ok(())
}
