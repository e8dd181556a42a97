//! What a ray carries: an RGB triple (`lut`, `rgb` shading) or a spectrum over the camera
//! sample's wavelengths (`spectral` shading). The integrator is written once, generic over
//! [`Lanes`]; each shading mode supplies its own, so the RGB modes pay nothing for the spectral
//! one.
//!
//! Spectral mode turns RGB inputs (environment, light colours, prop albedos) into smooth
//! spectra with Smits' method (B. Smits, "An RGB-to-spectrum conversion for reflectances",
//! J. Graphics Tools 4(4), 1999): a sum of seven basis spectra (white, cyan, magenta, yellow,
//! red, green, blue), interpolated linearly between Smits' ten published samples over
//! 380–720 nm and held constant outside. Spectra are carried relative to the D65 illuminant
//! (a value of 1 at every wavelength is D65 white), so the pixel's colour is the same
//! D65-weighted sum the `rgb` mode uses at a film hit, and a grey input stays exactly grey.

use super::lights::AreaLight;
use super::shading::{FilmShader, SampleShading};
use crate::optics::FilmFresnel;
use glam::Vec3;
use std::ops::{Add, AddAssign, Mul, Sub};

/// Most wavelengths a spectral sample carries.
pub const SPECTRAL_LANES: usize = 16;

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

/// Values at the sample's wavelengths (lanes past the sample's count stay unused).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spectrum(pub [f32; SPECTRAL_LANES]);

macro_rules! lanewise {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for Spectrum {
            type Output = Spectrum;
            #[inline]
            fn $f(self, o: Spectrum) -> Spectrum {
                Spectrum(std::array::from_fn(|i| self.0[i] $op o.0[i]))
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);

impl Mul<f32> for Spectrum {
    type Output = Spectrum;
    #[inline]
    fn mul(self, k: f32) -> Spectrum {
        Spectrum(self.0.map(|v| v * k))
    }
}

impl AddAssign for Spectrum {
    #[inline]
    fn add_assign(&mut self, o: Spectrum) {
        *self = *self + o;
    }
}

impl Radiance for Spectrum {
    #[inline]
    fn splat(v: f32) -> Self {
        Spectrum([v; SPECTRAL_LANES])
    }
    #[inline]
    fn max_channel(self) -> f32 {
        self.0.iter().copied().fold(0.0, f32::max)
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
    /// What `light` emits from its front, as carried.
    #[inline]
    fn emission(&self, light: &AreaLight) -> Self::C {
        self.input(light.radiance)
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

/// Smits' sample wavelengths: ten points from 380 to 720 nm.
const SMITS_MIN_NM: f32 = 380.0;
const SMITS_STEP_NM: f32 = 340.0 / 9.0;
/// Smits (1999), table 1: white, cyan, magenta, yellow, red, green, blue.
const SMITS: [[f32; 10]; 7] = [
    [
        1.0000, 1.0000, 0.9999, 0.9993, 0.9992, 0.9998, 1.0000, 1.0000, 1.0000, 1.0000,
    ],
    [
        0.9710, 0.9426, 1.0007, 1.0007, 1.0007, 1.0007, 0.1564, 0.0000, 0.0000, 0.0000,
    ],
    [
        1.0000, 1.0000, 0.9685, 0.2229, 0.0000, 0.0458, 0.8369, 1.0000, 1.0000, 0.9959,
    ],
    [
        0.0001, 0.0000, 0.1088, 0.6651, 1.0000, 1.0000, 0.9996, 0.9586, 0.9685, 0.9840,
    ],
    [
        0.1012, 0.0515, 0.0000, 0.0000, 0.0000, 0.0000, 0.8325, 1.0149, 1.0149, 1.0149,
    ],
    [
        0.0000, 0.0000, 0.0273, 0.7937, 1.0000, 0.9418, 0.1719, 0.0000, 0.0000, 0.0025,
    ],
    [
        1.0000, 1.0000, 0.8916, 0.3323, 0.0000, 0.0000, 0.0003, 0.0369, 0.0483, 0.0496,
    ],
];

/// Smits basis spectrum `k` at `lambda_nm` (linear between samples, constant outside).
fn smits_basis(k: usize, lambda_nm: f32) -> f32 {
    let x = ((lambda_nm - SMITS_MIN_NM) / SMITS_STEP_NM).clamp(0.0, 9.0);
    let i = (x as usize).min(8);
    let f = x - i as f32;
    SMITS[k][i] + f * (SMITS[k][i + 1] - SMITS[k][i])
}

/// Spectral transport over one sample's wavelengths.
#[derive(Debug, Clone)]
pub struct SpectralLanes {
    ior: f32,
    n: usize,
    lambda: [f32; SPECTRAL_LANES],
    inv_lambda: [f32; SPECTRAL_LANES],
    /// Smits basis at each lane: white, cyan, magenta, yellow, red, green, blue.
    basis: [Spectrum; 7],
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
        let mut basis = [Spectrum::splat(0.0); 7];
        for i in 0..n {
            inv_lambda[i] = 1.0 / lambda[i];
            lam[i] = lambda[i];
            weight[i] = weights[i];
            for (k, b) in basis.iter_mut().enumerate() {
                b.0[i] = smits_basis(k, lambda[i]);
            }
        }
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

    /// Smits' construction: the smallest channel's amount of white, then the secondary and
    /// primary colours that make up the rest.
    #[inline]
    fn input(&self, c: Vec3) -> Spectrum {
        let [w, cy, ma, ye, re, gr, bl] = self.basis;
        let (r, g, b) = (c.x, c.y, c.z);
        if r <= g && r <= b {
            let s = w * r;
            if g <= b {
                s + cy * (g - r) + bl * (b - g)
            } else {
                s + cy * (b - r) + gr * (g - b)
            }
        } else if g <= r && g <= b {
            let s = w * g;
            if r <= b {
                s + ma * (r - g) + bl * (b - r)
            } else {
                s + ma * (b - g) + re * (r - b)
            }
        } else {
            let s = w * b;
            if r <= g {
                s + ye * (r - b) + gr * (g - r)
            } else {
                s + ye * (g - b) + re * (r - g)
            }
        }
    }

    /// A black-body light emits its Planck spectrum; others their radiance's Smits spectrum.
    #[inline]
    fn emission(&self, light: &AreaLight) -> Spectrum {
        match &light.blackbody {
            Some(b) => Spectrum(std::array::from_fn(|i| {
                if i < self.n {
                    b.relative_to_d65(self.lambda[i])
                } else {
                    0.0
                }
            })),
            None => self.input(light.radiance),
        }
    }

    #[inline]
    fn to_rgb(&self, c: Spectrum) -> Vec3 {
        let mut rgb = Vec3::ZERO;
        for i in 0..self.n {
            rgb += c.0[i] * Vec3::from(self.weight[i]);
        }
        rgb
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
