//! Colour spaces: CIE XYZ → linear sRGB (D65 white, IEC 61966-2-1) and the sRGB transfer curve.

/// XYZ → linear sRGB matrix (IEC 61966-2-1, D65 white point, no chromatic adaptation).
pub const XYZ_TO_LINEAR_SRGB: [[f64; 3]; 3] = [
    [3.240_454_2, -1.537_138_5, -0.498_531_4],
    [-0.969_266_0, 1.876_010_8, 0.041_556_0],
    [0.055_643_4, -0.204_025_9, 1.057_225_2],
];

/// Converts CIE XYZ to linear sRGB.
///
/// # Example
/// The D65 white point (the sRGB white) maps to linear (1, 1, 1); encoded, 18 % grey is the
/// familiar 46 % (118 of 255):
/// ```
/// use filmsplat::spectrum::{linear_to_srgb, srgb_to_linear, xyz_to_linear_srgb};
/// let white = xyz_to_linear_srgb([0.950_47, 1.0, 1.088_83]);
/// assert!(white.iter().all(|c| (c - 1.0).abs() < 1e-3), "{white:?}");
/// let grey = linear_to_srgb(0.18);
/// assert_eq!((grey * 255.0).round(), 118.0);
/// assert!((srgb_to_linear(grey) - 0.18).abs() < 1e-6);
/// ```
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> [f64; 3] {
    let m = &XYZ_TO_LINEAR_SRGB;
    [0, 1, 2].map(|r| m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2])
}

/// sRGB encoding (the piecewise gamma curve) of a linear value; input clamped to [0, 1].
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB decoding of an encoded value in [0, 1] to linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_round_trips_and_hits_known_points() {
        for i in 0..=100 {
            let v = i as f32 / 100.0;
            assert!((srgb_to_linear(linear_to_srgb(v)) - v).abs() < 1e-5);
        }
        // Middle grey 18% encodes to ~0.4613 (118/255).
        assert!((linear_to_srgb(0.18) - 0.4613).abs() < 1e-3);
    }

    #[test]
    fn d65_white_maps_to_equal_rgb() {
        // D65 white point XYZ (Y = 1): x = 0.3127, y = 0.3290.
        let (x, y) = (0.3127, 0.3290);
        let rgb = xyz_to_linear_srgb([x / y, 1.0, (1.0 - x - y) / y]);
        for c in rgb {
            assert!((c - 1.0).abs() < 1e-3, "{rgb:?}");
        }
    }
}
