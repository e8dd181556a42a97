//! Invariants and extremes of the thin-film optics (no reference data needed).

use filmsplat::optics::{FilmFresnel, check_film_params, film_rt};
use filmsplat::spectrum::{
    FilmLut, SampledWavelengths, SpectralWeights, WavelengthRange, WavelengthStrategy,
};

/// A small deterministic generator so the sweeps cover many values without a rand crate.
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn energy_is_conserved_everywhere() {
    let mut s = 7;
    for _ in 0..200_000 {
        let cos_i = lcg(&mut s);
        let h = 10f64.powf(lcg(&mut s) * 11.0 - 6.0); // 1e-6 .. 1e5 nm
        let ior = 1.0 + 2.0 * lcg(&mut s);
        let lambda = 360.0 + 470.0 * lcg(&mut s);
        let rt = film_rt(cos_i, h, ior, lambda);
        for (r, t) in [(rt.rs, rt.ts), (rt.rp, rt.tp), (rt.r(), rt.t())] {
            assert!(r.is_finite() && t.is_finite());
            assert!(
                (r + t - 1.0).abs() < 1e-12,
                "R+T-1 = {} at cos {cos_i} h {h} n {ior} l {lambda}",
                r + t - 1.0
            );
            assert!((0.0..=1.0 + 1e-12).contains(&r));
        }
    }
}

#[test]
fn vanishing_film_reflects_nothing() {
    for cos_i in [0.0, 1e-9, 0.3, 1.0] {
        let rt = film_rt(cos_i, 0.0, 1.33, 500.0);
        assert_eq!((rt.r(), rt.t()), (0.0, 1.0));
        assert_eq!(
            FilmFresnel::new(cos_i as f32, 1.33).reflectance(0.0, 1.0 / 500.0),
            0.0
        );
    }
    // And continuously so: R ~ h² as h → 0.
    let r1 = film_rt(1.0, 1e-3, 1.33, 500.0).r();
    let r2 = film_rt(1.0, 2e-3, 1.33, 500.0).r();
    assert!(
        r1 > 0.0 && r1 < 1e-9 && (r2 / r1 - 4.0).abs() < 1e-3,
        "{r1} {r2}"
    );
    assert!(film_rt(1.0, 1e-6, 1.33, 500.0).r().is_finite());
}

#[test]
fn index_one_film_is_invisible() {
    for h in [1.0, 250.0, 5000.0] {
        for cos_i in [0.05, 0.5, 1.0] {
            assert!(film_rt(cos_i, h, 1.0, 550.0).r() < 1e-15);
            assert!(FilmFresnel::new(cos_i as f32, 1.0).reflectance(h as f32, 1.0 / 550.0) < 1e-6);
        }
    }
}

#[test]
fn grazing_incidence_reflects_everything_without_nan() {
    for h in [50.0, 333.3, 10_000.0, 100_000.0] {
        let at_zero = film_rt(0.0, h, 1.33, 500.0);
        assert_eq!(at_zero.r(), 1.0);
        // Approaching grazing: R climbs toward 1 (away from resonances, sampled over λ).
        let mean = |cos_i: f64| {
            (0..100)
                .map(|k| film_rt(cos_i, h, 1.33, 400.0 + 3.0 * k as f64).r())
                .sum::<f64>()
                / 100.0
        };
        assert!(
            mean(1e-4) > 0.99 && mean(1e-4) > mean(0.1),
            "{h}: {}",
            mean(1e-4)
        );
        let fast = FilmFresnel::new(1e-6, 1.33);
        let r = fast.reflectance(h as f32, 1.0 / 500.0);
        assert!(r.is_finite() && r > 0.99, "{r}");
    }
}

/// Reflectance of the stack `n_in | film (ior, h nm) | n_out` for unpolarised light arriving
/// from `n_in` at `cos_in`, by the characteristic-matrix method (Born & Wolf §1.6.2): with
/// tilted admittances η = n cos θ (s) and n / cos θ (p) and the layer phase δ = 2π n h cos θ / λ,
/// r = (η₀B − C)/(η₀B + C), [B, C] = M [1, η₂]. No Airy sum, no shared code with `film_rt`.
fn matrix_reflectance(cos_in: f64, n_in: f64, ior: f64, n_out: f64, h: f64, lambda: f64) -> f64 {
    let invariant = (1.0 - cos_in * cos_in) * n_in * n_in; // (n sin θ)², the same in every layer
    let cos_at = |n: f64| (1.0 - invariant / (n * n)).sqrt();
    let (c0, c1, c2) = (cos_in, cos_at(ior), cos_at(n_out));
    let delta = 2.0 * std::f64::consts::PI * ior * h * c1 / lambda;
    let (cd, sd) = (delta.cos(), delta.sin());
    let r = |e0: f64, e1: f64, e2: f64| {
        let (num_re, num_im) = ((e0 - e2) * cd, (e0 * e2 / e1 - e1) * sd);
        let (den_re, den_im) = ((e0 + e2) * cd, (e0 * e2 / e1 + e1) * sd);
        (num_re * num_re + num_im * num_im) / (den_re * den_re + den_im * den_im)
    };
    let s = r(n_in * c0, ior * c1, n_out * c2);
    let p = r(n_in / c0, ior / c1, n_out / c2);
    0.5 * (s + p)
}

