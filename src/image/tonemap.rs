//! Exposure, tone mapping and sRGB encoding of linear images to 8-bit.

use std::fmt;
use std::str::FromStr;
use std::sync::OnceLock;

use rayon::prelude::*;

use super::buffer::RgbImage;
use crate::{Error, Result};

/// How scene-linear values (after exposure) are compressed into the displayable range `[0, 1]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneMap {
    /// Clip each channel to `[0, 1]`: exact, for charts and for images already in range.
    #[default]
    Clamp,
    /// Per-channel filmic curve: the ACES fitted curve of K. Narkowicz, "ACES Filmic Tone
    /// Mapping Curve" (2016), `f(y) = y(2.51y + 0.03) / (y(2.43y + 0.59) + 0.14)`, applied to
    /// `y = k x` with `k = 0.72317` chosen so that linear mid-grey 0.18 maps to 0.18 (sRGB 118),
    /// i.e. mid-tones look as under [`Clamp`](ToneMap::Clamp). Shadows get a gentle toe, mid-tone
    /// contrast is ~1.3 and highlights roll off smoothly, reaching white at linear ~10 (5.8 stops
    /// above mid-grey).
    Filmic,
}

impl ToneMap {
    /// Maps one exposed linear value to `[0, 1]`. NaN and infinities map to 0.
    #[inline]
    pub fn apply(self, x: f32) -> f32 {
        if !x.is_finite() {
            return 0.0;
        }
        match self {
            ToneMap::Clamp => x.clamp(0.0, 1.0),
            ToneMap::Filmic => aces_narkowicz(ACES_MID_GREY_SCALE * x.max(0.0)),
        }
    }
}

/// Pre-scale making [`ToneMap::Filmic`] map 0.18 to 0.18: the positive root `y` of
/// `f(y) = 0.18` divided by 0.18.
const ACES_MID_GREY_SCALE: f32 = 0.723_170_8;

/// Narkowicz's ACES fit, clamped to `[0, 1]`. Input must be `>= 0`.
#[inline]
fn aces_narkowicz(y: f32) -> f32 {
    if y >= 8.0 {
        return 1.0; // the curve passes 1 at y = 7.24; avoids inf/inf for huge inputs
    }
    let v = (y * (2.51 * y + 0.03)) / (y * (2.43 * y + 0.59) + 0.14);
    v.clamp(0.0, 1.0)
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ToneMap::Clamp => "clamp",
            ToneMap::Filmic => "filmic",
        })
    }
}

impl FromStr for ToneMap {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "clamp" => Ok(ToneMap::Clamp),
            "filmic" => Ok(ToneMap::Filmic),
            _ => Err(Error::invalid(format!(
                "unknown tone map '{s}' (expected 'clamp' or 'filmic')"
            ))),
        }
    }
}

/// sRGB transfer function (IEC 61966-2-1), linear `[0, 1]` to encoded `[0, 1]`.
///
/// Extended to all reals so it can be inverted exactly by [`srgb_to_linear`]: values above 1
/// follow the same power segment, negative values mirror. NaN stays NaN.
#[inline]
pub fn linear_to_srgb(x: f32) -> f32 {
    let a = x.abs();
    let e = if a <= 0.003_130_8 {
        12.92 * a
    } else {
        1.055 * a.powf(1.0 / 2.4) - 0.055
    };
    e.copysign(x)
}

/// Inverse of [`linear_to_srgb`] (IEC 61966-2-1 decoding, extended the same way).
#[inline]
pub fn srgb_to_linear(e: f32) -> f32 {
    let a = e.abs();
    let x = if a <= 0.040_45 {
        a / 12.92
    } else {
        ((a + 0.055) / 1.055).powf(2.4)
    };
    x.copysign(e)
}

/// Encodes a display-referred value in `[0, 1]` (clamped) to an 8-bit sRGB code, rounding to
/// nearest (`round(255 * linear_to_srgb(x))`). NaN maps to 0.
///
/// Uses a binary search in a table of the 255 decision thresholds (8 comparisons, no `powf`).
#[inline]
pub fn encode_srgb8(x: f32) -> u8 {
    if x.is_nan() {
        return 0;
    }
    srgb8_thresholds().partition_point(|&t| t <= x) as u8
}

