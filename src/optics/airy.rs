//! Reference thin-film reflectance: complex Fresnel amplitudes and the Airy sum, in f64.

use std::f64::consts::PI;
use std::ops::{Add, Div, Mul, Sub};

/// A minimal complex number (only what the Airy sum needs).
#[derive(Debug, Clone, Copy, PartialEq)]
struct C64 {
    re: f64,
    im: f64,
}

impl C64 {
    fn real(re: f64) -> Self {
        C64 { re, im: 0.0 }
    }
    fn cis(phase: f64) -> Self {
        let (s, c) = phase.sin_cos();
        C64 { re: c, im: s }
    }
    fn norm_sqr(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
}

impl Add for C64 {
    type Output = C64;
    fn add(self, o: C64) -> C64 {
        C64 {
            re: self.re + o.re,
            im: self.im + o.im,
        }
    }
}
impl Sub for C64 {
    type Output = C64;
    fn sub(self, o: C64) -> C64 {
        C64 {
            re: self.re - o.re,
            im: self.im - o.im,
        }
    }
}
impl Mul for C64 {
    type Output = C64;
    fn mul(self, o: C64) -> C64 {
        C64 {
            re: self.re * o.re - self.im * o.im,
            im: self.re * o.im + self.im * o.re,
        }
    }
}
impl Div for C64 {
    type Output = C64;
    fn div(self, o: C64) -> C64 {
        let d = o.norm_sqr();
        C64 {
            re: (self.re * o.re + self.im * o.im) / d,
            im: (self.im * o.re - self.re * o.im) / d,
        }
    }
}

/// Reflectance and transmittance (intensities) of a film for s and p polarisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmRT {
    /// Reflectance for s (TE) polarisation.
    pub rs: f64,
    /// Reflectance for p (TM) polarisation.
    pub rp: f64,
    /// Transmittance for s polarisation.
    pub ts: f64,
    /// Transmittance for p polarisation.
    pub tp: f64,
}

impl FilmRT {
    /// Unpolarised reflectance: the mean of the s and p intensities.
    pub fn r(&self) -> f64 {
        0.5 * (self.rs + self.rp)
    }
    /// Unpolarised transmittance: the mean of the s and p intensities.
    pub fn t(&self) -> f64 {
        0.5 * (self.ts + self.tp)
    }
}

