//! How much of each film shows its colours under the default lighting: the share of film
//! pixels whose colour is visible (see `filmsplat::image::visibility`), per input, as a
//! Markdown table. Not a timing: a measure of the default studio on real frames.
//!
//! `cargo bench --bench colour_visibility -- INPUT...` (particle files, simulator frame
//! folders or scene files; default: the samples and the real frames in tests/data). Env:
//! FILMSPLAT_BENCH_SIZE=WxH (default 160x90), FILMSPLAT_VISIBILITY_PNG=DIR writes each
//! picture there.

use filmsplat::pipeline::{colour_visibility_of, prepare, render, write_image};
use filmsplat::scene::SceneDesc;
use std::path::{Path, PathBuf};

fn inputs() -> Vec<PathBuf> {
    let given: Vec<PathBuf> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .collect();
    if !given.is_empty() {
        return given;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut v: Vec<PathBuf> = [
        "tests/data/thin-film-sph/bursting_bubble/60",
        "tests/data/thin-film-sph/bursting_bubble/100",
        "tests/data/melp/bubble/l_particles_0100.vtp",
        "tests/data/melp/foam3/50",
    ]
    .iter()
    .map(|p| root.join(p))
    .filter(|p| p.exists())
    .collect();
    let mut samples: Vec<PathBuf> = std::fs::read_dir(root.join("samples"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    samples.sort();
    v.extend(samples);
    v
}

fn main() {
    let size = std::env::var("FILMSPLAT_BENCH_SIZE").unwrap_or_else(|_| "160x90".into());
    let (w, h) = size.split_once('x').expect("WxH");
    let (w, h): (usize, usize) = (w.parse().unwrap(), h.parse().unwrap());
    let png_dir = std::env::var("FILMSPLAT_VISIBILITY_PNG")
        .ok()
        .map(PathBuf::from);
    println!("| input | film pixels | colour visible | faint | dark | burnt |");
    println!("|---|---:|---:|---:|---:|---:|");
    for input in inputs() {
        let is_scene = input.extension().is_some_and(|e| e == "toml");
        let (mut desc, base) = if is_scene {
            let text = std::fs::read_to_string(&input).unwrap();
            let d = SceneDesc::from_toml(&text, &input.display().to_string()).unwrap();
            (d, input.parent().unwrap().to_path_buf())
        } else {
            let mut d = SceneDesc::default();
            d.input.cloud = Some(std::path::absolute(&input).unwrap());
            (d, PathBuf::new())
        };
        (desc.render.width, desc.render.height) = (Some(w), Some(h));
        desc.render.spp = Some(2);
        if desc.input.sample.is_some() {
            desc.input.particles = Some(desc.input.particles.unwrap_or(20_000).min(20_000));
        }
        let p = match prepare(&desc, &base, false) {
            Ok(p) => p,
            Err(e) => {
                println!("| {} | error: {e} | | | | |", input.display());
                continue;
            }
        };
        let out = render(&p, &p.shot).unwrap();
        let v = colour_visibility_of(&p, &out);
        let pct = |n: usize| 100.0 * n as f64 / v.film_pixels.max(1) as f64;
        let name = input
            .strip_prefix(env!("CARGO_MANIFEST_DIR"))
            .unwrap_or(&input)
            .display()
            .to_string();
        println!(
            "| {name} | {} | {:.1} % | {:.1} % | {:.1} % | {:.1} % |",
            v.film_pixels,
            100.0 * v.share(),
            pct(v.faint),
            pct(v.dark),
            pct(v.burnt)
        );
        if let Some(dir) = &png_dir {
            std::fs::create_dir_all(dir).unwrap();
            let file = name.trim_start_matches('/').replace(['/', '.'], "_") + ".png";
            write_image(&p.shot, &out, &dir.join(file)).unwrap();
        }
    }
}
