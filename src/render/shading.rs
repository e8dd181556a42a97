//! How a film crossing is turned into reflected and transmitted RGB weights: the speed/accuracy
//! knob of the renderer.

use crate::optics::FilmFresnel;
use crate::spectrum::film_colour::SpectralWeights;
use crate::spectrum::{FilmLut, SampledWavelengths, WavelengthRange, WavelengthStrategy};
use glam::Vec3;
use std::fmt;
use std::str::FromStr;

/// Shading mode, chosen per render (`--shading`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShadingMode {
    /// A precomputed table of the film's RGB reflectance over (cos θ, thickness), integrated at
    /// 1 nm: fastest (~5 ns a hit), error < 2e-3 up to 85° incidence.
    #[default]
    Lut,
    /// Per-hit integration over the sample's wavelengths (`--wavelengths N`, jittered per camera
    /// sample so thick films converge instead of aliasing), reduced to RGB at the hit.
    Rgb,
    /// Full spectral transport: each camera sample carries its `--wavelengths N` (at most 16,
    /// jittered per sample) through every bounce; RGB inputs become smooth spectra (Smits
    /// 1999) and the pixel gets spectrum → XYZ → linear sRGB. The reference mode.
    Spectral,
}

impl FromStr for ShadingMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "lut" => Ok(Self::Lut),
            "rgb" => Ok(Self::Rgb),
            "spectral" => Ok(Self::Spectral),
            _ => Err(format!(
                "unknown shading mode '{s}' (expected lut, rgb or spectral)"
            )),
        }
    }
}

impl fmt::Display for ShadingMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Lut => "lut",
            Self::Rgb => "rgb",
            Self::Spectral => "spectral",
        })
    }
}

/// The film shader for one render: the film's index and the chosen mode's precomputed state.
#[derive(Debug, Clone)]
pub struct FilmShader {
    ior: f32,
    mode: ShadingMode,
    lut: Option<FilmLut>,
    wavelengths: usize,
    strategy: WavelengthStrategy,
}

/// Per-camera-sample shading state (the sample's wavelengths and colour weights).
#[derive(Debug, Clone, Default)]
pub struct SampleShading {
    weights: SpectralWeights,
    lambda: Vec<f32>,
}

impl SampleShading {
    /// The sample's wavelengths (nm) and their colour weights (empty for `lut`).
    pub fn spectral(&self) -> (&[f32], &[[f32; 3]]) {
        (&self.lambda, self.weights.weights())
    }
}

impl FilmShader {
    /// A shader for film index `ior` in `mode`; `wavelengths` and `strategy` apply to
    /// [`ShadingMode::Rgb`] and [`ShadingMode::Spectral`]. The table is shared per index and built lazily, a block of thicknesses at a time, as lookups reach it.
    pub fn new(
        ior: f32,
        mode: ShadingMode,
        wavelengths: usize,
        strategy: WavelengthStrategy,
    ) -> Self {
        let lut = (mode == ShadingMode::Lut).then(|| FilmLut::new(ior));
        FilmShader {
            ior,
            mode,
            lut,
            wavelengths,
            strategy,
        }
    }

    /// The shading mode.
    pub fn mode(&self) -> ShadingMode {
        self.mode
    }

    /// The film's index of refraction.
    pub fn ior(&self) -> f32 {
        self.ior
    }

    /// Prepares `state` for a new camera sample; `u` supplies one random number per wavelength.
    pub fn begin_sample(&self, state: &mut SampleShading, u: &[f32]) {
        if self.lut.is_none() {
            let wl = SampledWavelengths::sample(
                WavelengthRange::VISIBLE,
                self.wavelengths,
                self.strategy,
                u,
            );
            match self.strategy {
                WavelengthStrategy::Stratified => state.weights.set(wl.as_slice()),
                _ => state.weights.set_unbiased(wl.as_slice()),
            }
            state.lambda.clear();
            state.lambda.extend_from_slice(wl.as_slice());
        }
    }

    /// Number of random numbers [`begin_sample`](Self::begin_sample) uses.
    pub fn randoms_per_sample(&self) -> usize {
        if self.lut.is_some() {
            0
        } else {
            self.wavelengths
        }
    }

    /// Reflected RGB fraction of a film of `thickness_nm` met at `|cos θ|` = `cos_i`; the
    /// transmitted fraction is `1 − this`.
    #[inline]
    pub fn reflectance(&self, state: &SampleShading, cos_i: f32, thickness_nm: f32) -> Vec3 {
        match &self.lut {
            Some(lut) => Vec3::from(lut.reflectance_rgb(cos_i, thickness_nm)),
            None => {
                let f = FilmFresnel::new(cos_i, self.ior);
                Vec3::from(state.weights.film_reflectance_rgb(&f, thickness_nm))
            }
        }
    }
}
