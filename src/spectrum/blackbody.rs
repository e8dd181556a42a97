//! Black-body (Planck) emission: the spectrum of incandescent and "tungsten"/"daylight" lamps
//! given by a colour temperature.

use super::cie::{self, CMF_MAX_NM, CMF_MIN_NM};
use super::colour::xyz_to_linear_srgb;

/// Planck's law: spectral radiance of a black body at `kelvin`, W·sr⁻¹·m⁻²·nm⁻¹, at
/// `lambda_nm`.
pub fn planck(lambda_nm: f64, kelvin: f64) -> f64 {
    const H: f64 = 6.626_070_15e-34;
    const C: f64 = 2.997_924_58e8;
    const K: f64 = 1.380_649e-23;
    let l = lambda_nm * 1e-9;
    let x = H * C / (l * K * kelvin);
    2.0 * H * C * C / (l.powi(5) * x.exp_m1()) * 1e-9
}

/// A black body's emission scaled to luminance 1 relative to D65 white (the renderer's unit:
/// radiance 1 in every channel has luminance 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blackbody {
    /// Temperature, kelvin.
    pub kelvin: f32,
    /// Factor on [`planck`] that gives luminance 1 in the renderer's units.
    pub scale: f32,
    /// Its colour, linear sRGB, luminance 1.
    pub rgb: [f32; 3],
}

impl Blackbody {
    /// The black body at `kelvin` (> 0), integrated over the 1 nm CIE grid.
    pub fn new(kelvin: f32) -> Self {
        let t = cie::tables();
        let (mut xyz, mut d65_y) = ([0.0f64; 3], 0.0f64);
        let n = (CMF_MAX_NM - CMF_MIN_NM) as usize + 1;
        for i in 0..n {
            let l = CMF_MIN_NM + i as f64;
            let b = planck(l, kelvin as f64);
            let c = t.cmf(l);
            for k in 0..3 {
                xyz[k] += b * c[k];
            }
            d65_y += t.d65(l) * c[1];
        }
        // Luminance relative to D65: Y(B) / Y(D65); scale it to 1.
        let y = xyz[1] / d65_y;
        let rgb = xyz_to_linear_srgb(xyz.map(|v| v / xyz[1]));
        Blackbody {
            kelvin,
            scale: (1.0 / y) as f32,
            rgb: rgb.map(|v| v as f32),
        }
    }

    /// Emission at `lambda_nm` relative to D65 (the spectral renderer's carried unit), at
    /// luminance 1.
    pub fn relative_to_d65(&self, lambda_nm: f32) -> f32 {
        let d = cie::tables().d65(lambda_nm as f64).max(1e-6);
        (self.scale as f64 * planck(lambda_nm as f64, self.kelvin as f64) / d) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planck_peaks_where_wien_says_and_colours_run_warm_to_cool() {
        // Wien: λ_max = 2.897771955e6 nm·K / T.
        let t = 5000.0;
        let peak = (300..1200)
            .max_by(|a, b| planck(*a as f64, t).total_cmp(&planck(*b as f64, t)))
            .unwrap();
        assert!((peak as f64 - 2.897_771_955e6 / t).abs() <= 1.0, "{peak}");
        let warm = Blackbody::new(2700.0).rgb;
        let cool = Blackbody::new(12000.0).rgb;
        assert!(warm[0] > warm[2] && cool[2] > cool[0], "{warm:?} {cool:?}");
        // ~6500 K is close to white.
        let w = Blackbody::new(6504.0).rgb;
        assert!(w.iter().all(|c| (c - 1.0).abs() < 0.1), "{w:?}");
    }
}
