//! Bulk liquid on a real frame: the four drops of `drops_on_film/105` (tests/data; 1,956 3D
//! particles) render as bodies of water that cover the projection of the blocks — not as
//! sparse dust — and write alpha and depth like the film.

use filmsplat::pipeline::{self, load_parts};
use filmsplat::pointcloud::liquid::classify;
use filmsplat::scene::SceneDesc;
use glam::Vec3;
use std::path::Path;

const FRAME: &str = "tests/data/thin-film-sph/drops_on_film/105";

fn desc(liquid: &str) -> SceneDesc {
    // Straight down onto the film from 0.8 m (up = −z), one sample a pixel so each pixel's
    // first crossing is one surface: film (thickness > 0) or liquid (thickness 0).
    let text = format!(
        "[input]\ncloud = \"{FRAME}\"\nliquid = \"{liquid}\"\n\
         [camera]\nposition = [0.0, 0.8, 0.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\nfov = 40\n\
         [render]\nwidth = 160\nheight = 120\nspp = 1\n"
    );
    SceneDesc::from_toml(&text, "liquid.toml").unwrap()
}

/// Distance from `p` to the ray's line (the ray starts above everything).
fn line_distance(o: Vec3, d: Vec3, p: Vec3) -> f32 {
    let v = p - o;
    (v - d * v.dot(d)).length()
}

#[test]
fn drops_render_as_water_covering_the_blocks() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let d = desc("surface");
    let p = pipeline::prepare(&d, root, false).unwrap();
    assert_eq!(p.scene.staging.liquid.len(), 1956);
    assert_eq!(p.droplets, 0);
    let out = pipeline::render(&p, &p.shot).unwrap();
    // The liquid particles, as the pipeline classifies them.
    let parts = load_parts(&d, root).unwrap();
    let pts: Vec<Vec3> = parts
        .iter()
        .filter(|q| q.label.contains("droplets"))
        .flat_map(|q| q.cloud.positions.iter().copied())
        .collect();
    let split = classify(&pts);
    let s = split.spacing;
    let r = filmsplat::geometry::VOLUME_RADIUS * s;
    let (w, h) = (out.width, out.height);
    let aspect = w as f32 / h as f32;
    let (mut core, mut core_liquid, mut liquid, mut liquid_near) = (0, 0, 0, 0);
    for y in 0..h {
        for x in 0..w {
            let k = y * w + x;
            let ray = p.scene.camera.ray(
                (x as f32 + 0.5) / w as f32,
                (y as f32 + 0.5) / h as f32,
                aspect,
            );
            let near = pts
                .iter()
                .map(|&c| line_distance(ray.origin, ray.dir, c))
                .fold(f32::MAX, f32::min);
            let is_liquid = out.alpha[k] == 1.0 && out.thickness[k] == 0.0;
            if near < 0.5 * r {
                core += 1;
                core_liquid += is_liquid as usize;
            }
            if is_liquid {
                liquid += 1;
                liquid_near += (near < r + 0.6 * s) as usize;
                // Depth like the film's: the distance to the first crossing, above the film
                // plane (y ≈ 0 at 0.8 m below the camera; the drops reach up to 0.19 m).
                let t_film = 0.8 / ray.dir.y.abs();
                assert!(
                    out.depth[k] > 0.55 && out.depth[k] < t_film + 0.02,
                    "{}",
                    out.depth[k]
                );
                assert!(out.normal[k].length() > 0.99);
            }
        }
    }
    // The blocks' projection is covered by the water surface (not dust), and the water stays
    // within about half a spacing of the particles' own spheres.
    eprintln!("core {core_liquid} of {core}; liquid {liquid_near} of {liquid} near the particles");
    assert!(core > 60, "{core} pixels over the blocks");
    assert!(
        core_liquid as f32 >= 0.97 * core as f32,
        "{core_liquid} of {core} core pixels"
    );
    assert!(
        liquid_near as f32 >= 0.99 * liquid as f32,
        "{liquid_near} of {liquid} liquid pixels near"
    );
}

#[test]
fn droplet_mode_keeps_every_particle_a_droplet() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let p = pipeline::prepare(&desc("droplets"), root, false).unwrap();
    assert!(p.scene.staging.liquid.is_empty());
    assert_eq!(p.droplets, 1956);
    let bad = SceneDesc::from_toml(
        &format!("[input]\ncloud = \"{FRAME}\"\nliquid = \"mesh\"\n"),
        "bad.toml",
    )
    .unwrap();
    let err = pipeline::prepare(&bad, root, false)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("input.liquid") && err.contains("mesh"),
        "{err}"
    );
}
