//! RGB → spectrum: Smits' method (B. Smits, "An RGB-to-spectrum conversion for reflectances",
//! J. Graphics Tools 4(4), 1999). A colour becomes a sum of seven basis spectra (white, cyan,
//! magenta, yellow, red, green, blue), interpolated linearly between Smits' ten published
//! samples over 380–720 nm and held constant outside. A grey input gives a constant spectrum.

use super::sampled::{SPECTRAL_LANES, Spectrum};

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

/// The seven Smits basis spectra at one sample's wavelengths (built once per camera sample).
#[derive(Debug, Clone, Copy)]
pub struct SmitsBasis {
    /// White, cyan, magenta, yellow, red, green, blue.
    basis: [Spectrum; 7],
}

impl SmitsBasis {
    /// The basis at `lambda_nm` (at most [`SPECTRAL_LANES`] used; other lanes are 0).
    pub fn new(lambda_nm: &[f32]) -> Self {
        let mut basis = [Spectrum::splat(0.0); 7];
        for (i, &l) in lambda_nm.iter().take(SPECTRAL_LANES).enumerate() {
            for (k, b) in basis.iter_mut().enumerate() {
                b.0[i] = smits_basis(k, l);
            }
        }
        SmitsBasis { basis }
    }

    /// The spectrum of linear RGB `[r, g, b]`: the smallest channel's amount of white, then the
    /// secondary and primary colours that make up the rest. Cost: ~50 flops a lane.
    #[inline]
    pub fn uplift(&self, [r, g, b]: [f32; 3]) -> Spectrum {
        let [w, cy, ma, ye, re, gr, bl] = self.basis;
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
}
