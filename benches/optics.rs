//! Hot-path thin-film evaluation: reflectance at one (h, θ) for 4–32 wavelengths, and the RGB
//! colour of one hit (per-hit integration and lookup table).

use criterion::{Criterion, criterion_group, criterion_main};
use filmsplat::optics::{FilmFresnel, film_rt};
use filmsplat::spectrum::{
    FilmLut, SampledWavelengths, SpectralWeights, WavelengthRange, WavelengthStrategy,
};
use std::hint::black_box;

fn reflectance(c: &mut Criterion) {
    let mut g = c.benchmark_group("reflectance");
    for n in [4usize, 8, 16, 32] {
        let wl = SampledWavelengths::sample(
            WavelengthRange::VISIBLE,
            n,
            WavelengthStrategy::Stratified,
            &[],
        );
        let inv: Vec<f32> = wl.as_slice().iter().map(|l| 1.0 / l).collect();
        let mut out = vec![0.0; n];
        g.bench_function(format!("fast_f32_{n}_wavelengths"), |b| {
            let mut h = 100.0f32;
            b.iter(|| {
                h = if h > 1500.0 { 100.0 } else { h + 1.0 };
                let f = FilmFresnel::new(black_box(0.8), 1.33);
                f.reflectance_into(black_box(h), &inv, &mut out);
                black_box(&out);
            })
        });
        g.bench_function(format!("reference_f64_{n}_wavelengths"), |b| {
            b.iter(|| {
                for l in wl.as_slice() {
                    black_box(film_rt(black_box(0.8), black_box(420.0), 1.33, *l as f64).r());
                }
            })
        });
    }
    g.finish();
}

fn hit_colour(c: &mut Criterion) {
    let mut g = c.benchmark_group("hit_rgb");
    for n in [8usize, 16, 32] {
        let wl = SampledWavelengths::sample(
            WavelengthRange::VISIBLE,
            n,
            WavelengthStrategy::Jittered,
            &[0.3; 64],
        );
        let w = SpectralWeights::new(wl.as_slice());
        g.bench_function(format!("per_hit_{n}_wavelengths"), |b| {
            let mut h = 100.0f32;
            b.iter(|| {
                h = if h > 1500.0 { 100.0 } else { h + 1.0 };
                let f = FilmFresnel::new(black_box(0.8), 1.33);
                black_box(w.film_reflectance_rgb(&f, black_box(h)))
            })
        });
        g.bench_function(format!("weights_setup_{n}_wavelengths"), |b| {
            let mut w = SpectralWeights::default();
            b.iter(|| w.set(black_box(wl.as_slice())))
        });
    }
    let lut = FilmLut::new(1.33);
    g.bench_function("lut", |b| {
        let mut h = 100.0f32;
        b.iter(|| {
            h = if h > 1500.0 { 100.0 } else { h + 1.0 };
            black_box(lut.reflectance_rgb(black_box(0.8), black_box(h)))
        })
    });
    g.finish();
    // The whole table from empty (a render builds only the blocks its thicknesses need).
    c.bench_function("lut_build", |b| {
        b.iter(|| black_box(FilmLut::build_uncached(1.33)).prebuild())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2)).sample_size(20);
    targets = reflectance, hit_colour
}
criterion_main!(benches);
