//! [`Spectrum`]: values at one camera sample's wavelengths (pbrt's `SampledSpectrum`), with
//! lane-wise arithmetic, and its reduction to linear sRGB with per-wavelength colour weights.

use std::ops::{Add, AddAssign, Mul, Sub};

/// Most wavelengths a spectral sample carries.
pub const SPECTRAL_LANES: usize = 16;

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

impl Spectrum {
    /// Every lane `v`.
    #[inline]
    pub fn splat(v: f32) -> Self {
        Spectrum([v; SPECTRAL_LANES])
    }

    /// The largest lane (at least 0).
    #[inline]
    pub fn max_value(self) -> f32 {
        self.0.iter().copied().fold(0.0, f32::max)
    }

    /// Linear sRGB `Σᵢ vᵢ · wᵢ` over the first `weights.len()` lanes, with `weights[i]` the colour
    /// weights of wavelength `i` (see [`super::SpectralWeights::weights`]). Cost: 3 flops a lane.
    #[inline]
    pub fn to_rgb(&self, weights: &[[f32; 3]]) -> [f32; 3] {
        let mut rgb = [0.0f32; 3];
        for (v, w) in self.0.iter().zip(weights) {
            for k in 0..3 {
                rgb[k] += v * w[k];
            }
        }
        rgb
    }
}
