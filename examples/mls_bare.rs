//! The film the MLS surface leaves bare, with and without the particles' own disks
//! ([`filmsplat::geometry::MlsSurface::set_own_disks`]): for each frame, `--preset preview`,
//! `--primitive mls`, 960×540, the default camera, the pieces of the film the particles' own
//! areas hold (4-connected pixels whose primary ray crosses them, [`FilmSpan::crosses`]; the
//! pieces of `tests/torn_fragments.rs`) of 8+ pixels with no film drawn, and the render
//! summary's pinhole figure where the data holds film.
//!
//! `cargo run --release --example mls_bare -- FOLDER FIRST LAST` (FOLDER holds the frames
//! FIRST..=LAST, e.g. the bursting bubble's). Prints one Markdown row per frame: own disks,
//! bare pieces (count, px) and the pinhole figure (%), without the disks → with them.

use filmsplat::geometry::FilmGeometry;
use filmsplat::pipeline;
use filmsplat::pipeline::Prepared;
use filmsplat::pipeline::pinholes::{film_particles, front_layer_in_data};
use filmsplat::pointcloud::span::FilmSpan;
use filmsplat::scene::SceneDesc;
use std::path::{Path, PathBuf};

#[path = "../tests/pieces/mod.rs"]
mod pieces;
use pieces::{data_mask, pieces};

/// Pieces of fewer pixels are not counted.
const LEAST: usize = 8;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: mls_bare FOLDER FIRST LAST";
    let folder = PathBuf::from(args.get(1).expect(usage));
    let first: u32 = args.get(2).expect(usage).parse().expect(usage);
    let last: u32 = args.get(3).expect(usage).parse().expect(usage);
    println!(
        "| frame | own disks | bare pieces (px) | with own disks | pinholes, % | with own disks |"
    );
    println!("|---|---|---|---|---|---|");
    for frame in first..=last {
        let path = folder.join(frame.to_string());
        if !path.exists() {
            continue;
        }
        let mut desc = SceneDesc::default();
        desc.input.cloud = Some(path);
        desc.render.preset = Some("preview".into());
        desc.film.primitive = Some("mls".into());
        let (positions, normals, own) = film_particles(&desc, Path::new("")).expect("load");
        let span = FilmSpan::new(&positions, &normals).with_own_radii(own);
        let mut prepared = pipeline::prepare(&desc, Path::new(""), false).expect("prepare");
        let data = data_mask(&prepared, &span);
        let with = bare_and_pinholes(&prepared, &span, &data);
        let FilmGeometry::Mls(surface) = &mut prepared.scene.geometry else {
            panic!("not an MLS surface");
        };
        let disks = surface.own_disk_count();
        surface
            .set_own_disks(&vec![0.0; surface.len()], None)
            .expect("clear");
        let without = bare_and_pinholes(&prepared, &span, &data);
        println!(
            "| {frame} | {disks} | {} ({}) | {} ({}) | {:.3} | {:.3} |",
            without.0, without.1, with.0, with.1, without.2, with.2
        );
    }
}

/// The render's bare pieces of the film `data` marks (count, pixels) and its pinhole figure.
fn bare_and_pinholes(prepared: &Prepared, span: &FilmSpan, data: &[bool]) -> (usize, usize, f64) {
    let out = pipeline::render(prepared, &prepared.shot).expect("render");
    let w = prepared.shot.settings.width;
    let drawn: Vec<bool> = out.depth.iter().map(|d| *d > 0.0).collect();
    let bare: Vec<usize> = pieces(data, w)
        .into_iter()
        .filter(|p| p.len() >= LEAST && p.iter().all(|&k| !drawn[k]))
        .map(|p| p.len())
        .collect();
    let pinholes = front_layer_in_data(prepared, &out, span).percent();
    (bare.len(), bare.iter().sum(), pinholes)
}
