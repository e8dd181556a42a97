//! Image comparison metrics: PSNR, SSIM and the CIEDE2000 colour difference.
//!
//! All three compare images *as displayed*: each linear-RGB channel is clipped to `[0, 1]`
//! (apply exposure and tone mapping first if the images are scene-referred). PSNR and SSIM work
//! on the sRGB-encoded values, as image-quality literature does; CIEDE2000 converts linear sRGB
//! (D65) to CIELAB. Costs are O(pixels); SSIM is a separable 11-tap filter (~60 flops a pixel).

use super::buffer::RgbImage;
use super::tonemap::linear_to_srgb;
use crate::{Error, Result};

/// Linear sRGB (D65) to CIE 1931 XYZ (IEC 61966-2-1).
const XYZ_FROM_SRGB: [[f64; 3]; 3] = [
    [0.412_456_4, 0.357_576_1, 0.180_437_5],
    [0.212_672_9, 0.715_152_2, 0.072_175_0],
    [0.019_333_9, 0.119_192_0, 0.950_304_1],
];

/// The D65 white point in XYZ (Y = 1), the reference white of the CIELAB conversion.
pub const WHITE_D65: [f64; 3] = [0.950_47, 1.0, 1.088_83];

/// CIELAB `[L*, a*, b*]` of a linear sRGB colour (D65 white; channels clipped to `[0, 1]`).
pub fn linear_srgb_to_lab(rgb: [f32; 3]) -> [f64; 3] {
    let c = rgb.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 } as f64);
    let xyz: [f64; 3] =
        std::array::from_fn(|i| (0..3).map(|j| XYZ_FROM_SRGB[i][j] * c[j]).sum::<f64>());
    xyz_to_lab(xyz, WHITE_D65)
}