#[test]
fn back_face_hits_see_the_same_film() {
    // A ray meeting the film from its back has d · n = −cos θ; the renderer passes |d · n| to
    // the optics (the contract: negative cosines are clamped to grazing). That is right only
    // because air | film | air reads the same from both sides: check the front-face answer
    // against the matrix method for light arriving from the front air, and the answer for the
    // negative cosine (through |cos|) against the matrix method for the reversed stack.
    let (ior, lambda) = (1.33, 480.0);
    let (front_air, back_air) = (1.0, 1.0);
    for h in [0.0, 120.0, 777.0] {
        for cos_i in [1.0, 0.6, 0.01] {
            let signed: f64 = -cos_i;
            let back = film_rt(signed.abs(), h, ior, lambda).r();
            let want_back = matrix_reflectance(cos_i, back_air, ior, front_air, h, lambda);
            assert!(
                (back - want_back).abs() < 1e-9,
                "h {h} cos {signed}: {back} vs matrix method {want_back}"
            );
            let front = film_rt(cos_i, h, ior, lambda).r();
            let want_front = matrix_reflectance(cos_i, front_air, ior, back_air, h, lambda);
            assert!((front - want_front).abs() < 1e-9, "h {h} cos {cos_i}");
            // Negative cosines are clamped to 0 by contract: callers pass |cos|.
            assert_eq!(
                film_rt(signed, h, ior, lambda).r(),
                film_rt(0.0, h, ior, lambda).r()
            );
        }
    }
}

#[test]
fn extreme_thicknesses_stay_finite_and_bounded() {
    for h in [1e-6, 1e-3, 1e5, 1e6] {
        for cos_i in [0.0, 0.5, 1.0] {
            let rt = film_rt(cos_i, h, 1.33, 550.0);
            assert!(rt.r().is_finite() && (0.0..=1.0).contains(&rt.r()));
            let f = FilmFresnel::new(cos_i as f32, 1.33).reflectance(h as f32, 1.0 / 550.0);
            assert!(f.is_finite() && (0.0..=1.0).contains(&f));
        }
    }
}

#[test]
fn fast_path_agrees_with_reference_over_a_wide_sweep() {
    let mut s = 11;
    let mut worst = 0.0f64;
    for _ in 0..100_000 {
        // Away from grazing: at cos θ → 0 the Airy resonances become narrower than the f32 phase
        // resolution; there only the spectrally integrated colour is guaranteed (next test).
        let cos_i = 0.05 + 0.95 * lcg(&mut s);
        let h = 5000.0 * lcg(&mut s);
        let ior = 1.0 + 2.0 * lcg(&mut s);
        let lambda = 360.0 + 470.0 * lcg(&mut s);
        let exact = film_rt(cos_i, h, ior, lambda).r();
        let fast = FilmFresnel::new(cos_i as f32, ior as f32)
            .reflectance(h as f32, 1.0 / lambda as f32) as f64;
        worst = worst.max((exact - fast).abs());
    }
    assert!(worst < 2e-4, "worst {worst}");
}

#[test]
fn bad_parameters_are_rejected_before_the_kernels() {
    assert!(check_film_params(1.33, -1.0).is_err());
    assert!(check_film_params(1.33, f64::NAN).is_err());
    assert!(check_film_params(1.33, f64::INFINITY).is_err());
    assert!(check_film_params(0.9, 100.0).is_err());
    assert!(check_film_params(f64::NAN, 100.0).is_err());
    assert!(check_film_params(1.33, 2e6).is_err());
    assert!(check_film_params(1.0, 0.0).is_ok());
    assert!(check_film_params(3.0, 1e5).is_ok());
}