/// `thresholds[k]` is the linear value where the 8-bit code changes from `k` to `k + 1`.
fn srgb8_thresholds() -> &'static [f32; 255] {
    static T: OnceLock<[f32; 255]> = OnceLock::new();
    T.get_or_init(|| {
        std::array::from_fn(|k| {
            // Decode in f64 so the threshold is the correctly rounded midpoint.
            let e = (k as f64 + 0.5) / 255.0;
            (if e <= 0.040_45 {
                e / 12.92
            } else {
                ((e + 0.055) / 1.055).powf(2.4)
            }) as f32
        })
    })
}

/// Exposes, tone maps and sRGB-encodes a linear image to packed RGB8 (`3 * width * height`
/// bytes, row-major, top row first).
///
/// Each channel is multiplied by `2^exposure_ev`, passed through `tone`, then encoded with the
/// IEC 61966-2-1 piecewise curve. Non-finite input values (NaN, +-Inf) become 0. Rows are
/// processed in parallel (rayon); cost a few tens of ns per pixel per core (table-based sRGB
/// encoding, no `powf`; `Filmic` adds a division per channel).
pub fn to_srgb8(img: &RgbImage, exposure_ev: f32, tone: ToneMap) -> Vec<u8> {
    let gain = exposure_ev.exp2();
    let mut out = vec![0u8; img.data.len() * 3];
    let encode_row = |(dst, src): (&mut [u8], &[[f32; 3]])| {
        for (d, &c) in dst.iter_mut().zip(src.iter().flatten()) {
            let v = if c.is_finite() {
                tone.apply(c * gain)
            } else {
                0.0
            };
            *d = encode_srgb8(v);
        }
    };
    let w = img.width.max(1);
    out.par_chunks_mut(3 * w)
        .zip(img.data.par_chunks(w))
        .for_each(encode_row);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_known_points() {
        assert_eq!(encode_srgb8(0.0), 0);
        assert_eq!(encode_srgb8(1.0), 255);
        // 0.5 linear -> 0.7354 encoded -> 188; 0.18 -> 0.4614 -> 118 (mid-grey card)
        assert!((linear_to_srgb(0.5) - 0.735_357).abs() < 1e-5);
        assert_eq!(encode_srgb8(0.5), 188);
        assert_eq!(encode_srgb8(0.18), 118);
        // The breakpoint: 0.0031308 -> 0.04045 from both pieces (continuity).
        let lo = 12.92 * 0.003_130_8_f32;
        let hi = 1.055 * 0.003_130_8_f32.powf(1.0 / 2.4) - 0.055;
        assert!((lo - 0.040_45).abs() < 1e-5 && (hi - 0.040_45).abs() < 1e-5);
        // Linear segment: 0.001 -> 0.01292.
        assert!((linear_to_srgb(0.001) - 0.012_92).abs() < 1e-7);
        // 8-bit code 128 decodes to 0.21586 linear.
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_861).abs() < 1e-5);
    }

    #[test]
    fn table_encoder_matches_the_formula() {
        for i in 0..=200_000 {
            let x = i as f32 / 200_000.0;
            let exact = (x as f64).max(0.0);
            let e = if exact <= 0.003_130_8 {
                12.92 * exact
            } else {
                1.055 * exact.powf(1.0 / 2.4) - 0.055
            } * 255.0;
            if (e - e.floor() - 0.5).abs() > 1e-4 {
                assert_eq!(encode_srgb8(x), e.round() as u8, "x = {x}");
            }
        }
        assert_eq!(encode_srgb8(-1.0), 0);
        assert_eq!(encode_srgb8(7.0), 255);
    }

    #[test]
    fn srgb_round_trip_all_codes() {
        for code in 0..=255u8 {
            let lin = srgb_to_linear(code as f32 / 255.0);
            assert_eq!(encode_srgb8(lin), code);
        }
        for &x in &[-2.0f32, -0.5, 1.5, 10.0] {
            assert!((srgb_to_linear(linear_to_srgb(x)) - x).abs() < 1e-4 * x.abs());
        }
    }

    #[test]
    fn tone_maps_zero_to_zero_and_are_monotonic() {
        for tone in [ToneMap::Clamp, ToneMap::Filmic] {
            assert_eq!(tone.apply(0.0), 0.0);
            assert_eq!(tone.apply(-1.0), 0.0);
            let mut prev = 0.0;
            for i in 1..=4000 {
                let x = i as f32 * 0.005; // up to 20
                let y = tone.apply(x);
                assert!(y >= prev, "{tone} not monotonic at {x}: {y} < {prev}");
                assert!(y <= 1.0);
                prev = y;
            }
            assert_eq!(tone.apply(1e30), 1.0);
        }
    }

    #[test]
    fn filmic_mid_grey_and_rolloff() {
        let f = |x| ToneMap::Filmic.apply(x);
        assert!((f(0.18) - 0.18).abs() < 1e-4, "{}", f(0.18));
        // Highlights compress: 1.0 stays below white, white is reached near 10.
        assert!(f(1.0) > 0.6 && f(1.0) < 0.9, "{}", f(1.0));
        assert!(f(5.0) < 1.0 && f(5.0) > 0.95);
        assert_eq!(f(10.1), 1.0);
        // Slope decreases through the highlights (smooth shoulder).
        let slope = |x: f32| (f(x * 1.01) - f(x)) / (0.01 * x);
        assert!(slope(0.5) > slope(1.0) && slope(1.0) > slope(2.0) && slope(2.0) > slope(4.0));
        // Mid-tone contrast in log-log around mid-grey is filmic (> 1), not extreme.
        let gamma = (f(0.18 * 1.1).ln() - f(0.18).ln()) / 1.1f32.ln();
        assert!(gamma > 1.1 && gamma < 1.6, "{gamma}");
    }

    #[test]
    fn clamp_mode_is_exact() {
        let img = RgbImage::from_data(
            3,
            1,
            vec![
                [0.0, 0.18, 0.5],
                [1.0, 2.0, -1.0],
                [f32::NAN, f32::INFINITY, f32::NEG_INFINITY],
            ],
        )
        .unwrap();
        let out = to_srgb8(&img, 0.0, ToneMap::Clamp);
        assert_eq!(out, vec![0, 118, 188, 255, 255, 0, 0, 0, 0]);
        // Exposure: +1 EV doubles (0.09 -> 0.18 -> 118, 0.6 -> 1.2 -> 255), -1 EV halves
        // (0.36 -> 0.18).
        let img = RgbImage::from_data(1, 1, vec![[0.09, 0.36, 0.6]]).unwrap();
        assert_eq!(
            to_srgb8(&img, 1.0, ToneMap::Clamp),
            [118, encode_srgb8(0.72), 255]
        );
        assert_eq!(to_srgb8(&img, -1.0, ToneMap::Clamp)[1], 118);
        // Every value exactly matches the formula.
        let vals: Vec<[f32; 3]> = (0..100).map(|i| [i as f32 / 99.0; 3]).collect();
        let img = RgbImage::from_data(100, 1, vals).unwrap();
        let out = to_srgb8(&img, 0.0, ToneMap::Clamp);
        for i in 0..100 {
            let x = i as f32 / 99.0;
            let e = if x <= 0.003_130_8 {
                12.92 * x
            } else {
                1.055 * x.powf(1.0 / 2.4) - 0.055
            };
            assert_eq!(out[3 * i], (e * 255.0).round() as u8);
        }
    }

    #[test]
    fn filmic_non_finite_is_zero() {
        let img = RgbImage::from_data(1, 1, vec![[f32::NAN, f32::INFINITY, 0.18]]).unwrap();
        assert_eq!(to_srgb8(&img, 0.0, ToneMap::Filmic), vec![0, 0, 118]);
    }

    #[test]
    fn parse_and_display() {
        for t in [ToneMap::Clamp, ToneMap::Filmic] {
            assert_eq!(t.to_string().parse::<ToneMap>().unwrap(), t);
        }
        assert_eq!("Filmic".parse::<ToneMap>().unwrap(), ToneMap::Filmic);
        assert!("aces".parse::<ToneMap>().is_err());
    }
}
