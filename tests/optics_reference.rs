//! Thin-film optics against independent references: the transfer-matrix solver `tmm` and
//! colours from `colour-science` (tests/data/, copied from shared/reference, see its README).

use filmsplat::optics::{FilmFresnel, film_rt};
use filmsplat::spectrum::{SpectralWeights, film_rgb_reference, reference_grid_nm};

fn csv_rows(name: &str) -> Vec<Vec<f64>> {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn airy_reference_matches_transfer_matrix_solver() {
    let rows = csv_rows("thinfilm_rt.csv");
    assert_eq!(rows.len(), 2624);
    for r in &rows {
        let (ior, h, angle, lambda) = (r[0], r[1], r[2], r[3]);
        let rt = film_rt(angle.to_radians().cos(), h, ior, lambda);
        let got = [rt.r(), rt.t(), rt.rs, rt.rp];
        for (k, (g, want)) in got.iter().zip(&r[4..8]).enumerate() {
            assert!(
                (g - want).abs() < 1e-6,
                "column {k} at ior {ior} h {h} angle {angle} lambda {lambda}: {g} vs {want}"
            );
        }
    }
}

#[test]
fn fast_path_matches_transfer_matrix_solver() {
    // The f32 renderer path: same rows, f32 tolerance.
    let mut worst = 0.0f64;
    for r in csv_rows("thinfilm_rt.csv") {
        let (ior, h, angle, lambda) = (r[0], r[1], r[2], r[3]);
        let f = FilmFresnel::new(angle.to_radians().cos() as f32, ior as f32);
        let got = f.reflectance(h as f32, 1.0 / lambda as f32) as f64;
        worst = worst.max((got - r[4]).abs());
    }
    assert!(worst < 1e-4, "worst |R_fast - R_tmm| = {worst}");
}

#[test]
fn film_colour_matches_colour_science() {
    let grid = reference_grid_nm();
    let grid32: Vec<f32> = grid.iter().map(|&l| l as f32).collect();
    let weights = SpectralWeights::new(&grid32);
    for r in csv_rows("thinfilm_rgb_d65.csv") {
        let (ior, h, angle) = (r[0], r[1], r[2]);
        let cos_i = angle.to_radians().cos();
        let rgb = film_rgb_reference(cos_i, h, ior, &grid);
        let fast =
            weights.film_reflectance_rgb(&FilmFresnel::new(cos_i as f32, ior as f32), h as f32);
        for c in 0..3 {
            assert!(
                (rgb[c] - r[3 + c]).abs() < 2e-3,
                "f64 h {h} angle {angle} c{c}: {rgb:?} vs {:?}",
                &r[3..]
            );
            assert!(
                (fast[c] as f64 - r[3 + c]).abs() < 2e-3,
                "f32 h {h} angle {angle} c{c}: {fast:?} vs {:?}",
                &r[3..]
            );
        }
    }
}
