//! `filmsplat film`: thin-film reflectance and colour as CSV.

use super::parse::{self, NumberList};
use crate::optics::{check_film_params, film_rt};
use crate::spectrum::{film_rgb_reference, reference_grid_nm};
use crate::{Error, Result};
use clap::Args;
use std::io::Write;

/// Arguments of `filmsplat film`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  filmsplat film --thickness 0,100,300 --angle 0,45,89\n  \
filmsplat film --rgb --thickness 0:1500:25 --angle 0 --ior 1.33"
)]
pub struct FilmArgs {
    /// Film thicknesses in nanometres: a comma-separated list, items may be ranges start:end:step
    /// (e.g. 0,100,300 or 0:1000:50).
    #[arg(long, value_parser = parse::number_list_arg, allow_hyphen_values = true)]
    thickness: Vec<NumberList>,
    /// Angles of incidence in degrees, 0 (normal) to 90 (grazing); list or ranges as for
    /// --thickness.
    #[arg(long, value_parser = parse::number_list_arg, allow_hyphen_values = true)]
    angle: Vec<NumberList>,
    /// Index of refraction of the film (soap water ≈ 1.33); the film sits between air and air.
    #[arg(long, default_value_t = 1.33, value_parser = super::parse::finite_f64)]
    ior: f64,
    /// Vacuum wavelengths in nanometres, as start:end:step or a list. Default: 380:780:5 for
    /// spectra; 360:830:1 for --rgb.
    #[arg(long, value_parser = parse::number_list_arg)]
    wavelengths: Option<NumberList>,
    /// Print the colour of D65 light reflected by the film instead (linear sRGB; a perfect white
    /// reflector gives 1,1,1): columns thickness_nm,angle_deg,r,g,b.
    #[arg(long)]
    rgb: bool,
}

/// Runs `filmsplat film`.
pub fn run(args: &FilmArgs, out: &mut dyn Write) -> Result<()> {
    let thicknesses: Vec<f64> = args
        .thickness
        .iter()
        .flat_map(|l| l.0.iter().copied())
        .collect();
    let angles: Vec<f64> = args
        .angle
        .iter()
        .flat_map(|l| l.0.iter().copied())
        .collect();
    if thicknesses.is_empty() || angles.is_empty() {
        return Err(Error::invalid(
            "film: give at least one --thickness and one --angle",
        ));
    }
    for &h in &thicknesses {
        check_film_params(args.ior, h).map_err(|m| Error::invalid(format!("film: {m}")))?;
    }
    if let Some(a) = angles.iter().find(|a| !(0.0..=90.0).contains(*a)) {
        return Err(Error::invalid(format!(
            "film: angle {a} is outside 0..90 degrees"
        )));
    }
    let lambdas = match &args.wavelengths {
        Some(l) => l.0.clone(),
        None if args.rgb => reference_grid_nm(),
        None => parse::range("380:780:5").expect("valid default"),
    };
    if let Some(l) = lambdas.iter().find(|l| !(100.0..=10_000.0).contains(*l)) {
        return Err(Error::invalid(format!(
            "film: wavelength {l} nm is outside 100..10000 nm"
        )));
    }
    let io = |e: std::io::Error| Error::invalid(format!("film: writing output: {e}"));
    if args.rgb {
        writeln!(out, "thickness_nm,angle_deg,r,g,b").map_err(io)?;
    } else {
        writeln!(out, "thickness_nm,angle_deg,wavelength_nm,R,T,Rs,Rp").map_err(io)?;
    }
    for &h in &thicknesses {
        for &a in &angles {
            let cos_i = a.to_radians().cos().max(0.0);
            // cos(90°) in f64 is 6e-17, not 0: treat 90° as exactly grazing.
            let cos_i = if a == 90.0 { 0.0 } else { cos_i };
            if args.rgb {
                let [r, g, b] = film_rgb_reference(cos_i, h, args.ior, &lambdas);
                writeln!(out, "{h},{a},{r},{g},{b}").map_err(io)?;
            } else {
                for &l in &lambdas {
                    let rt = film_rt(cos_i, h, args.ior, l);
                    writeln!(out, "{h},{a},{l},{},{},{},{}", rt.r(), rt.t(), rt.rs, rt.rp)
                        .map_err(io)?;
                }
            }
        }
    }
    Ok(())
}