#[test]
fn lut_matches_per_hit_integration() {
    let lut = FilmLut::new(1.33);
    let grid: Vec<f32> = (360..=830).map(|l| l as f32).collect();
    let w = SpectralWeights::new(&grid);
    let mut s = 3;
    let mut worst = 0.0f32;
    for _ in 0..2000 {
        // Up to 85°: beyond it the film's colour changes faster with angle than any table
        // resolves (checked separately below with a looser bound).
        let cos_i = 0.087 + 0.913 * lcg(&mut s) as f32;
        let h = 5000.0 * lcg(&mut s) as f32;
        let exact = w.film_reflectance_rgb(&FilmFresnel::new(cos_i, 1.33), h);
        let got = lut.reflectance_rgb(cos_i, h);
        for c in 0..3 {
            worst = worst.max((exact[c] - got[c]).abs());
        }
    }
    assert!(worst < 2e-3, "worst LUT error {worst}");
    // Grazing, 85°–90°, and nanometre films there: still within 0.02.
    let mut worst = 0.0f32;
    for _ in 0..2000 {
        let cos_i = 0.087 * lcg(&mut s) as f32;
        let h = 5000.0 * (lcg(&mut s) as f32).powi(3);
        let exact = w.film_reflectance_rgb(&FilmFresnel::new(cos_i, 1.33), h);
        let got = lut.reflectance_rgb(cos_i, h);
        for c in 0..3 {
            worst = worst.max((exact[c] - got[c]).abs());
        }
    }
    assert!(worst < 0.02, "worst grazing LUT error {worst}");
    // Past the table the incoherent grey takes over without a visible step.
    let inside = lut.reflectance_rgb(1.0, FilmLut::MAX_THICKNESS_NM);
    let beyond = lut.reflectance_rgb(1.0, FilmLut::MAX_THICKNESS_NM + 1.0);
    for c in 0..3 {
        assert!(
            (inside[c] - beyond[c]).abs() < 0.01,
            "{inside:?} vs {beyond:?}"
        );
    }
}

#[test]
fn jittered_wavelengths_converge_to_the_reference_colour_on_thick_films() {
    // A 5 µm film: 8 fixed wavelengths alias into false colour; jittered ones average out to
    // the near-neutral reference.
    let reference = {
        let grid: Vec<f32> = (360..=830).map(|l| l as f32).collect();
        SpectralWeights::new(&grid).film_reflectance_rgb(&FilmFresnel::new(1.0, 1.33), 5000.0)
    };
    let f = FilmFresnel::new(1.0, 1.33);
    let colour_error = |rgb: [f32; 3]| {
        (0..3)
            .map(|c| (rgb[c] - reference[c]).abs())
            .fold(0.0, f32::max)
    };
    let fixed = SampledWavelengths::sample(
        WavelengthRange::VISIBLE,
        8,
        WavelengthStrategy::Stratified,
        &[],
    );
    let fixed_err =
        colour_error(SpectralWeights::new(fixed.as_slice()).film_reflectance_rgb(&f, 5000.0));
    let mut s = 5;
    let mut acc = [0.0f32; 3];
    let samples = 4096;
    let mut w = SpectralWeights::default();
    for _ in 0..samples {
        let u: Vec<f32> = (0..8).map(|_| lcg(&mut s) as f32).collect();
        let wl = SampledWavelengths::sample(
            WavelengthRange::VISIBLE,
            8,
            WavelengthStrategy::Jittered,
            &u,
        );
        w.set_unbiased(wl.as_slice());
        let rgb = w.film_reflectance_rgb(&f, 5000.0);
        for c in 0..3 {
            acc[c] += rgb[c] / samples as f32;
        }
    }
    let jitter_err = colour_error(acc);
    assert!(fixed_err > 0.01, "fixed grid should alias: {fixed_err}");
    assert!(
        jitter_err < 0.004 && jitter_err < fixed_err / 4.0,
        "jittered {jitter_err} vs fixed {fixed_err}"
    );
}

#[test]
fn fast_path_colour_agrees_with_reference_at_all_angles() {
    let grid: Vec<f64> = (360..=830).map(|l| l as f64).collect();
    let grid32: Vec<f32> = grid.iter().map(|&l| l as f32).collect();
    let w = SpectralWeights::new(&grid32);
    let mut s = 13;
    let mut worst = 0.0f64;
    for _ in 0..300 {
        let cos_i = lcg(&mut s).powi(3); // dense near grazing
        let h = 5000.0 * lcg(&mut s);
        let ior = 1.0 + 2.0 * lcg(&mut s);
        let exact = filmsplat::spectrum::film_rgb_reference(cos_i, h, ior, &grid);
        let fast = w.film_reflectance_rgb(&FilmFresnel::new(cos_i as f32, ior as f32), h as f32);
        for c in 0..3 {
            worst = worst.max((exact[c] - fast[c] as f64).abs());
        }
    }
    assert!(worst < 2e-4, "worst colour error {worst}");
}
