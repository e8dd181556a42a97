//! The interference colour chart: the reflected colour of a film against thickness (x) and
//! angle of incidence (y) — the picture a scientist reads a film's thickness from.

use crate::image::{Anchor, RgbImage, draw_line, draw_text, draw_text_vertical};
use crate::optics::FilmFresnel;
use crate::spectrum::{SpectralWeights, reference_grid_nm};
use rayon::prelude::*;

/// Parameters of [`interference_chart`].
#[derive(Debug, Clone)]
pub struct ChartParams {
    /// Largest thickness shown, nm.
    pub max_thickness_nm: f32,
    /// Film index of refraction.
    pub ior: f32,
    /// Largest angle of incidence shown, degrees (< 90).
    pub max_angle_deg: f32,
    /// Image size, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
}

impl Default for ChartParams {
    fn default() -> Self {
        ChartParams {
            max_thickness_nm: 1500.0,
            ior: 1.33,
            max_angle_deg: 89.0,
            width: 1600,
            height: 900,
        }
    }
}

impl ChartParams {
    /// Checks the parameters as `filmsplat chart` does: a valid film (index, thickness > 0),
    /// a largest angle of 1..89.9 degrees, a size between 400x300 and 16384x16384.
    pub fn check(&self) -> crate::Result<()> {
        use crate::Error;
        crate::optics::check_film_params(self.ior as f64, self.max_thickness_nm as f64)
            .map_err(|m| Error::invalid(format!("chart: {m}")))?;
        if self.max_thickness_nm <= 0.0 {
            return Err(Error::invalid("chart: --max-thickness must be > 0 nm"));
        }
        if !(1.0..=89.9).contains(&self.max_angle_deg) {
            return Err(Error::invalid(format!(
                "chart: --max-angle must be 1..89.9 degrees, got {}",
                self.max_angle_deg
            )));
        }
        if !(400..=16_384).contains(&self.width) || !(300..=16_384).contains(&self.height) {
            return Err(Error::invalid(
                "chart: --size must be between 400x300 and 16384x16384",
            ));
        }
        // The chart, its 8-bit copy and the encoder: ~40 bytes a pixel.
        let (w, h) = (self.width, self.height);
        crate::budget::check((w * h) as u64 * 40, || format!("chart: a {w}x{h} chart"))
            .map_err(Error::invalid)?;
        Ok(())
    }
}

const INK: [f32; 3] = [0.015, 0.015, 0.015];
const GRID: [f32; 3] = [0.35, 0.35, 0.35];

/// A "nice" tick step (1, 2 or 5 × 10^k) giving about `target` ticks over `span`.
fn nice_step(span: f32, target: f32) -> f32 {
    let raw = span / target;
    let mag = 10f32.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag)
}

/// Renders the chart as a linear-RGB image (white background), ready for sRGB encoding with a
/// clamp tone curve.
///
/// Colour: the 1 nm spectral integral of D65 light reflected by the film (the same numbers as
/// `filmsplat film --rgb`). Each row is exposed so that the incoherent reflectance of a very
/// thick film at that angle shows as a light grey (0.45); without it the chart would be black
/// at normal incidence (soap reflects ~4%) and white near grazing. Out-of-gamut colours are
/// brought into gamut by scaling (hue kept) and clipping negatives.
pub fn interference_chart(p: &ChartParams) -> RgbImage {
    let (w, h) = (p.width.max(400), p.height.max(300));
    let mut img = RgbImage::filled(w, h, [1.0; 3]);
    let s = (h as f32 / 900.0).max(0.5); // type scale
    let (left, right, top, bottom) = (
        (120.0 * s) as usize,
        (40.0 * s) as usize,
        (96.0 * s) as usize,
        (100.0 * s) as usize,
    );
    let (pw, ph) = (w - left - right, h - top - bottom);
    for (r, row) in chart_rows(p, pw, ph).into_iter().enumerate() {
        for (c, v) in row.into_iter().enumerate() {
            img.set(left + c, top + r, v);
        }
    }
    let plot = Plot {
        x0: left as f32,
        y0: top as f32,
        x1: (left + pw) as f32,
        y1: (top + ph) as f32,
        s,
    };
    draw_ticks(&mut img, p, &plot);
    draw_labels(&mut img, p, &plot);
    img
}

