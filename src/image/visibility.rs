//! Can the film's colours be seen? The share of film pixels whose interference colour is
//! visible, a property of the lighting (not of the film): a film pixel shows the light the
//! film reflects (which carries the interference colour) on top of the backdrop seen through
//! it (which does not). Its colour is visible when
//!
//! 1. **the reflection dominates**: the pixel's luminance is at least [`CONTRAST`] = 2 times
//!    the backdrop's along the same ray, i.e. the film adds at least as much light as the
//!    backdrop gives (Weber contrast ≥ 1). Below that the pixel is mostly backdrop: on a dark
//!    ground the film looks like a dark glass, its colour a tint at best;
//! 2. **the pixel is not black**: its displayed lightness L* is at least [`MIN_LIGHTNESS`] =
//!    20 (hue discrimination collapses toward black; on a dark ground a 2× contrast over a
//!    near-black backdrop is still black);
//! 3. **the pixel is not burnt out**: no displayed channel is at or above [`BURNT`] (0.98),
//!    where the tone curve has flattened the hue toward white.
//!
//! Chroma itself is not a criterion: it belongs to the data (a 10 µm film is white in any
//! light, a 30 nm one black); the lighting can hide it only by the three ways above.

/// Film luminance over backdrop luminance at which the film's colour dominates its pixel.
pub const CONTRAST: f32 = 2.0;
/// Least displayed lightness L* (CIELAB, 0..100) at which a colour is seen.
pub const MIN_LIGHTNESS: f32 = 20.0;
/// A displayed channel at or above this (0..1) is burnt out.
pub const BURNT: f32 = 0.98;
/// Least coverage (share of the pixel's samples that hit a film) of a film pixel.
pub const MIN_COVERAGE: f32 = 0.5;

/// How many film pixels show their colour, and why the others do not.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ColourVisibility {
    /// Pixels covered by film (coverage ≥ [`MIN_COVERAGE`]).
    pub film_pixels: usize,
    /// Film pixels whose colour is visible.
    pub visible: usize,
    /// Film pixels less than [`CONTRAST`] times as bright as their backdrop.
    pub faint: usize,
    /// Film pixels darker than [`MIN_LIGHTNESS`] (and not faint).
    pub dark: usize,
    /// Film pixels burnt out (and neither faint nor dark).
    pub burnt: usize,
}

impl ColourVisibility {
    /// Share of the film pixels whose colour is visible, 0..1 (0 without film).
    pub fn share(&self) -> f64 {
        if self.film_pixels == 0 {
            0.0
        } else {
            self.visible as f64 / self.film_pixels as f64
        }
    }
}

impl std::fmt::Display for ColourVisibility {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let pct = |n: usize| 100.0 * n as f64 / self.film_pixels.max(1) as f64;
        write!(
            f,
            "colour visible on {:.1} % of {} film pixels (faint {:.1} %, dark {:.1} %, burnt {:.1} %)",
            100.0 * self.share(),
            self.film_pixels,
            pct(self.faint),
            pct(self.dark),
            pct(self.burnt)
        )
    }
}

/// Relative luminance of linear sRGB (Rec. 709 weights).
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// CIELAB L* of a relative luminance (white = 1).
fn lightness(y: f32) -> f32 {
    let t = y.max(0.0);
    let f = if t > 216.0 / 24389.0 {
        t.cbrt()
    } else {
        (24389.0 / 27.0 * t + 16.0) / 116.0
    };
    116.0 * f - 16.0
}

/// Classifies every film pixel. Per pixel (row-major, all slices the same length): `pixel`,
/// the rendered linear RGB (film and what shows through it); `backdrop`, the linear RGB the
/// same camera ray gets with no film; `coverage`, the share of its samples that hit a film;
/// `display`, the displayed (tone-mapped, linear-light 0..1) RGB.
///
/// # Panics
/// If the slices differ in length.
pub fn colour_visibility(
    pixel: &[[f32; 3]],
    backdrop: &[[f32; 3]],
    coverage: &[f32],
    display: &[[f32; 3]],
) -> ColourVisibility {
    assert!(
        pixel.len() == backdrop.len()
            && pixel.len() == coverage.len()
            && pixel.len() == display.len(),
        "one value of each per pixel"
    );
    let mut v = ColourVisibility::default();
    for i in 0..pixel.len() {
        if coverage[i].is_nan() || coverage[i] < MIN_COVERAGE {
            continue;
        }
        v.film_pixels += 1;
        let (y, back) = (luminance(pixel[i]), luminance(backdrop[i]));
        if y.is_nan() || y < CONTRAST * back {
            v.faint += 1;
        } else if lightness(luminance(display[i])) < MIN_LIGHTNESS {
            v.dark += 1;
        } else if display[i].iter().any(|&c| c >= BURNT) {
            v.burnt += 1;
        } else {
            v.visible += 1;
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_pixel_lands_in_one_class_by_the_stated_thresholds() {
        let grey = |v: f32| [v; 3];
        // (pixel, backdrop, coverage, display) → the class expected.
        let cases = [
            (grey(0.30), grey(0.10), 1.0, grey(0.30), "visible"),
            (grey(0.19), grey(0.10), 1.0, grey(0.19), "faint"), // 1.9× < 2×
            (grey(0.20), grey(0.10), 1.0, grey(0.20), "visible"), // exactly 2×
            (grey(0.02), grey(0.001), 1.0, grey(0.02), "dark"), // L* 15.5 < 20
            (grey(0.04), grey(0.001), 1.0, grey(0.04), "visible"), // L* 23.7
            (grey(5.0), grey(0.1), 1.0, [0.99, 0.5, 0.5], "burnt"),
            (grey(0.30), grey(0.10), 0.4, grey(0.30), "none"), // not film
        ];
        for (p, b, c, d, want) in cases {
            let v = colour_visibility(&[p], &[b], &[c], &[d]);
            let got = match (v.film_pixels, v.visible, v.faint, v.dark, v.burnt) {
                (0, ..) => "none",
                (1, 1, ..) => "visible",
                (1, 0, 1, ..) => "faint",
                (1, 0, 0, 1, _) => "dark",
                (1, 0, 0, 0, 1) => "burnt",
                other => panic!("{other:?}"),
            };
            assert_eq!(got, want, "{p:?} over {b:?}");
        }
    }

    #[test]
    fn the_share_counts_film_pixels_only() {
        let n = 10;
        let pixel: Vec<[f32; 3]> = (0..n).map(|i| [0.05 * i as f32; 3]).collect();
        let backdrop = vec![[0.1f32; 3]; n];
        let coverage: Vec<f32> = (0..n).map(|i| if i < 8 { 1.0 } else { 0.0 }).collect();
        let v = colour_visibility(&pixel, &backdrop, &coverage, &pixel);
        // Film pixels 0..8 at 0, 0.05, ... 0.35: those from 0.2 (i = 4..8) are 2× the backdrop.
        assert_eq!((v.film_pixels, v.visible, v.faint), (8, 4, 4));
        assert!((v.share() - 0.5).abs() < 1e-12);
        assert_eq!(ColourVisibility::default().share(), 0.0);
        assert!(
            v.to_string()
                .starts_with("colour visible on 50.0 % of 8 film pixels")
        );
    }

    #[test]
    fn lightness_matches_cielab() {
        assert!((lightness(1.0) - 100.0).abs() < 1e-3);
        assert!((lightness(0.18) - 49.5).abs() < 0.1);
        assert!(lightness(0.0).abs() < 1e-4);
    }
}
