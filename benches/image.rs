//! Image stage costs: exposure + tone map + sRGB encoding of a frame, text labels, EXR writing.

use criterion::{Criterion, criterion_group, criterion_main};
use filmsplat::image::{
    Anchor, ExrLayers, RgbImage, ToneMap, draw_text, draw_text_vertical, to_srgb8, write_exr,
};
use std::hint::black_box;

fn frame(w: usize, h: usize) -> RgbImage {
    let data = (0..w * h)
        .map(|i| [(i % 97) as f32 * 0.05, (i % 13) as f32 * 0.1, 0.18])
        .collect();
    RgbImage::from_data(w, h, data).unwrap()
}

fn tonemap(c: &mut Criterion) {
    let img = frame(512, 512);
    let mut g = c.benchmark_group("to_srgb8_512x512");
    for tone in [ToneMap::Clamp, ToneMap::Filmic] {
        g.bench_function(tone.to_string(), |b| {
            b.iter(|| black_box(to_srgb8(&img, 0.5, tone)))
        });
    }
    g.finish();
}

fn text(c: &mut Criterion) {
    let mut img = RgbImage::filled(600, 100, [1.0; 3]);
    let label = "Film thickness (nm)"; // 19 characters
    let mut g = c.benchmark_group("text");
    for size in [12.0f32, 22.0, 32.0] {
        g.bench_function(format!("label_19_chars_{size}px"), |b| {
            b.iter(|| {
                draw_text(
                    &mut img,
                    10.0,
                    50.0,
                    label,
                    black_box(size),
                    [0.0; 3],
                    Anchor::MIDDLE_LEFT,
                )
            })
        });
    }
    let mut tall = RgbImage::filled(100, 600, [1.0; 3]);
    g.bench_function("vertical_label_19_chars_22px", |b| {
        b.iter(|| {
            draw_text_vertical(
                &mut tall,
                50.0,
                300.0,
                label,
                22.0,
                [0.0; 3],
                Anchor::CENTRE,
            )
        })
    });
    g.finish();
}

fn exr(c: &mut Criterion) {
    let (w, h) = (256, 256);
    let n = w * h;
    let layers = ExrLayers {
        width: w,
        height: h,
        rgba: (0..n).map(|i| [i as f32 * 1e-4, 0.5, 0.25, 1.0]).collect(),
        depth: Some((0..n).map(|i| i as f32).collect()),
        normal: Some(vec![[0.0, 0.0, 1.0]; n]),
        thickness: Some((0..n).map(|i| (i % 700) as f32).collect()),
        hit_count: Some(vec![2.0; n]),
        droplets: Some(vec![0.0; n]),
    };
    let path = std::env::temp_dir().join(format!("filmsplat-bench-{}.exr", std::process::id()));
    c.bench_function("write_exr_256x256_all_layers", |b| {
        b.iter(|| write_exr(&path, &layers).unwrap())
    });
    let _ = std::fs::remove_file(&path);
}

criterion_group!(benches, tonemap, text, exr);
criterion_main!(benches);