/// CIELAB `[L*, a*, b*]` of an XYZ colour relative to the white `white` (CIE 15:2004).
pub fn xyz_to_lab(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    const D: f64 = 6.0 / 29.0;
    let f = |t: f64| {
        if t > D * D * D {
            t.cbrt()
        } else {
            t / (3.0 * D * D) + 4.0 / 29.0
        }
    };
    let [fx, fy, fz] = std::array::from_fn(|i| f(xyz[i] / white[i]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// The CIEDE2000 colour difference ΔE₀₀ between two CIELAB colours, with the parametric factors
/// k_L = k_C = k_H = 1. Implements G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000
/// color-difference formula: implementation notes, supplementary test data, and mathematical
/// observations", Color Res. Appl. 30 (2005), equations (1)–(19). ΔE₀₀ ≈ 1 is about one just
/// noticeable difference.
pub fn delta_e2000(lab1: [f64; 3], lab2: [f64; 3]) -> f64 {
    const POW25_7: f64 = 6_103_515_625.0; // 25⁷
    let [l1, a1, b1] = lab1;
    let [l2, a2, b2] = lab2;
    // (2)–(7): a′, C′ and h′ (degrees in [0, 360), 0 for a neutral colour).
    let c_mean = 0.5 * (a1.hypot(b1) + a2.hypot(b2));
    let c7 = c_mean.powi(7);
    let g = 0.5 * (1.0 - (c7 / (c7 + POW25_7)).sqrt());
    let (a1p, a2p) = ((1.0 + g) * a1, (1.0 + g) * a2);
    let (c1p, c2p) = (a1p.hypot(b1), a2p.hypot(b2));
    let hue = |b: f64, a: f64| {
        if a == 0.0 && b == 0.0 {
            0.0
        } else {
            b.atan2(a).to_degrees().rem_euclid(360.0)
        }
    };
    let (h1p, h2p) = (hue(b1, a1p), hue(b2, a2p));
    // (8)–(10): differences ΔL′, ΔC′, ΔH′.
    let dl = l2 - l1;
    let dc = c2p - c1p;
    let chroma_zero = c1p * c2p == 0.0;
    let dh_deg = if chroma_zero {
        0.0
    } else {
        let d = h2p - h1p;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let dh = 2.0 * (c1p * c2p).sqrt() * (0.5 * dh_deg).to_radians().sin();
    // (12)–(22): means, weighting functions and the rotation term.
    let l_mean = 0.5 * (l1 + l2);
    let c_mean_p = 0.5 * (c1p + c2p);
    let h_mean = if chroma_zero {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        0.5 * (h1p + h2p)
    } else if h1p + h2p < 360.0 {
        0.5 * (h1p + h2p + 360.0)
    } else {
        0.5 * (h1p + h2p - 360.0)
    };
    let cosd = |deg: f64| deg.to_radians().cos();
    let t = 1.0 - 0.17 * cosd(h_mean - 30.0)
        + 0.24 * cosd(2.0 * h_mean)
        + 0.32 * cosd(3.0 * h_mean + 6.0)
        - 0.20 * cosd(4.0 * h_mean - 63.0);
    let d_theta = 30.0 * (-((h_mean - 275.0) / 25.0).powi(2)).exp();
    let c7p = c_mean_p.powi(7);
    let r_c = 2.0 * (c7p / (c7p + POW25_7)).sqrt();
    let l50 = (l_mean - 50.0).powi(2);
    let s_l = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let s_c = 1.0 + 0.045 * c_mean_p;
    let s_h = 1.0 + 0.015 * c_mean_p * t;
    let r_t = -(2.0 * d_theta).to_radians().sin() * r_c;
    let (tl, tc, th) = (dl / s_l, dc / s_c, dh / s_h);
    (tl * tl + tc * tc + th * th + r_t * tc * th)
        .max(0.0)
        .sqrt()
}

/// Summary of a per-pixel colour difference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeltaEStats {
    /// Mean ΔE₀₀ over all pixels.
    pub mean: f64,
    /// 95th percentile (nearest rank).
    pub p95: f64,
    /// Largest ΔE₀₀.
    pub max: f64,
}

fn check_same_size(a: &RgbImage, b: &RgbImage) -> Result<()> {
    if a.width != b.width || a.height != b.height {
        return Err(Error::invalid(format!(
            "cannot compare a {}x{} image with a {}x{} image",
            a.width, a.height, b.width, b.height
        )));
    }
    if a.data.is_empty() {
        return Err(Error::invalid("cannot compare empty images"));
    }
    Ok(())
}

/// The per-pixel CIEDE2000 difference of two images (linear sRGB, clipped to `[0, 1]`), row-major.
pub fn delta_e_map(a: &RgbImage, b: &RgbImage) -> Result<Vec<f32>> {
    check_same_size(a, b)?;
    Ok(a.data
        .iter()
        .zip(&b.data)
        .map(|(p, q)| delta_e2000(linear_srgb_to_lab(*p), linear_srgb_to_lab(*q)) as f32)
        .collect())
}

/// Mean, 95th percentile and maximum of [`delta_e_map`].
pub fn delta_e_stats(a: &RgbImage, b: &RgbImage) -> Result<DeltaEStats> {
    let mut d = delta_e_map(a, b)?;
    let mean = d.iter().map(|&v| v as f64).sum::<f64>() / d.len() as f64;
    d.sort_unstable_by(f32::total_cmp);
    // Nearest rank: the smallest value with at least 95% of the pixels at or below it.
    let rank = ((0.95 * d.len() as f64).ceil() as usize).clamp(1, d.len());
    Ok(DeltaEStats {
        mean,
        p95: d[rank - 1] as f64,
        max: *d.last().expect("non-empty") as f64,
    })
}

/// sRGB-encoded display values in `[0, 1]`, three per pixel.
fn encoded(img: &RgbImage) -> impl Iterator<Item = f64> + '_ {
    img.data.iter().flat_map(|p| {
        p.map(|v| {
            linear_to_srgb(if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }) as f64
        })
    })
}

/// Peak signal-to-noise ratio in dB between the sRGB-encoded images (peak 1, all three
/// channels): `10 log10(1 / MSE)`. Identical images give `f64::INFINITY`.
pub fn psnr(a: &RgbImage, b: &RgbImage) -> Result<f64> {
    check_same_size(a, b)?;
    let n = 3 * a.data.len();
    let mse = encoded(a)
        .zip(encoded(b))
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        / n as f64;
    Ok(if mse == 0.0 {
        f64::INFINITY
    } else {
        -10.0 * mse.log10()
    })
}

/// Rec. 709 luma of the sRGB-encoded image, one value per pixel.
fn luma(img: &RgbImage) -> Vec<f64> {
    let e: Vec<f64> = encoded(img).collect();
    e.chunks_exact(3)
        .map(|c| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2])
        .collect()
}

/// Half-width of the SSIM window: 11 taps of a Gaussian with σ = 1.5.
const SSIM_RADIUS: usize = 5;
const SSIM_SIGMA: f64 = 1.5;

/// Separable Gaussian filter with edge clamping.
fn gaussian_blur(v: &[f64], w: usize, h: usize, kernel: &[f64]) -> Vec<f64> {
    let r = SSIM_RADIUS as isize;
    let pass = |src: &[f64], step_x: bool| -> Vec<f64> {
        let mut out = vec![0.0; src.len()];
        for y in 0..h {
            for x in 0..w {
                let mut s = 0.0;
                for (k, wk) in kernel.iter().enumerate() {
                    let o = k as isize - r;
                    let (sx, sy) = if step_x {
                        ((x as isize + o).clamp(0, w as isize - 1) as usize, y)
                    } else {
                        (x, (y as isize + o).clamp(0, h as isize - 1) as usize)
                    };
                    s += wk * src[sy * w + sx];
                }
                out[y * w + x] = s;
            }
        }
        out
    };
    pass(&pass(v, true), false)
}

