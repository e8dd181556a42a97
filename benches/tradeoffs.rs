//! The speed/accuracy table users choose their settings from: the bubble sample rendered with
//! every combination of the costly knobs (primitive, shading mode, wavelengths, samples per
//! pixel, ray depth), each timed and compared with a converged render of the same primitive
//! (mean and 95th-percentile CIEDE2000 of the tone-mapped images). Rows on the Pareto front (no
//! other row is both faster and more accurate) are marked; the presets are chosen from them.
//!
//! Writes the table as Markdown to stdout and `target/tradeoffs.md`, and a scatter plot (time vs
//! error, log–log) to `target/tradeoffs.png`.
//!
//! `cargo bench --bench tradeoffs`; environment: `FILMSPLAT_BENCH_PARTICLES` (default 200000),
//! `FILMSPLAT_BENCH_SIZE` (default 480x270), `FILMSPLAT_BENCH_PRIMITIVES` (default `disk,sphere`).

use std::path::Path;
use std::time::Instant;

use filmsplat::image::metrics::delta_e_stats;
use filmsplat::image::{
    Anchor, RgbImage, ToneMap, draw_line, draw_text, fill_rect, save_png, stroke_rect,
};
use filmsplat::pipeline::{self, Prepared};
use filmsplat::render::{FilmShader, ShadingMode};
use filmsplat::scene::SceneDesc;
use filmsplat::spectrum::WavelengthStrategy;

/// One setting a user can choose.
#[derive(Clone, Debug)]
struct Setting {
    shading: ShadingMode,
    wavelengths: usize,
    spp: u32,
    max_depth: u32,
    /// Russian roulette threshold (0: the full ray tree).
    roulette: f32,
}

struct Row {
    primitive: String,
    setting: Setting,
    seconds: f64,
    de_mean: f64,
    de_p95: f64,
    pareto: bool,
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Renders `p` with `s` and returns (seconds, tone-mapped linear image).
fn run(p: &mut Prepared, s: &Setting, ior: f32) -> (f64, RgbImage) {
    p.shader = FilmShader::new(ior, s.shading, s.wavelengths, WavelengthStrategy::Jittered);
    p.shot.settings.spp = s.spp;
    p.shot.settings.max_depth = s.max_depth;
    p.shot.settings.roulette = s.roulette;
    let t = Instant::now();
    let out = pipeline::render(p, &p.shot).expect("render");
    let secs = t.elapsed().as_secs_f64();
    let img = RgbImage::from_data(
        out.width,
        out.height,
        out.rgb
            .iter()
            .map(|c| {
                let e = 2f32.powf(p.shot.exposure);
                [c.x, c.y, c.z].map(|v| p.shot.tonemap.apply(v * e))
            })
            .collect(),
    )
    .expect("size");
    (secs, img)
}

fn main() {
    // Cargo passes `--bench`; nothing else is accepted.
    let particles: usize = env_or("FILMSPLAT_BENCH_PARTICLES", 200_000);
    let size: String = env_or("FILMSPLAT_BENCH_SIZE", "480x270".to_string());
    let prims: String = env_or("FILMSPLAT_BENCH_PRIMITIVES", "disk,sphere".to_string());
    let (w, h) = size
        .split_once('x')
        .and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?)))
        .expect("FILMSPLAT_BENCH_SIZE like 480x270");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("samples/bubble.toml")).expect("bubble.toml");
    let ior = 1.33;
    let reference = Setting {
        shading: ShadingMode::Rgb,
        wavelengths: 32,
        spp: 64,
        max_depth: 24,
        roulette: 0.0,
    };
    let mut settings = Vec::new();
    for spp in [1, 4, 16] {
        for max_depth in [4, 12] {
            let lut = Setting {
                shading: ShadingMode::Lut,
                wavelengths: 0,
                spp,
                max_depth,
                roulette: 0.0,
            };
            settings.push(lut.clone());
            for wavelengths in [8, 16] {
                settings.push(Setting {
                    shading: ShadingMode::Rgb,
                    wavelengths,
                    ..lut.clone()
                });
            }
            if max_depth == 12 {
                for roulette in [0.1, 0.3] {
                    settings.push(Setting {
                        roulette,
                        ..lut.clone()
                    });
                }
            }
        }
    }

    let mut rows = Vec::new();
    for prim in prims.split(',') {
        let mut desc: SceneDesc = toml::from_str(&text).expect("scene");
        desc.input.particles = Some(particles);
        desc.film.primitive = Some(prim.to_string());
        desc.render.width = Some(w);
        desc.render.height = Some(h);
        desc.output.path = None;
        let t = Instant::now();
        let mut p = pipeline::prepare(&desc, root, false).expect("prepare");
        let setup = t.elapsed().as_secs_f64() - p.load_time.as_secs_f64();
        eprintln!(
            "{prim}: {particles} particles, estimate + build {setup:.2} s; reference render..."
        );
        let (ref_secs, ref_img) = run(&mut p, &reference, ior);
        eprintln!("  reference {ref_secs:.1} s");
        for s in &settings {
            let (secs, img) = run(&mut p, s, ior);
            let de = delta_e_stats(&img, &ref_img).expect("same size");
            eprintln!(
                "  {:?} {} wl {} spp depth {} roulette {}: {:.3} s, mean dE {:.3}",
                s.shading, s.wavelengths, s.spp, s.max_depth, s.roulette, secs, de.mean
            );
            rows.push(Row {
                primitive: prim.to_string(),
                setting: s.clone(),
                seconds: secs + setup,
                de_mean: de.mean,
                de_p95: de.p95,
                pareto: false,
            });
        }
    }
    // Pareto front per primitive: no other row of it is at least as fast and as accurate and
    // strictly better in one.
    for i in 0..rows.len() {
        rows[i].pareto = !rows.iter().any(|o| {
            o.primitive == rows[i].primitive
                && o.seconds <= rows[i].seconds
                && o.de_mean <= rows[i].de_mean
                && (o.seconds < rows[i].seconds || o.de_mean < rows[i].de_mean)
        });
    }

    let mut md = format!(
        "bubble sample, {particles} particles, {w}x{h}; time = estimate + build + render (s); \
         error vs a {}-spp, {}-wavelength rgb render of the same primitive at depth {}; \
         ★ = Pareto front\n\n| primitive | shading | wavelengths | spp | max depth | roulette | \
         time (s) | mean ΔE00 | p95 ΔE00 | |\n|---|---|---|---|---|---|---|---|---|---|\n",
        reference.spp, reference.wavelengths, reference.max_depth
    );
    for r in &rows {
        let s = &r.setting;
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {} |\n",
            r.primitive,
            format!("{:?}", s.shading).to_lowercase(),
            if s.shading == ShadingMode::Lut {
                "table".to_string()
            } else {
                s.wavelengths.to_string()
            },
            s.spp,
            s.max_depth,
            if s.roulette > 0.0 {
                s.roulette.to_string()
            } else {
                "—".to_string()
            },
            r.seconds,
            r.de_mean,
            r.de_p95,
            if r.pareto { "★" } else { "" }
        );
    }
    print!("{md}");
    let target = root.join("target");
    std::fs::write(target.join("tradeoffs.md"), &md).expect("write table");
    plot(&rows, &target.join("tradeoffs.png"));
}

