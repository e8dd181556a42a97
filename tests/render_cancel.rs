//! The render's hooks for callers (the Python package): a cancel flag and a tile counter.

use filmsplat::Error;
use filmsplat::pipeline;
use filmsplat::scene::SceneDesc;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

fn prepared() -> pipeline::Prepared {
    let desc = SceneDesc::from_toml(
        "[input]\nsample = \"bubble\"\nparticles = 2000\n[render]\nwidth = 40\nheight = 20\nspp = 1\n",
        "cancel.toml",
    )
    .unwrap();
    pipeline::prepare(&desc, Path::new("."), false).unwrap()
}

#[test]
fn the_tile_counter_reaches_every_tile_and_the_image_is_unchanged() {
    let mut p = prepared();
    let plain = pipeline::render(&p).unwrap();
    let done = Arc::new(AtomicUsize::new(0));
    p.settings.tiles_done = Some(done.clone());
    p.settings.cancel = Some(Arc::new(AtomicBool::new(false)));
    let counted = pipeline::render(&p).unwrap();
    // 40 x 20 pixels in 16 x 16 tiles: 3 x 2.
    assert_eq!(done.load(Ordering::Relaxed), 6);
    assert_eq!(plain.rgb, counted.rgb);
}

#[test]
fn a_raised_cancel_flag_stops_before_any_tile_and_says_cancelled() {
    let mut p = prepared();
    let done = Arc::new(AtomicUsize::new(0));
    p.settings.tiles_done = Some(done.clone());
    p.settings.cancel = Some(Arc::new(AtomicBool::new(true)));
    let e = pipeline::render(&p).unwrap_err();
    assert!(matches!(e, Error::Cancelled), "{e}");
    assert_eq!(e.to_string(), "cancelled");
    assert_eq!(done.load(Ordering::Relaxed), 0);
}

#[test]
fn prepare_with_an_in_memory_cloud_equals_the_same_cloud_from_the_scene() {
    let desc = SceneDesc::from_toml(
        "[input]\nsample = \"bubble\"\nparticles = 2000\n[render]\nwidth = 24\nheight = 16\nspp = 1\n",
        "memory.toml",
    )
    .unwrap();
    let cloud = pipeline::load_cloud(&desc, Path::new(".")).unwrap();
    let from_scene = pipeline::prepare(&desc, Path::new("."), false).unwrap();
    // The in-memory cloud wins over [input], which would fail here.
    let mut no_input = desc.clone();
    no_input.input = Default::default();
    let from_memory =
        pipeline::prepare_with(&no_input, Path::new("."), false, Some(cloud)).unwrap();
    assert_eq!(from_scene.framing, from_memory.framing);
    let (a, b) = (
        pipeline::render(&from_scene).unwrap(),
        pipeline::render(&from_memory).unwrap(),
    );
    assert_eq!(a.rgb, b.rgb);
}
