//! Colour grading of a linear image before the tone curve: white balance, contrast and
//! saturation (exposure is the tone stage's own `exposure_ev`). Applied in this order, each on
//! linear RGB; the identity settings change nothing, bit for bit.

use super::buffer::RgbImage;
use crate::{Error, Result};

/// Linear mid-grey, the pivot of the contrast control.
const MID_GREY: f32 = 0.18;

/// Grading settings. [`Grade::default`] is the identity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grade {
    /// Per-channel gains (white balance), applied first.
    pub gains: [f32; 3],
    /// Contrast: 1 = unchanged; each channel becomes `0.18 · (x / 0.18)^contrast`.
    pub contrast: f32,
    /// Saturation: 1 = unchanged, 0 = grey of the same luminance.
    pub saturation: f32,
}

impl Default for Grade {
    fn default() -> Self {
        Grade {
            gains: [1.0; 3],
            contrast: 1.0,
            saturation: 1.0,
        }
    }
}

/// Rec. 709 / sRGB luminance weights.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Chromaticity (x, y) of a Planckian (black-body) radiator at `kelvin` (1667–25000 K),
/// by the cubic-spline fit of Kim et al. (2002), US patent 7024034.
fn planck_xy(kelvin: f32) -> (f32, f32) {
    let t = kelvin.clamp(1667.0, 25000.0) as f64;
    let (t1, t2, t3) = (1e3 / t, 1e6 / (t * t), 1e9 / (t * t * t));
    let x = if t <= 4000.0 {
        -0.266_123_9 * t3 - 0.234_358_9 * t2 + 0.877_695_6 * t1 + 0.179_910
    } else {
        -3.025_846_9 * t3 + 2.107_037_9 * t2 + 0.222_634_7 * t1 + 0.240_390
    };
    let (x2, x3) = (x * x, x * x * x);
    let y = if t <= 2222.0 {
        -1.106_381_4 * x3 - 1.348_110_20 * x2 + 2.185_558_32 * x - 0.202_196_83
    } else if t <= 4000.0 {
        -0.954_947_6 * x3 - 1.374_185_93 * x2 + 2.091_370_15 * x - 0.167_488_80
    } else {
        3.081_758_0 * x3 - 5.873_386_70 * x2 + 3.751_129_97 * x - 0.370_014_83
    };
    (x as f32, y as f32)
}

/// Linear sRGB of the chromaticity (x, y) at luminance 1.
fn xy_to_rgb(x: f32, y: f32) -> [f32; 3] {
    let (cx, cz) = (x / y, (1.0 - x - y) / y);
    [
        3.240_454_2 * cx - 1.537_138_5 - 0.498_531_4 * cz,
        -0.969_266 * cx + 1.876_010_8 + 0.041_556 * cz,
        0.055_643_4 * cx - 0.204_025_9 + 1.057_225_2 * cz,
    ]
}

impl Grade {
    /// White-balance gains that neutralise light of colour temperature `kelvin`
    /// (1667–25000 K): a black body of that temperature becomes as neutral as one of
    /// 6504 K (which these gains leave alone). Luminance of white is kept.
    pub fn white_balance_gains(kelvin: f32) -> Result<[f32; 3]> {
        if !(1667.0..=25000.0).contains(&kelvin) {
            return Err(Error::invalid(format!(
                "white balance must be 1667..25000 K, got {kelvin}"
            )));
        }
        let (x, y) = planck_xy(kelvin);
        let (x0, y0) = planck_xy(6504.0);
        let (c, c0) = (xy_to_rgb(x, y), xy_to_rgb(x0, y0));
        let g = [0, 1, 2].map(|i| c0[i] / c[i].max(1e-6));
        // Keep the luminance of white light: gains·c has the luminance of c.
        let k = luminance(c) / luminance([0, 1, 2].map(|i| g[i] * c[i])).max(1e-6);
        Ok(g.map(|v| v * k))
    }

    /// Checks the settings: gains ≥ 0, contrast > 0, saturation ≥ 0, all finite.
    pub fn validate(&self) -> Result<()> {
        let ok = self.gains.iter().all(|g| g.is_finite() && *g >= 0.0)
            && self.contrast.is_finite()
            && self.contrast > 0.0
            && self.saturation.is_finite()
            && self.saturation >= 0.0;
        if ok {
            Ok(())
        } else {
            Err(Error::invalid(format!(
                "grading needs gains >= 0, contrast > 0 and saturation >= 0, got {self:?}"
            )))
        }
    }

    /// True if the settings leave every image unchanged.
    pub fn is_identity(&self) -> bool {
        *self == Grade::default()
    }

    /// Grades one pixel (linear RGB).
    #[inline]
    pub fn pixel(&self, c: [f32; 3]) -> [f32; 3] {
        let mut c = [0, 1, 2].map(|i| c[i] * self.gains[i]);
        if self.contrast != 1.0 {
            c = c.map(|v| {
                if v > 0.0 {
                    MID_GREY * (v / MID_GREY).powf(self.contrast)
                } else {
                    v
                }
            });
        }
        if self.saturation != 1.0 {
            let l = luminance(c);
            c = c.map(|v| l + self.saturation * (v - l));
        }
        c
    }

    /// The graded image.
    pub fn apply(&self, img: &RgbImage) -> RgbImage {
        if self.is_identity() {
            return img.clone();
        }
        RgbImage {
            width: img.width,
            height: img.height,
            data: img.data.iter().map(|c| self.pixel(*c)).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_changes_nothing_and_controls_do_what_they_say() {
        let data: Vec<[f32; 3]> = (0..50)
            .map(|i| {
                let t = i as f32 * 0.37;
                [t.sin().abs() * 3.0, (t * 1.3).cos().abs(), 0.01 * i as f32]
            })
            .collect();
        let img = RgbImage::from_data(10, 5, data).unwrap();
        assert_eq!(Grade::default().apply(&img), img);
        let g = Grade {
            gains: Grade::white_balance_gains(6504.0).unwrap(),
            ..Grade::default()
        };
        for (a, b) in g.apply(&img).data.iter().zip(&img.data) {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() <= 1e-4 * b[k].max(1.0));
            }
        }
        // Neutralising a warm light: its black body becomes grey, luminance kept.
        let gains = Grade::white_balance_gains(3200.0).unwrap();
        let (x, y) = planck_xy(3200.0);
        let warm = xy_to_rgb(x, y);
        let (x0, y0) = planck_xy(6504.0);
        let neutral = xy_to_rgb(x0, y0);
        let out = [0, 1, 2].map(|i| warm[i] * gains[i] / neutral[i]);
        assert!(
            (out[0] - out[2]).abs() < 1e-3 && (out[1] - out[2]).abs() < 1e-3,
            "{out:?}"
        );
        assert!(gains[2] > gains[0], "warm light: boost blue");
        // Contrast pivots on mid-grey; saturation 0 gives grey of the same luminance.
        let c = Grade {
            contrast: 1.5,
            saturation: 0.0,
            ..Grade::default()
        };
        let p = c.pixel([0.18; 3]);
        assert!((p[0] - 0.18).abs() < 1e-6);
        let q = c.pixel([0.5, 0.2, 0.1]);
        assert!((q[0] - q[1]).abs() < 1e-6 && (q[1] - q[2]).abs() < 1e-6);
        assert!(
            Grade {
                contrast: 0.0,
                ..Grade::default()
            }
            .validate()
            .is_err()
        );
    }
}
