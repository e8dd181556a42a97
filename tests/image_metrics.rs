//! Image metrics against independent references: CIEDE2000 and CIELAB from colour-science, PSNR
//! and SSIM from scikit-image (generator: tests/data/metrics_reference.py).

use filmsplat::image::RgbImage;
use filmsplat::image::metrics::{delta_e_stats, delta_e2000, psnr, ssim};

fn csv_rows(name: &str) -> Vec<Vec<f64>> {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn ciede2000_matches_colour_science() {
    let rows = csv_rows("metrics_de2000.csv");
    assert!(rows.len() >= 50);
    for r in rows {
        let d = delta_e2000([r[0], r[1], r[2]], [r[3], r[4], r[5]]);
        assert!((d - r[6]).abs() < 1e-9 * (1.0 + r[6]), "{r:?}: got {d}");
        // Symmetric in its arguments.
        let back = delta_e2000([r[3], r[4], r[5]], [r[0], r[1], r[2]]);
        assert!((d - back).abs() < 1e-9 * (1.0 + d));
    }
}

/// The two formula images of the generator (linear RGB; values above 1 are clipped).
fn formula_image(second: bool) -> RgbImage {
    let (w, h) = (24usize, 20usize);
    let mut data = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let (x, y) = (i as f64, j as f64);
            data.push(std::array::from_fn(|c| {
                let c = c as f64;
                let v = if second {
                    0.5 + 0.45 * (0.31 * x + 0.17 * y + 1.3 * c + 0.25).sin()
                        + 0.08 * (0.9 * x * y / 7.0 + c).cos()
                } else {
                    0.5 + 0.45 * (0.31 * x + 0.17 * y + 1.3 * c).sin()
                };
                (v * v) as f32
            }));
        }
    }
    RgbImage::from_data(w, h, data).unwrap()
}

#[test]
fn psnr_ssim_and_delta_e_match_scikit_image_and_colour_science() {
    let r = &csv_rows("metrics_images.csv")[0];
    let (a, b) = (formula_image(false), formula_image(true));
    let p = psnr(&a, &b).unwrap();
    assert!((p - r[0]).abs() < 1e-4, "PSNR {p} vs {}", r[0]);
    let s = ssim(&a, &b).unwrap();
    assert!((s - r[1]).abs() < 1e-5, "SSIM {s} vs {}", r[1]);
    let d = delta_e_stats(&a, &b).unwrap();
    assert!(
        (d.mean - r[2]).abs() < 1e-3,
        "mean dE {} vs {}",
        d.mean,
        r[2]
    );
    assert!((d.max - r[3]).abs() < 1e-3, "max dE {} vs {}", d.max, r[3]);
    assert!(d.mean <= d.p95 && d.p95 <= d.max);
}