/// The plot's colours: one row per pixel row, angle decreasing upward from the largest at the
/// top, thickness increasing to the right.
fn chart_rows(p: &ChartParams, pw: usize, ph: usize) -> Vec<Vec<[f32; 3]>> {
    let grid: Vec<f32> = reference_grid_nm().iter().map(|&l| l as f32).collect();
    let weights = SpectralWeights::new(&grid);
    (0..ph)
        .into_par_iter()
        .map(|r| {
            let angle = p.max_angle_deg * (1.0 - (r as f32 + 0.5) / ph as f32);
            let fresnel = FilmFresnel::new(angle.to_radians().cos(), p.ior);
            let exposure = 0.45 / fresnel.incoherent_reflectance().max(1e-6);
            (0..pw)
                .map(|c| {
                    let thickness = p.max_thickness_nm * (c as f32 + 0.5) / pw as f32;
                    let rgb = weights
                        .film_reflectance_rgb(&fresnel, thickness)
                        .map(|v| (v * exposure).max(0.0));
                    let m = rgb[0].max(rgb[1]).max(rgb[2]);
                    if m > 1.0 { rgb.map(|v| v / m) } else { rgb }
                })
                .collect()
        })
        .collect()
}

/// The plot's frame in pixels (`x0, y0` top left, `x1, y1` bottom right) and the type scale.
struct Plot {
    x0: f32,
    y0: f32,
    x1: f32,
    y1: f32,
    s: f32,
}

/// Frame, major and minor ticks and their values.
fn draw_ticks(img: &mut RgbImage, p: &ChartParams, plot: &Plot) {
    let Plot { x0, y0, x1, y1, s } = *plot;
    let (pw, ph) = (x1 - x0, y1 - y0);
    let tick = 8.0 * s;
    let label = 20.0 * s;
    let x_step = nice_step(p.max_thickness_nm, 12.0);
    let mut v = 0.0;
    while v <= p.max_thickness_nm + 1e-3 {
        let x = x0 + v / p.max_thickness_nm * pw;
        draw_line(img, x, y1, x, y1 + tick, 1.5 * s, INK);
        let at = (x, y1 + tick + 4.0 * s);
        draw_text(
            img,
            at.0,
            at.1,
            &format!("{v}"),
            label,
            INK,
            Anchor::TOP_CENTRE,
        );
        v += x_step;
    }
    // Minor ticks.
    let mut v = 0.0;
    while v <= p.max_thickness_nm + 1e-3 {
        let x = x0 + v / p.max_thickness_nm * pw;
        draw_line(img, x, y1, x, y1 + 0.5 * tick, 1.0 * s, GRID);
        v += x_step / 5.0;
    }
    let y_step = nice_step(p.max_angle_deg, 9.0);
    let mut a = 0.0;
    while a <= p.max_angle_deg + 1e-3 {
        let y = y1 - a / p.max_angle_deg * ph;
        draw_line(img, x0 - tick, y, x0, y, 1.5 * s, INK);
        let at = (x0 - tick - 6.0 * s, y);
        draw_text(
            img,
            at.0,
            at.1,
            &format!("{a}°"),
            label,
            INK,
            Anchor::MIDDLE_RIGHT,
        );
        a += y_step;
    }
    for (xa, ya, xb, yb) in [
        (x0, y0, x1, y0),
        (x0, y1, x1, y1),
        (x0, y0, x0, y1),
        (x1, y0, x1, y1),
    ] {
        draw_line(img, xa, ya, xb, yb, 1.5 * s, INK);
    }
}

/// Axis titles, title and subtitle.
fn draw_labels(img: &mut RgbImage, p: &ChartParams, plot: &Plot) {
    let Plot { x0, y0, x1, y1, s } = *plot;
    let h = img.height as f32;
    let axis = "Film thickness (nm)";
    draw_text(
        img,
        0.5 * (x0 + x1),
        h - 22.0 * s,
        axis,
        24.0 * s,
        INK,
        Anchor::BASELINE_CENTRE,
    );
    let axis = "Angle of incidence (degrees)";
    draw_text_vertical(
        img,
        30.0 * s,
        0.5 * (y0 + y1),
        axis,
        24.0 * s,
        INK,
        Anchor::CENTRE,
    );
    let title = format!(
        "Thin-film interference colours: film of n = {} in air, D65 light, CIE 1931 2°",
        p.ior
    );
    draw_text(
        img,
        x0,
        40.0 * s,
        &title,
        28.0 * s,
        INK,
        Anchor::BASELINE_LEFT,
    );
    let sub = "Reflected colour; each angle exposed so a very thick film appears light grey";
    draw_text(
        img,
        x0,
        70.0 * s,
        sub,
        18.0 * s,
        [0.25; 3],
        Anchor::BASELINE_LEFT,
    );
}
