//! The pinhole table of `docs/rendering.md`: every real simulator frame, as disks
//! and as the MLS surface, seen from the default camera and edge-on
//! ([`pipeline::pinholes::edge_on`]), at 960×540 and 1 spp (`--preset preview`).
//!
//! `cargo run --release --example pinhole_table -- DATA [PART]` (DATA: the folder holding
//! `thin-film-sph/` and `melp/`; PART: only the frames whose path contains it). Prints one
//! Markdown row per render: the front layer missing on the film's whole interior and only where
//! the particles themselves hold film ([`pipeline::pinholes::front_layer_in_data`]; the
//! figure `render`'s summary calls pinholes, the other beside it), percent.

use filmsplat::image::pinholes::missing_front_layer_besides;
use filmsplat::pipeline;
use filmsplat::pipeline::pinholes::{edge_on, film_particles, front_layer_in_data};
use filmsplat::pointcloud::span::FilmSpan;
use filmsplat::scene::SceneDesc;
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

fn main() {
    let data = PathBuf::from(
        std::env::args()
            .nth(1)
            .expect("usage: pinhole_table DATA [PART]"),
    );
    let only = std::env::args().nth(2).unwrap_or_default();
    println!("| frame | primitive | view | film interior, % | where the data holds film, % |");
    println!("|---|---|---|---|---|");
    for frame in FRAMES.iter().filter(|f| f.contains(&only)) {
        let mut desc = SceneDesc::default();
        desc.input.cloud = Some(data.join(frame));
        desc.render.preset = Some("preview".into());
        let (positions, normals, own) = film_particles(&desc, Path::new("")).expect("load");
        let span = FilmSpan::new(&positions, &normals).with_own_radii(own);
        for primitive in ["disk", "mls"] {
            for (view, from) in [("default", None), ("edge-on", Some(edge_on(&positions)))] {
                desc.film.primitive = Some(primitive.into());
                desc.camera.from = from;
                let prepared = pipeline::prepare(&desc, Path::new(""), false).expect("prepare");
                let out = pipeline::render(&prepared, &prepared.shot).expect("render");
                let (w, h) = (prepared.shot.settings.width, prepared.shot.settings.height);
                let droplets: Vec<bool> = out.droplets.iter().map(|c| *c > 0.0).collect();
                let all = missing_front_layer_besides(&out.depth, w, h, &droplets);
                let data = front_layer_in_data(&prepared, &out, &span);
                println!(
                    "| `{frame}` | {primitive} | {view} | {:.3} | {:.3} |",
                    all.percent(),
                    data.percent()
                );
            }
        }
    }
}