/// Mean structural similarity (Wang, Bovik, Sheikh, Simoncelli 2004) of the images' luma:
/// Gaussian window σ = 1.5 (11 taps), `C1 = (0.01)²`, `C2 = (0.03)²` for the range 1, averaged
/// over the pixels whose window lies inside the image (all pixels if the image is smaller than
/// the window). Matches scikit-image's `structural_similarity(gaussian_weights=True,
/// use_sample_covariance=False, data_range=1)`. Identical images give 1.
pub fn ssim(a: &RgbImage, b: &RgbImage) -> Result<f64> {
    check_same_size(a, b)?;
    let (w, h) = (a.width, a.height);
    let kernel: Vec<f64> = {
        let k: Vec<f64> = (0..=2 * SSIM_RADIUS)
            .map(|i| {
                let x = i as f64 - SSIM_RADIUS as f64;
                (-x * x / (2.0 * SSIM_SIGMA * SSIM_SIGMA)).exp()
            })
            .collect();
        let s: f64 = k.iter().sum();
        k.into_iter().map(|v| v / s).collect()
    };
    let (x, y) = (luma(a), luma(b));
    let prod = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(u, v)| u * v).collect::<Vec<f64>>();
    let blur = |v: &[f64]| gaussian_blur(v, w, h, &kernel);
    let (mx, my) = (blur(&x), blur(&y));
    let (sxx, syy, sxy) = (
        blur(&prod(&x, &x)),
        blur(&prod(&y, &y)),
        blur(&prod(&x, &y)),
    );
    const C1: f64 = 1e-4;
    const C2: f64 = 9e-4;
    let inside = |n: usize| {
        if n > 2 * SSIM_RADIUS {
            SSIM_RADIUS..n - SSIM_RADIUS
        } else {
            0..n
        }
    };
    let (mut sum, mut count) = (0.0, 0usize);
    for j in inside(h) {
        for i in inside(w) {
            let k = j * w + i;
            let (ux, uy) = (mx[k], my[k]);
            let vx = sxx[k] - ux * ux;
            let vy = syy[k] - uy * uy;
            let cxy = sxy[k] - ux * uy;
            sum += ((2.0 * ux * uy + C1) * (2.0 * cxy + C2))
                / ((ux * ux + uy * uy + C1) * (vx + vy + C2));
            count += 1;
        }
    }
    Ok(sum / count as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(w: usize, h: usize, v: f32) -> RgbImage {
        RgbImage::filled(w, h, [v; 3])
    }

    #[test]
    fn identical_images_are_perfect() {
        let a = RgbImage::from_data(4, 3, (0..12).map(|i| [i as f32 / 12.0, 0.3, 0.9]).collect())
            .unwrap();
        assert_eq!(psnr(&a, &a).unwrap(), f64::INFINITY);
        assert!((ssim(&a, &a).unwrap() - 1.0).abs() < 1e-12);
        let s = delta_e_stats(&a, &a).unwrap();
        assert_eq!((s.mean, s.p95, s.max), (0.0, 0.0, 0.0));
    }

    #[test]
    fn a_known_shift_gives_the_known_psnr() {
        // Encoded values 0.5 and 0.6 everywhere: MSE = 0.01, PSNR = 20 dB.
        let a = grey(8, 8, srgb_lin(0.5));
        let b = grey(8, 8, srgb_lin(0.6));
        assert!((psnr(&a, &b).unwrap() - 20.0).abs() < 1e-4);
    }

    fn srgb_lin(e: f32) -> f32 {
        super::super::tonemap::srgb_to_linear(e)
    }

    #[test]
    fn white_and_black_have_the_textbook_lab() {
        let w = linear_srgb_to_lab([1.0; 3]);
        assert!((w[0] - 100.0).abs() < 1e-3 && w[1].abs() < 1e-2 && w[2].abs() < 1e-2);
        assert_eq!(linear_srgb_to_lab([0.0; 3]), [0.0, 0.0, 0.0]);
        // Neutral greys differ only in L*, where CIEDE2000 reduces to ΔL/S_L.
        let d = delta_e2000([50.0, 0.0, 0.0], [60.0, 0.0, 0.0]);
        let l50 = 25.0;
        assert!((d - 10.0 / (1.0 + 0.015 * l50 / (20.0f64 + l50).sqrt())).abs() < 1e-12);
    }

    #[test]
    fn mismatched_sizes_are_an_error() {
        assert!(psnr(&grey(2, 2, 0.5), &grey(3, 2, 0.5)).is_err());
        assert!(ssim(&grey(2, 2, 0.5), &grey(2, 3, 0.5)).is_err());
        assert!(delta_e_stats(&grey(1, 1, 0.5), &grey(2, 1, 0.5)).is_err());
    }
}
