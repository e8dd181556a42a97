//! Speed/accuracy of the shading modes on the studio scene (samples/studio.toml: the bubble
//! over a floor and backdrop, one area light, the studio environment): time per render and
//! the CIEDE2000 colour error, mean and 95th percentile, against a high-sample `spectral`
//! reference (16 jittered wavelengths per sample). Errors are measured on the displayed
//! image (filmic tone curve), so they include each mode's noise at the given spp. Prints a
//! Markdown table.
//!
//! `cargo bench --bench studio` (env: FILMSPLAT_BENCH_SIZE=WxH, default 160x90;
//! FILMSPLAT_BENCH_SPP, default 16; FILMSPLAT_BENCH_REF_SPP, default 256;
//! FILMSPLAT_BENCH_PARTICLES, default 50000).

use filmsplat::image::metrics::delta_e_stats;
use filmsplat::image::{RgbImage, ToneMap};
use filmsplat::pipeline::{Prepared, prepare, render};
use filmsplat::render::{FilmShader, ShadingMode};
use filmsplat::scene::SceneDesc;
use filmsplat::spectrum::WavelengthStrategy;
use std::path::Path;
use std::time::Instant;

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn display(p: &Prepared, spp: u32, shader: &FilmShader) -> (RgbImage, f64) {
    let mut settings = p.shot.settings.clone();
    settings.spp = spp;
    let t = Instant::now();
    let out = filmsplat::render::render(&p.scene, shader, &settings).unwrap(); // the scene as prepared: its own camera, no droplets
    let secs = t.elapsed().as_secs_f64();
    let k = 2f32.powf(p.shot.exposure);
    let data = out
        .rgb
        .iter()
        .map(|c| c.to_array().map(|v| ToneMap::Filmic.apply(v * k)))
        .collect();
    (
        RgbImage::from_data(out.width, out.height, data).unwrap(),
        secs,
    )
}

fn main() {
    let size: String = env_or("FILMSPLAT_BENCH_SIZE", "160x90".to_string());
    let (w, h): (usize, usize) = size
        .split_once('x')
        .map(|(a, b)| (a.parse().unwrap(), b.parse().unwrap()))
        .unwrap();
    let spp: u32 = env_or("FILMSPLAT_BENCH_SPP", 16);
    let ref_spp: u32 = env_or("FILMSPLAT_BENCH_REF_SPP", 256);
    let particles: usize = env_or("FILMSPLAT_BENCH_PARTICLES", 50_000);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples");
    let text = std::fs::read_to_string(root.join("studio.toml")).unwrap();
    let mut desc = SceneDesc::from_toml(&text, "studio.toml").unwrap();
    desc.input.particles = Some(particles);
    desc.render.width = Some(w);
    desc.render.height = Some(h);
    let p = prepare(&desc, &root, false).unwrap();
    // Warm the thread pool.
    let _ = render(&p, &p.shot);
    let jit = WavelengthStrategy::Jittered;
    let ior = p.shader.ior();
    let (reference, ref_secs) = display(
        &p,
        ref_spp,
        &FilmShader::new(ior, ShadingMode::Spectral, 16, jit),
    );
    println!(
        "studio scene, {particles} particles, {w}x{h}, {spp} spp, {} threads; reference: spectral, \
         16 wavelengths, {ref_spp} spp ({ref_secs:.1} s)\n",
        rayon::current_num_threads()
    );
    println!("| shading | wavelengths | time (s) | ΔE00 mean | ΔE00 p95 |");
    println!("|---|---:|---:|---:|---:|");
    let mut rows: Vec<(ShadingMode, usize)> = vec![(ShadingMode::Lut, 0)];
    for n in [4, 8, 16] {
        rows.push((ShadingMode::Rgb, n));
    }
    for n in [4, 8, 16] {
        rows.push((ShadingMode::Spectral, n));
    }
    for (mode, n) in rows {
        let t = Instant::now();
        let shader = FilmShader::new(ior, mode, n.max(1), jit);
        let build = t.elapsed().as_secs_f64();
        let (img, secs) = display(&p, spp, &shader);
        let e = delta_e_stats(&img, &reference).unwrap();
        let nl = if n == 0 {
            "—".to_string()
        } else {
            n.to_string()
        };
        println!(
            "| {mode} | {nl} | {:.2} | {:.2} | {:.2} |",
            secs + build,
            e.mean,
            e.p95
        );
    }
}
