//! The liquid surface against the MLS film surface, on the real frame drops_on_film/105
//! (tests/data): build time per particle, and single-thread CPU time per camera ray that hits
//! (a camera aimed at the drops for the liquid, at the film for MLS, the same 200×150 grid); the
//! liquid on its field's grid (the default) and exact (`--liquid-field exact`).
//!
//! `cargo bench --bench liquid`

use filmsplat::geometry::{FilmGeometry, LiquidField, LiquidSurface};
use filmsplat::pipeline;
use filmsplat::render::Camera;
use filmsplat::scene::SceneDesc;
use glam::Vec3;
use std::path::Path;
use std::time::Instant;

mod support;
use support::thread_cpu_ns;

const FRAME: &str = "tests/data/thin-film-sph/drops_on_film/105";

/// CPU ns per ray and per hitting ray of `hit` over a `w`×`h` grid of `cam`, repeated `reps`.
fn per_ray(cam: &Camera, hit: impl Fn(&filmsplat::geometry::Ray) -> bool) -> (f64, f64, usize) {
    let (w, h, reps) = (200usize, 150usize, 5);
    let aspect = w as f32 / h as f32;
    let t0 = thread_cpu_ns().unwrap_or(0);
    let wall = Instant::now();
    let mut hits = 0;
    for _ in 0..reps {
        for y in 0..h {
            for x in 0..w {
                let ray = cam.ray(
                    (x as f32 + 0.5) / w as f32,
                    (y as f32 + 0.5) / h as f32,
                    aspect,
                );
                hits += hit(&ray) as usize;
            }
        }
    }
    let ns = match thread_cpu_ns() {
        Some(t1) if t1 > t0 => (t1 - t0) as f64,
        _ => wall.elapsed().as_nanos() as f64,
    };
    let rays = (w * h * reps) as f64;
    (ns / rays, ns / hits.max(1) as f64, hits / reps)
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let desc = |extra: &str| {
        let text = format!("[input]\ncloud = \"{FRAME}\"\n{extra}");
        SceneDesc::from_toml(&text, "bench.toml").unwrap()
    };
    let p = pipeline::prepare(&desc("[film]\nprimitive = \"mls\"\n"), root, false).unwrap();
    let liquid: &LiquidSurface = &p.scene.staging.liquid;
    let FilmGeometry::Mls(mls) = &p.scene.geometry else {
        panic!("expected the MLS film");
    };
    // Build cost per particle (the liquid rebuilt here from the pipeline's classification).
    let parts = pipeline::load_parts(&desc(""), root).unwrap();
    let pts: Vec<Vec3> = parts
        .iter()
        .filter(|q| q.label.contains("droplets"))
        .flat_map(|q| q.cloud.positions.iter().copied())
        .collect();
    let t = Instant::now();
    let reps = 20;
    for _ in 0..reps {
        std::hint::black_box(LiquidSurface::build(&pts, liquid.spacing()).unwrap());
    }
    let liquid_build = t.elapsed().as_nanos() as f64 / (reps * pts.len()) as f64;
    let t = Instant::now();
    for _ in 0..reps {
        let field = LiquidField::Exact;
        std::hint::black_box(LiquidSurface::build_with(&pts, liquid.spacing(), field).unwrap());
    }
    let exact_build = t.elapsed().as_nanos() as f64 / (reps * pts.len()) as f64;
    let exact = LiquidSurface::build_with(&pts, liquid.spacing(), LiquidField::Exact).unwrap();
    let mls_build = p.build_time.as_nanos() as f64 / p.particles as f64;
    // One body (the 8×8×8 block, centre ≈ (−0.025, 0.178, −0.157)) filling the view; the film
    // from above at the same distance.
    let body = Vec3::new(-0.0245, 0.1784, -0.1565);
    let cam_l = Camera::look_at(body + Vec3::new(0.03, 0.02, 0.05), body, Vec3::Y, 35.0);
    let (l_ray, l_hit, l_hits) = per_ray(&cam_l, |r| {
        liquid.intersect(r, 0.0, f32::INFINITY).is_some()
    });
    let (e_ray, e_hit, e_hits) =
        per_ray(&cam_l, |r| exact.intersect(r, 0.0, f32::INFINITY).is_some());
    let film = Vec3::new(0.05, 0.0, 0.05);
    let cam_m = Camera::look_at(film + Vec3::new(0.03, 0.04, 0.05), film, Vec3::Y, 35.0);
    let (m_ray, m_hit, m_hits) =
        per_ray(&cam_m, |r| mls.intersect(r, 0.0, f32::INFINITY).is_some());
    println!(
        "liquid: {} particles, build {liquid_build:.0} ns/particle; {l_ray:.0} ns/ray, {l_hit:.0} ns/hit ({l_hits} of 30000 rays hit)",
        pts.len()
    );
    println!(
        "liquid, exact field (--liquid-field exact): build {exact_build:.0} ns/particle; {e_ray:.0} ns/ray, {e_hit:.0} ns/hit ({e_hits} of 30000 rays hit)"
    );
    println!(
        "mls:    {} particles, build {mls_build:.0} ns/particle (pipeline build stage); {m_ray:.0} ns/ray, {m_hit:.0} ns/hit ({m_hits} of 30000 rays hit)",
        p.particles
    );
    println!(
        "liquid / mls per hit: {:.2} (grid), {:.2} (exact)",
        l_hit / m_hit,
        e_hit / m_hit
    );
}