/// Log–log scatter of time vs mean ΔE, one colour per primitive, Pareto rows filled.
fn plot(rows: &[Row], path: &Path) {
    let (w, h) = (640usize, 400usize);
    let (x0, y0, x1, y1) = (70.0f32, 20.0f32, 620.0f32, 350.0f32);
    let mut img = RgbImage::filled(w, h, [1.0; 3]);
    let lx = |v: f64| v.max(1e-3).log10() as f32;
    let (tmin, tmax) = rows.iter().fold((f32::MAX, f32::MIN), |(a, b), r| {
        (a.min(lx(r.seconds)), b.max(lx(r.seconds)))
    });
    let (emin, emax) = rows.iter().fold((f32::MAX, f32::MIN), |(a, b), r| {
        (a.min(lx(r.de_mean)), b.max(lx(r.de_mean)))
    });
    let (tmin, tmax) = (tmin.floor(), tmax.ceil().max(tmin.floor() + 1.0));
    let (emin, emax) = (emin.floor(), emax.ceil().max(emin.floor() + 1.0));
    let px = |t: f64| x0 + (lx(t) - tmin) / (tmax - tmin) * (x1 - x0);
    let py = |e: f64| y1 - (lx(e) - emin) / (emax - emin) * (y1 - y0);
    let grey = [0.6; 3];
    stroke_rect(&mut img, x0, y0, x1, y1, 1.0, [0.0; 3]);
    for d in (tmin as i32)..=(tmax as i32) {
        let x = x0 + (d as f32 - tmin) / (tmax - tmin) * (x1 - x0);
        draw_line(&mut img, x, y0, x, y1, 1.0, grey);
        draw_text(
            &mut img,
            x,
            y1 + 6.0,
            &tick(d),
            12.0,
            [0.0; 3],
            Anchor::TOP_CENTRE,
        );
    }
    for d in (emin as i32)..=(emax as i32) {
        let y = y1 - (d as f32 - emin) / (emax - emin) * (y1 - y0);
        draw_line(&mut img, x0, y, x1, y, 1.0, grey);
        draw_text(
            &mut img,
            x0 - 6.0,
            y,
            &tick(d),
            12.0,
            [0.0; 3],
            Anchor::MIDDLE_RIGHT,
        );
    }
    draw_text(
        &mut img,
        0.5 * (x0 + x1),
        376.0,
        "time per frame (s)",
        12.0,
        [0.0; 3],
        Anchor::TOP_CENTRE,
    );
    draw_text(
        &mut img,
        4.0,
        4.0,
        "mean dE00",
        12.0,
        [0.0; 3],
        Anchor::TOP_LEFT,
    );
    let colours = [[0.1, 0.3, 0.8], [0.85, 0.3, 0.1], [0.1, 0.6, 0.2]];
    let mut prims: Vec<&str> = Vec::new();
    for r in rows {
        if !prims.contains(&r.primitive.as_str()) {
            prims.push(&r.primitive);
        }
        let c = colours[prims.iter().position(|p| *p == r.primitive).unwrap() % 3];
        let (x, y) = (px(r.seconds), py(r.de_mean));
        if r.pareto {
            fill_rect(&mut img, x - 4.0, y - 4.0, x + 4.0, y + 4.0, c);
        } else {
            stroke_rect(&mut img, x - 3.0, y - 3.0, x + 3.0, y + 3.0, 1.5, c);
        }
    }
    for (i, p) in prims.iter().enumerate() {
        let y = 30.0 + 16.0 * i as f32;
        fill_rect(&mut img, x1 - 90.0, y, x1 - 82.0, y + 8.0, colours[i % 3]);
        draw_text(
            &mut img,
            x1 - 76.0,
            y - 2.0,
            p,
            12.0,
            [0.0; 3],
            Anchor::TOP_LEFT,
        );
    }
    save_png(path, &img, 0.0, ToneMap::Clamp).expect("write plot");
}

/// Tick label of the decade 10^d.
fn tick(d: i32) -> String {
    if d >= 0 {
        format!("{}", 10u64.pow(d as u32))
    } else {
        format!("{}", 10f64.powi(d))
    }
}