/// Reflectance and transmittance of a lossless film (air | index `ior` | air).
///
/// * `cos_i`: cosine of the angle of incidence in air, in [0, 1] (pass `|cos|` for back-face
///   hits: the film is symmetric). Values outside are clamped.
/// * `thickness_nm`: film thickness in nanometres, >= 0.
/// * `ior`: the film's index of refraction (>= 1; see [`super::check_film_params`]).
/// * `lambda_nm`: vacuum wavelength in nanometres, > 0.
///
/// Method (Born & Wolf §7.6; Heavens 1955): Snell gives `cos θt`; Fresnel amplitude coefficients
/// `r01, t01` (air→film) and `r10, t10` (film→air) for s and p; the phase of one round trip is
/// `φ = 4π n h cos θt / λ`; the Airy sum of all internal reflections gives
/// `r = r01 + t01 t10 r10 e^{iφ} / (1 − r10² e^{iφ})` and
/// `t = t01 t10 e^{iφ/2} / (1 − r10² e^{iφ})`; R = |r|², T = |t|² (same medium on both sides).
///
/// Limits: `thickness_nm == 0` is no film (R = 0, T = 1, at every angle); `cos_i == 0` is
/// grazing incidence (R = 1, T = 0, except at an exact transmission resonance where R = 0).
/// Cost: about 60 ns (two `sin_cos`, complex divisions).
///
/// # Example
/// A lossless film conserves energy, and a quarter-wave film at normal incidence reflects the
/// textbook maximum ((n² − 1)/(n² + 1))² (Hecht, *Optics*, §9.7):
/// ```
/// use filmsplat::optics::film_rt;
/// let (n, h) = (1.33, 100.0); // water film, nm
/// let quarter_wave = 4.0 * n * h; // 532 nm
/// let rt = film_rt(1.0, h, n, quarter_wave);
/// let peak = ((n * n - 1.0) / (n * n + 1.0)).powi(2);
/// assert!((rt.r() - peak).abs() < 1e-9, "R = {}", rt.r());
/// for cos_i in [1.0, 0.7, 0.2] {
///     let rt = film_rt(cos_i, 730.0, n, 480.0);
///     assert!((rt.r() + rt.t() - 1.0).abs() < 1e-12);
/// }
/// // A half-wave film is invisible: R = 0.
/// assert!(film_rt(1.0, h, n, 2.0 * n * h).r() < 1e-12);
/// ```
pub fn film_rt(cos_i: f64, thickness_nm: f64, ior: f64, lambda_nm: f64) -> FilmRT {
    let (n0, n1) = (1.0, ior);
    let c0 = cos_i.clamp(0.0, 1.0);
    if thickness_nm == 0.0 {
        return FilmRT {
            rs: 0.0,
            rp: 0.0,
            ts: 1.0,
            tp: 1.0,
        };
    }
    // Snell: n0 sin θi = n1 sin θt.
    let sin_t = n0 * (1.0 - c0 * c0).max(0.0).sqrt() / n1;
    let c1 = (1.0 - sin_t * sin_t).max(0.0).sqrt();
    let phase = 4.0 * PI * n1 * thickness_nm * c1 / lambda_nm;
    if c0 == 0.0 {
        // Grazing: t01 = 0, so r = r01 = -1, unless 1 − e^{iφ} = 0 (a resonance, 0/0) where the
        // limit along cos θi → 0 is R = 0.
        let resonant = (0.5 * phase).sin() == 0.0;
        let (r, t) = if resonant { (0.0, 1.0) } else { (1.0, 0.0) };
        return FilmRT {
            rs: r,
            rp: r,
            ts: t,
            tp: t,
        };
    }
    let e = C64::cis(phase);
    let e_half = C64::cis(0.5 * phase);
    // 1 − e^{iφ} = 2 sin²(φ/2) − i sin φ, exactly, without cancellation for small φ.
    let s_half = (0.5 * phase).sin();
    let one_minus_e = C64 {
        re: 2.0 * s_half * s_half,
        im: -phase.sin(),
    };
    let airy = |r01: f64, t01: f64, r10: f64, t10: f64| -> (f64, f64) {
        // 1 − r10² e^{iφ}, written as (1 − r10²) + r10² (1 − e^{iφ}) with 1 − r10² = t01 t10
        // (Stokes relations), which stays accurate when r10² → 1 (grazing) and φ → 0.
        let denom = C64::real(t01 * t10) + C64::real(r10 * r10) * one_minus_e;
        let r = C64::real(r01) + C64::real(t01 * t10 * r10) * e / denom;
        let t = C64::real(t01 * t10) * e_half / denom;
        (r.norm_sqr(), t.norm_sqr())
    };
    // s polarisation (E perpendicular to the plane of incidence).
    let (a, b) = (n0 * c0, n1 * c1);
    let (rs, ts) = airy(
        (a - b) / (a + b),
        2.0 * a / (a + b),
        (b - a) / (a + b),
        2.0 * b / (a + b),
    );
    // p polarisation (E in the plane of incidence).
    let (a, b) = (n1 * c0, n0 * c1);
    let (rp, tp) = airy(
        (a - b) / (a + b),
        2.0 * n0 * c0 / (a + b),
        (b - a) / (a + b),
        2.0 * n1 * c1 / (a + b),
    );
    FilmRT { rs, rp, ts, tp }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_interface_limit_matches_fresnel_at_normal_incidence() {
        // Averaged over phase, a film reflects the incoherent sum 2ρ/(1+ρ), ρ = ((n-1)/(n+1))².
        let n: f64 = 1.5;
        let rho = ((n - 1.0) / (n + 1.0)).powi(2);
        // One full period of the fringes in thickness: λ / (2n).
        let samples = 20_000;
        let period = 500.0 / (2.0 * n);
        let mean: f64 = (0..samples)
            .map(|i| {
                film_rt(
                    1.0,
                    1000.0 + (i as f64 + 0.5) * period / samples as f64,
                    n,
                    500.0,
                )
                .r()
            })
            .sum::<f64>()
            / samples as f64;
        assert!((mean - 2.0 * rho / (1.0 + rho)).abs() < 1e-9, "{mean}");
    }

    #[test]
    fn quarter_wave_film_is_maximally_reflective() {
        // At normal incidence R peaks where n h = λ/4: R = 4ρ/(1+ρ)².
        let (n, lambda): (f64, f64) = (1.33, 550.0);
        let rho: f64 = ((n - 1.0) / (n + 1.0)).powi(2);
        let r = film_rt(1.0, lambda / (4.0 * n), n, lambda).r();
        assert!((r - 4.0 * rho / (1.0 + rho).powi(2)).abs() < 1e-12, "{r}");
    }
}
