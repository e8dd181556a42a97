//! The colour of a thin film under white (D65) light: spectral reflectance reduced to linear
//! sRGB, three ways — an f64 reference, a per-hit f32 integration over any set of wavelengths,
//! and a precomputed lookup table.
//!
//! All three use the weights `w_c(λ) = D65(λ) · (M · cmf(λ))_c` (M: XYZ → linear sRGB),
//! normalised so that `Σ_λ w_c(λ) = 1`: a perfect reflector is exactly (1, 1, 1) and, since
//! the film is lossless, the transmitted colour is exactly `1 − reflected`.

use super::cie::{self, CMF_MAX_NM, CMF_MIN_NM};
use super::colour::XYZ_TO_LINEAR_SRGB;
use super::wavelengths::MAX_WAVELENGTHS;
use crate::optics::{FilmFresnel, film_rt};

mod lut;
pub use lut::FilmLut;

/// Un-normalised colour weights of one wavelength: D65(λ) · (M · cmf(λ)).
fn raw_weight(lambda_nm: f64) -> [f64; 3] {
    let t = cie::tables();
    let xyz = t.cmf(lambda_nm);
    let d = t.d65(lambda_nm);
    let m = &XYZ_TO_LINEAR_SRGB;
    [0, 1, 2].map(|r| d * (m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2]))
}

/// The 1 nm grid 360, 361, …, 830 nm used for reference colours.
pub fn reference_grid_nm() -> Vec<f64> {
    let n = (CMF_MAX_NM - CMF_MIN_NM) as usize + 1;
    (0..n).map(|i| CMF_MIN_NM + i as f64).collect()
}

/// Reference colour (linear sRGB) of D65 light reflected by a film, in f64 with the Airy
/// reference, summed over the wavelengths `lambda_nm` (use [`reference_grid_nm`] for the 1 nm
/// standard). Normalised so a perfect reflector gives exactly (1, 1, 1).
///
/// # Example
/// The colour `filmsplat film` prints. Its luminance is a mean of the film's reflectance over
/// the wavelengths weighted by the eye's (positive) sensitivity, so it lies within the
/// reflectance's range; no film reflects nothing; a 30 nm film (far thinner than a quarter
/// wave) reflects R ∝ 1/λ²: blue most, red least:
/// ```
/// use filmsplat::optics::film_rt;
/// use filmsplat::spectrum::{film_rgb_reference, reference_grid_nm};
/// let grid = reference_grid_nm();
/// for h in [30.0, 100.0, 450.0] {
///     let [r, g, b] = film_rgb_reference(1.0, h, 1.33, &grid);
///     let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
///     let rs: Vec<f64> = grid.iter().map(|&l| film_rt(1.0, h, 1.33, l).r()).collect();
///     let (lo, hi) = rs.iter().fold((1.0f64, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
///     assert!(lo - 1e-3 <= y && y <= hi + 1e-3, "{h} nm: Y {y} outside {lo}..{hi}");
/// }
/// let rgb = film_rgb_reference(1.0, 30.0, 1.33, &grid);
/// assert!(rgb[2] > rgb[1] && rgb[1] > rgb[0], "{rgb:?}");
/// assert_eq!(film_rgb_reference(1.0, 0.0, 1.33, &grid), [0.0; 3]);
/// ```
pub fn film_rgb_reference(cos_i: f64, thickness_nm: f64, ior: f64, lambda_nm: &[f64]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut white = [0.0; 3];
    for &l in lambda_nm {
        let w = raw_weight(l);
        let r = film_rt(cos_i, thickness_nm, ior, l).r();
        for c in 0..3 {
            sum[c] += r * w[c];
            white[c] += w[c];
        }
    }
    [0, 1, 2].map(|c| {
        if white[c] != 0.0 {
            sum[c] / white[c]
        } else {
            0.0
        }
    })
}

/// Colour weights for one set of wavelengths, reusable across many hits (build once per camera
/// sample, not per hit). Cost to build: ~15 ns per wavelength; per hit: ~1.5 ns per wavelength.
#[derive(Debug, Clone, Default)]
pub struct SpectralWeights {
    inv_lambda: Vec<f32>,
    weight: Vec<[f32; 3]>,
}

impl SpectralWeights {
    /// Weights for the wavelengths `lambda_nm` (any number).
    pub fn new(lambda_nm: &[f32]) -> Self {
        let mut w = SpectralWeights::default();
        w.set(lambda_nm);
        w
    }

