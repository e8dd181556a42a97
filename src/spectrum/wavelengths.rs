//! Choosing the wavelengths a sample carries (pbrt-v4's `SampledWavelengths`, in small).
//!
//! Every strategy spreads `n` wavelengths over a range with equal density, so the estimate of a
//! spectral integral is `range/n · Σ f(λᵢ)` and the colour of a sample is a weighted sum. They
//! differ in how the wavelengths move from one sample to the next:
//!
//! * [`Stratified`](WavelengthStrategy::Stratified): fixed midpoints of `n` equal strata. No noise,
//!   but fixed: spectral detail finer than a stratum aliases (false colour on thick films).
//! * [`Jittered`](WavelengthStrategy::Jittered): one independent random point in each stratum per
//!   sample. Converges to the true integral as samples accumulate; a little noise.
//! * [`Hero`](WavelengthStrategy::Hero): one random hero wavelength and `n − 1` companions at even
//!   spacing, wrapped around the range (Wilkie et al. 2014). Converges; correlated strata.

use std::fmt;
use std::str::FromStr;

/// Largest number of wavelengths one sample can carry.
pub const MAX_WAVELENGTHS: usize = 64;

/// A wavelength interval, in nanometres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WavelengthRange {
    /// Shortest wavelength, nm.
    pub min_nm: f32,
    /// Longest wavelength, nm.
    pub max_nm: f32,
}

impl WavelengthRange {
    /// The visible range covered by the CIE 1931 tables, 360–830 nm.
    pub const VISIBLE: WavelengthRange = WavelengthRange {
        min_nm: 360.0,
        max_nm: 830.0,
    };

    /// Width of the range, nm.
    pub fn width(&self) -> f32 {
        self.max_nm - self.min_nm
    }
}

/// How wavelengths are chosen per sample; see the module docs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WavelengthStrategy {
    /// Fixed stratum midpoints.
    Stratified,
    /// A random point in each stratum, per sample.
    #[default]
    Jittered,
    /// Hero wavelength with evenly spaced, wrapped companions.
    Hero,
}

impl FromStr for WavelengthStrategy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "stratified" => Ok(Self::Stratified),
            "jittered" => Ok(Self::Jittered),
            "hero" => Ok(Self::Hero),
            _ => Err(format!(
                "unknown wavelength strategy '{s}' (expected stratified, jittered or hero)"
            )),
        }
    }
}

impl fmt::Display for WavelengthStrategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Stratified => "stratified",
            Self::Jittered => "jittered",
            Self::Hero => "hero",
        })
    }
}

/// The wavelengths one sample carries (at most [`MAX_WAVELENGTHS`]), all with density
/// `1 / range.width()`.
#[derive(Debug, Clone, Copy)]
pub struct SampledWavelengths {
    len: usize,
    lambda: [f32; MAX_WAVELENGTHS],
}

impl SampledWavelengths {
    /// Chooses `n` wavelengths (1..=[`MAX_WAVELENGTHS`], clamped) in `range` with `strategy`.
    /// `u` supplies the randomness: one value in [0, 1) per wavelength (Jittered uses `u[i]`,
    /// Hero uses `u[0]`, Stratified none); missing values count as 0.5.
    pub fn sample(
        range: WavelengthRange,
        n: usize,
        strategy: WavelengthStrategy,
        u: &[f32],
    ) -> Self {
        let n = n.clamp(1, MAX_WAVELENGTHS);
        let step = range.width() / n as f32;
        let get = |i: usize| u.get(i).copied().unwrap_or(0.5);
        let mut lambda = [0.0; MAX_WAVELENGTHS];
        for (i, l) in lambda.iter_mut().take(n).enumerate() {
            let offset = match strategy {
                WavelengthStrategy::Stratified => i as f32 + 0.5,
                WavelengthStrategy::Jittered => i as f32 + get(i),
                WavelengthStrategy::Hero => {
                    let o = get(0) * n as f32 + i as f32;
                    if o >= n as f32 { o - n as f32 } else { o }
                }
            };
            *l = (range.min_nm + offset * step).min(range.max_nm);
        }
        SampledWavelengths { len: n, lambda }
    }

    /// Explicit wavelengths (e.g. a 1 nm grid); at most [`MAX_WAVELENGTHS`] are kept.
    pub fn from_slice(lambda_nm: &[f32]) -> Self {
        let len = lambda_nm.len().min(MAX_WAVELENGTHS);
        let mut lambda = [0.0; MAX_WAVELENGTHS];
        lambda[..len].copy_from_slice(&lambda_nm[..len]);
        SampledWavelengths { len, lambda }
    }

    /// The wavelengths, nm.
    pub fn as_slice(&self) -> &[f32] {
        &self.lambda[..self.len]
    }

    /// Number of wavelengths.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always false (a sample carries at least one wavelength); for API symmetry.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_strategy_puts_one_wavelength_in_each_stratum() {
        let r = WavelengthRange::VISIBLE;
        let u: Vec<f32> = (0..16).map(|i| (i as f32 * 0.618_034).fract()).collect();
        for s in [
            WavelengthStrategy::Stratified,
            WavelengthStrategy::Jittered,
            WavelengthStrategy::Hero,
        ] {
            let wl = SampledWavelengths::sample(r, 16, s, &u);
            let mut strata: Vec<usize> = wl
                .as_slice()
                .iter()
                .map(|&l| ((l - r.min_nm) / r.width() * 16.0) as usize)
                .collect();
            strata.sort();
            assert_eq!(strata, (0..16).collect::<Vec<_>>(), "{s}");
        }
    }
}
