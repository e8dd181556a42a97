//! The pinhole table of `docs/rendering.md`: every real simulator frame, as disks and as the
//! MLS surface, seen from the default camera and edge-on (5° above the plane of the film's two
//! longest axes), at 960×540 and 1 spp (`--preset preview`).
//!
//! `cargo run --release --example pinhole_table -- DATA [PART]` (DATA: the folder holding
//! `thin-film-sph/` and `melp/`; PART: only the frames whose path contains it). Prints one Markdown row per render: the front layer missing
//! on the film's whole interior (the figure `render` prints) and only where the particles
//! themselves hold film ([`filmsplat::pipeline::pinholes`]), percent.

use filmsplat::io::PartKind;
use filmsplat::pipeline;
use filmsplat::pointcloud::estimate::estimate_normals;
use filmsplat::pointcloud::span::FilmSpan;
use filmsplat::scene::SceneDesc;
use glam::{DMat3, DVec3, Vec3};
use std::path::{Path, PathBuf};

const FRAMES: &[&str] = &[
    "thin-film-sph/bursting_bubble/0",
    "thin-film-sph/bursting_bubble/30",
    "thin-film-sph/bursting_bubble/60",
    "thin-film-sph/bursting_bubble/100",
    "thin-film-sph/catenoid/45",
    "thin-film-sph/rayleigh_taylor/100",
    "thin-film-sph/drops_on_film/105",
    "melp/bubble/l_particles_0100.vtp",
    "melp/bubble/l_particles_0104.vtp",
    "melp/foam3/50",
];

/// The unit direction 5° above the plane of the cloud's two longest axes (edge-on), on the
/// side of the default camera.
fn edge_on(positions: &[Vec3]) -> [f32; 3] {
    let n = positions.len().max(1) as f64;
    let c = positions.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / n;
    let mut m = DMat3::ZERO;
    for p in positions {
        let d = p.as_dvec3() - c;
        m += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let e = filmsplat::pointcloud::eigen::sym_eigen3(&(m / n));
    let axis = e.vectors[0].as_vec3().normalize();
    let from = Vec3::from(pipeline::framing::DEFAULT_FROM).normalize();
    let flat = (from - from.dot(axis) * axis).normalize_or(axis.any_orthonormal_vector());
    let a = 5f32.to_radians();
    let up = if from.dot(axis) < 0.0 { -axis } else { axis };
    (a.cos() * flat + a.sin() * up).to_array()
}

fn main() {
    let data = PathBuf::from(
        std::env::args()
            .nth(1)
            .expect("usage: pinhole_table DATA [PART]"),
    );
    let only = std::env::args().nth(2).unwrap_or_default();
    println!("| frame | primitive | view | film interior, % | where the data holds film, % |");
    println!("|---|---|---|---|---|");
    for frame in FRAMES {
        let mut desc = SceneDesc::default();
        desc.input.cloud = Some(data.join(frame));
        desc.render.preset = Some("preview".into());
        if !frame.contains(&only) {
            continue;
        }
        // The film parts (droplets and liquid are not film), normals estimated where missing.
        let (mut positions, mut normals) = (Vec::new(), Vec::new());
        for part in pipeline::load_parts(&desc, Path::new("")).expect("load") {
            if part.kind != PartKind::Film {
                continue;
            }
            let c = part.cloud;
            let n = c
                .normals
                .clone()
                .unwrap_or_else(|| estimate_normals(&c.positions, 12));
            positions.extend_from_slice(&c.positions);
            normals.extend(n);
        }
        let span = FilmSpan::new(&positions, &normals);
        let side = edge_on(&positions);
        for primitive in ["disk", "mls"] {
            for (view, from) in [("default", None), ("edge-on", Some(side))] {
                desc.film.primitive = Some(primitive.into());
                desc.camera.from = from;
                let prepared = pipeline::prepare(&desc, Path::new(""), false).expect("prepare");
                let out = pipeline::render(&prepared).expect("render");
                let (w, h) = (prepared.settings.width, prepared.settings.height);
                let droplets: Vec<bool> = out.droplets.iter().map(|c| *c > 0.0).collect();
                let all = filmsplat::image::pinholes::missing_front_layer_besides(
                    &out.depth, w, h, &droplets,
                );
                let data = pipeline::pinholes::front_layer_in_data(&prepared, &out, &span);
                println!(
                    "| `{frame}` | {primitive} | {view} | {:.3} | {:.3} |",
                    all.percent(),
                    data.percent()
                );
            }
        }
    }
}
