//! The render's hooks for callers (the Python package, the viewer): a cancel flag that stops
//! even inside a tile, a tile counter, and the one spp range.

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
    let plain = pipeline::render(&p, &p.shot).unwrap();
    let done = Arc::new(AtomicUsize::new(0));
    p.shot.settings.tiles_done = Some(done.clone());
    p.shot.settings.cancel = Some(Arc::new(AtomicBool::new(false)));
    let counted = pipeline::render(&p, &p.shot).unwrap();
    // 40 x 20 pixels in 16 x 16 tiles: 3 x 2.
    assert_eq!(done.load(Ordering::Relaxed), 6);
    assert_eq!(plain.rgb, counted.rgb);
}

#[test]
fn a_raised_cancel_flag_stops_before_any_tile_and_says_cancelled() {
    let mut p = prepared();
    let done = Arc::new(AtomicUsize::new(0));
    p.shot.settings.tiles_done = Some(done.clone());
    p.shot.settings.cancel = Some(Arc::new(AtomicBool::new(true)));
    let e = pipeline::render(&p, &p.shot).unwrap_err();
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
        pipeline::render(&from_scene, &from_scene.shot).unwrap(),
        pipeline::render(&from_memory, &from_memory.shot).unwrap(),
    );
    assert_eq!(a.rgb, b.rgb);
}

#[test]
fn a_cancel_raised_inside_a_tile_stops_it() {
    // One 16x16 tile at the most samples a pixel may have: minutes of work in that tile alone
    // (16.8 M camera samples), so a render that looked at the flag only between tiles would
    // run past the cap below.
    let mut p = prepared();
    (p.shot.settings.width, p.shot.settings.height) = (16, 16);
    p.shot.settings.spp = filmsplat::render::MAX_SPP;
    let cancel = Arc::new(AtomicBool::new(false));
    p.shot.settings.cancel = Some(cancel.clone());
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(pipeline::render(&p, &p.shot).map(|_| ()));
    });
    std::thread::sleep(std::time::Duration::from_millis(300));
    cancel.store(true, Ordering::Relaxed);
    let r = rx
        .recv_timeout(std::time::Duration::from_secs(20))
        .expect("the render went on inside its tile after the cancel");
    assert!(matches!(r, Err(Error::Cancelled)), "{r:?}");
}

#[test]
fn spp_has_one_range_for_every_way_in() {
    let scene = |spp: &str| {
        SceneDesc::from_toml(
            &format!("[input]\nsample = \"bubble\"\n[render]\nspp = {spp}\n"),
            "spp.toml",
        )
        .unwrap()
    };
    for bad in ["0", "65537", "4294967295"] {
        let e = scene(bad).resolve(Path::new(".")).unwrap_err().to_string();
        assert!(e.contains("render.spp") && e.contains("65536"), "{e}");
    }
    assert!(scene("65536").resolve(Path::new(".")).is_ok());
    // The render itself refuses what bypasses the configuration.
    let mut p = prepared();
    p.shot.settings.spp = u32::MAX;
    let e = pipeline::render(&p, &p.shot).unwrap_err().to_string();
    assert!(e.contains("65536"), "{e}");
}