    /// Recomputes the weights for new wavelengths, reusing the allocation, white-balanced:
    /// normalised per channel so that a perfect reflector is exactly 1 with these very
    /// wavelengths. Right for fixed grids (no colour cast on neutral films); for random
    /// wavelengths use [`set_unbiased`](Self::set_unbiased).
    pub fn set(&mut self, lambda_nm: &[f32]) {
        self.set_normalised(lambda_nm, true)
    }

    /// Recomputes the weights for wavelengths drawn uniformly at random over 360–830 nm: the
    /// plain Monte Carlo estimator, normalised by the exact white integral, so its mean over
    /// samples is the true colour. (A per-sample white balance would be a ratio estimator:
    /// biased, and unstable for few wavelengths when a channel's weights nearly cancel.)
    pub fn set_unbiased(&mut self, lambda_nm: &[f32]) {
        self.set_normalised(lambda_nm, false)
    }

    fn set_normalised(&mut self, lambda_nm: &[f32], white_balance: bool) {
        self.inv_lambda.clear();
        self.weight.clear();
        let mut white = [0.0f64; 3];
        for &l in lambda_nm {
            let w = raw_weight(l as f64);
            for c in 0..3 {
                white[c] += w[c];
            }
            self.inv_lambda.push(1.0 / l);
            self.weight.push([w[0] as f32, w[1] as f32, w[2] as f32]);
        }
        // If a channel's weights cancel (possible for one or two wavelengths), white balance
        // falls back to the full-range integral.
        let full = white_integral_per_nm();
        let count = lambda_nm.len() as f64;
        for c in 0..3 {
            let exact = full[c] * count;
            let norm = if white_balance && white[c] > 1e-6 * exact {
                white[c]
            } else {
                exact
            };
            for w in &mut self.weight {
                w[c] = (w[c] as f64 / norm) as f32;
            }
        }
    }

    /// Per-wavelength colour weights (linear sRGB), in the order the wavelengths were given.
    pub fn weights(&self) -> &[[f32; 3]] {
        &self.weight
    }

    /// Number of wavelengths.
    pub fn len(&self) -> usize {
        self.inv_lambda.len()
    }

    /// True if there are no wavelengths.
    pub fn is_empty(&self) -> bool {
        self.inv_lambda.is_empty()
    }

    /// Reflected colour (linear sRGB, white = 1) of a film with Fresnel terms `fresnel` and
    /// thickness `thickness_nm`. The transmitted colour is `1 − this`.
    #[inline]
    pub fn film_reflectance_rgb(&self, fresnel: &FilmFresnel, thickness_nm: f32) -> [f32; 3] {
        let mut rgb = [0.0f32; 3];
        let mut buf = [0.0f32; MAX_WAVELENGTHS];
        for (il, w) in self
            .inv_lambda
            .chunks(MAX_WAVELENGTHS)
            .zip(self.weight.chunks(MAX_WAVELENGTHS))
        {
            let r = &mut buf[..il.len()];
            fresnel.reflectance_into(thickness_nm, il, r);
            for (ri, wi) in r.iter().zip(w) {
                rgb[0] += ri * wi[0];
                rgb[1] += ri * wi[1];
                rgb[2] += ri * wi[2];
            }
        }
        rgb
    }

    /// Colour (linear sRGB, white = 1) of a reflectance spectrum given at these wavelengths.
    pub fn spectrum_rgb(&self, values: &[f32]) -> [f32; 3] {
        let mut rgb = [0.0f32; 3];
        for (v, w) in values.iter().zip(&self.weight) {
            for c in 0..3 {
                rgb[c] += v * w[c];
            }
        }
        rgb
    }
}

/// Σ over the 1 nm grid of the raw weights, divided by the grid's size: the mean white weight.
fn white_integral_per_nm() -> [f64; 3] {
    static WHITE: std::sync::OnceLock<[f64; 3]> = std::sync::OnceLock::new();
    *WHITE.get_or_init(|| {
        let grid = reference_grid_nm();
        let mut s = [0.0; 3];
        for &l in &grid {
            let w = raw_weight(l);
            for c in 0..3 {
                s[c] += w[c];
            }
        }
        s.map(|v| v / grid.len() as f64)
    })
}
