//! What a ray carries: an RGB triple (`lut`, `rgb` shading) or a spectrum over the camera
//! sample's wavelengths (`spectral` shading). The integrator is written once, generic over
//! [`Lanes`]; each shading mode supplies its own, so the RGB modes pay nothing for the spectral
//! one.
//!
//! Spectral mode turns RGB inputs (environment, light colours, prop albedos) into smooth
//! spectra with Smits' method ([`crate::spectrum::smits`]) and carries a
//! [`Spectrum`] over the sample's wavelengths. Spectra are carried relative to the D65 illuminant
//! (a value of 1 at every wavelength is D65 white), so the pixel's colour is the same
//! D65-weighted sum the `rgb` mode uses at a film hit, and a grey input stays exactly grey.

use super::shading::{FilmShader, SampleShading};
use crate::optics::FilmFresnel;
use crate::spectrum::{Blackbody, SmitsBasis};
pub use crate::spectrum::{SPECTRAL_LANES, Spectrum};
use glam::Vec3;
use std::ops::{Add, Mul, Sub};

/// Radiance or a weight: RGB or spectral.
pub trait Radiance:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Mul<f32, Output = Self>
{
    /// Every channel `v`.
    fn splat(v: f32) -> Self;
    /// Largest channel.
    fn max_channel(self) -> f32;
}

impl Radiance for Vec3 {
    #[inline]
    fn splat(v: f32) -> Self {
        Vec3::splat(v)
    }
    #[inline]
    fn max_channel(self) -> f32 {
        self.max_element()
    }
}

impl Radiance for Spectrum {
    #[inline]
    fn splat(v: f32) -> Self {
        Spectrum::splat(v)
    }
    #[inline]
    fn max_channel(self) -> f32 {
        self.max_value()
    }
}

/// How one camera sample turns film optics and RGB inputs into what rays carry.
pub trait Lanes {
    /// The carried type.
    type C: Radiance;
    /// Film reflectance at `|cos θ|` = `cos_i` for a film `thickness_nm` thick.
    fn film_reflectance(&self, cos_i: f32, thickness_nm: f32) -> Self::C;
    /// An RGB input (radiance or reflectance) as carried.
    fn input(&self, rgb: Vec3) -> Self::C;
    /// An emitter's RGB `radiance` as carried; `blackbody`, if given, is its spectrum (with
    /// that colour), which spectral lanes carry instead.
    #[inline]
    fn emission(&self, radiance: Vec3, blackbody: Option<&Blackbody>) -> Self::C {
        let _ = blackbody;
        self.input(radiance)
    }
    /// Carried radiance to linear sRGB.
    fn to_rgb(&self, c: Self::C) -> Vec3;
}

/// RGB transport: the film shader's RGB reflectance, inputs as they are.
pub struct RgbLanes<'a> {
    /// The shader.
    pub shader: &'a FilmShader,
    /// The sample's shading state.
    pub state: &'a SampleShading,
}

impl Lanes for RgbLanes<'_> {
    type C = Vec3;
    #[inline]
    fn film_reflectance(&self, cos_i: f32, thickness_nm: f32) -> Vec3 {
        self.shader.reflectance(self.state, cos_i, thickness_nm)
    }
    #[inline]
    fn input(&self, rgb: Vec3) -> Vec3 {
        rgb
    }
    #[inline]
    fn to_rgb(&self, c: Vec3) -> Vec3 {
        c
    }
}

/// Spectral transport over one sample's wavelengths.
#[derive(Debug, Clone)]
pub struct SpectralLanes {
    ior: f32,
    n: usize,
    lambda: [f32; SPECTRAL_LANES],
    inv_lambda: [f32; SPECTRAL_LANES],
    /// Smits basis at each lane.
    basis: SmitsBasis,
    /// Per-lane colour weights (D65 · sRGB matching functions, normalised).
    weight: [[f32; 3]; SPECTRAL_LANES],
}

impl SpectralLanes {
    /// Lanes for the wavelengths of `state` (at most [`SPECTRAL_LANES`] are used), film index
    /// `ior`.
    pub fn new(state: &SampleShading, ior: f32) -> Self {
        let (lambda, weights) = state.spectral();
        let n = lambda.len().min(SPECTRAL_LANES);
        let mut inv_lambda = [0.0; SPECTRAL_LANES];
        let mut lam = [0.0; SPECTRAL_LANES];
        let mut weight = [[0.0; 3]; SPECTRAL_LANES];
        for i in 0..n {
            inv_lambda[i] = 1.0 / lambda[i];
            lam[i] = lambda[i];
            weight[i] = weights[i];
        }
        let basis = SmitsBasis::new(&lam[..n]);
        SpectralLanes {
            ior,
            n,
            lambda: lam,
            inv_lambda,
            basis,
            weight,
        }
    }
}

impl Lanes for SpectralLanes {
    type C = Spectrum;
    #[inline]
    fn film_reflectance(&self, cos_i: f32, thickness_nm: f32) -> Spectrum {
        let mut out = [0.0; SPECTRAL_LANES];
        FilmFresnel::new(cos_i, self.ior).reflectance_into(
            thickness_nm,
            &self.inv_lambda[..self.n],
            &mut out[..self.n],
        );
        Spectrum(out)
    }

    /// Smits' construction ([`SmitsBasis::uplift`]).
    #[inline]
    fn input(&self, c: Vec3) -> Spectrum {
        self.basis.uplift(c.to_array())
    }

    /// A black-body light emits its Planck spectrum; others their radiance's Smits spectrum.
    #[inline]
    fn emission(&self, radiance: Vec3, blackbody: Option<&Blackbody>) -> Spectrum {
        match blackbody {
            Some(b) => Spectrum(std::array::from_fn(|i| {
                if i < self.n {
                    b.relative_to_d65(self.lambda[i])
                } else {
                    0.0
                }
            })),
            None => self.input(radiance),
        }
    }

    #[inline]
    fn to_rgb(&self, c: Spectrum) -> Vec3 {
        Vec3::from(c.to_rgb(&self.weight[..self.n]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::ShadingMode;
    use crate::render::sampler::Pcg32;
    use crate::spectrum::WavelengthStrategy;

    /// Averaged over jittered wavelengths, RGB → spectrum → RGB returns grey exactly and
    /// saturated colours approximately (Smits' basis is a fit, not an inverse).
    #[test]
    fn smits_round_trip() {
        let shader = FilmShader::new(
            1.33,
            ShadingMode::Spectral,
            16,
            WavelengthStrategy::Jittered,
        );
        let mut state = SampleShading::default();
        let mut rng = Pcg32::new(1, 2);
        for (rgb, tol) in [
            (Vec3::splat(0.5), 0.01),
            (Vec3::new(0.8, 0.3, 0.1), 0.06),
            (Vec3::new(0.1, 0.6, 0.2), 0.06),
            (Vec3::new(0.2, 0.3, 0.9), 0.06),
        ] {
            let mut sum = Vec3::ZERO;
            let n = 4000;
            for _ in 0..n {
                let u: Vec<f32> = (0..16).map(|_| rng.next_f32()).collect();
                shader.begin_sample(&mut state, &u);
                let lanes = SpectralLanes::new(&state, 1.33);
                sum += lanes.to_rgb(lanes.input(rgb));
            }
            let mean = sum / n as f32;
            assert!((mean - rgb).abs().max_element() < tol, "{rgb} → {mean}");
        }
    }
}
