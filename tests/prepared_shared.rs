//! One prepared scene, many renders at once: `pipeline::render` reads the `Prepared` only and
//! takes its camera, light turn and settings from a `Shot`, so two threads render one
//! `Arc<Prepared>` from different cameras at the same time, each exactly as it renders alone.

use filmsplat::pipeline::{self, Prepared, Shot};
use filmsplat::render::RenderOutput;
use filmsplat::scene::SceneDesc;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// A bubble sample with droplets' worth of work kept small; the default camera is the
/// scene's, the second looks from the side with a narrower lens and the light turned.
fn prepared() -> (Arc<Prepared>, Shot, Shot) {
    let toml = "[input]\nsample = \"bubble\"\nparticles = 3000\n[render]\nwidth = 48\nheight = 32\nspp = 2\n";
    let desc = SceneDesc::from_toml(toml, "shared.toml").unwrap();
    let p = pipeline::prepare(&desc, Path::new("."), false).unwrap();
    let front = p.shot.clone();
    let mut side_desc = desc.clone();
    side_desc.camera.position = Some([2.5, 0.4, 0.5]);
    side_desc.camera.fov = Some(30.0);
    side_desc.environment.turn_deg = 70.0;
    let side = p.aimed(&side_desc).unwrap();
    (Arc::new(p), front, side)
}

fn bits(o: &RenderOutput) -> Vec<u32> {
    o.rgb
        .iter()
        .flat_map(|c| c.to_array())
        .chain(o.depth.iter().copied())
        .map(f32::to_bits)
        .collect()
}

/// Compiles only while a prepared scene can be shared between threads as it is.
fn shared<T: Send + Sync>(_: &T) {}

#[test]
fn two_threads_render_one_prepared_scene_each_as_alone() {
    let (p, front, side) = prepared();
    shared(&*p);
    let alone = [&front, &side].map(|s| bits(&pipeline::render(&p, s).unwrap()));
    assert_ne!(alone[0], alone[1], "the two cameras see different pictures");
    let together = std::thread::scope(|scope| {
        let runs = [&front, &side].map(|s| {
            let p = Arc::clone(&p);
            scope.spawn(move || bits(&pipeline::render(&p, s).unwrap()))
        });
        runs.map(|r| r.join().unwrap())
    });
    assert!(
        together[0] == alone[0],
        "front camera, rendered beside the side one"
    );
    assert!(
        together[1] == alone[1],
        "side camera, rendered beside the front one"
    );
    // And once more alone: neither render left anything behind in the prepared scene.
    assert!(bits(&pipeline::render(&p, &front).unwrap()) == alone[0]);
}

#[test]
fn a_render_runs_to_the_end_while_another_of_the_same_scene_is_in_flight() {
    // A long render (one 16x16 tile at the most samples a pixel may take, in a pool of its
    // own) is started; once it is under way, a small render of the same `Prepared` with another
    // camera runs to the end while the long one is still rendering, then the long one is
    // cancelled. Overlap is seen in the order of events, not measured in time: a lock held
    // for a whole render would make the small one wait until the long one had finished.
    let (p, front, side) = prepared();
    let cancel = Arc::new(AtomicBool::new(false));
    let started = Arc::new(AtomicUsize::new(0));
    let mut long = front.clone();
    (long.settings.width, long.settings.height) = (16, 16);
    long.settings.spp = filmsplat::render::MAX_SPP;
    long.settings.cancel = Some(cancel.clone());
    let finished = Arc::new(AtomicBool::new(false));
    let one = || {
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
    };
    let (pool_long, pool_small) = (one(), one());
    std::thread::scope(|scope| {
        let (p2, started2, finished2) = (Arc::clone(&p), started.clone(), finished.clone());
        let running = scope.spawn(move || {
            let r = pool_long.install(|| {
                started2.store(1, Ordering::SeqCst);
                pipeline::render(&p2, &long)
            });
            finished2.store(true, Ordering::SeqCst);
            r
        });
        while started.load(Ordering::SeqCst) == 0 {
            std::thread::yield_now();
        }
        // Give the long render a moment to get going (only makes a lock more surely seen; the
        // assertions do not depend on it).
        std::thread::sleep(std::time::Duration::from_millis(50));
        let small = pool_small.install(|| pipeline::render(&p, &side)).unwrap();
        let still_running = !finished.load(Ordering::SeqCst);
        cancel.store(true, Ordering::SeqCst);
        let long = running.join().unwrap();
        assert!(still_running, "the small render waited for the long one");
        assert!(
            matches!(long, Err(filmsplat::Error::Cancelled)),
            "the long render ended on its own: {:?}",
            long.map(|_| ())
        );
        assert!(bits(&small) == bits(&pipeline::render(&p, &side).unwrap()));
    });
}

#[test]
fn a_shot_from_another_camera_and_size_renders_what_a_fresh_preparation_renders() {
    // Droplets (865 on this frame of a bursting bubble, most smaller than a pixel) are grown
    // to the pixel footprints of the camera and height each shot renders with, as preparing
    // the scene for that camera and size would grow them.
    let frame =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/thin-film-sph/bursting_bubble/100");
    let scene = |camera: &str, size: &str| {
        let toml = format!(
            "[input]\ncloud = {:?}\n[render]\n{size}spp = 1\n{camera}",
            frame.display().to_string()
        );
        SceneDesc::from_toml(&toml, "droplets.toml").unwrap()
    };
    let desc = scene("", "width = 64\nheight = 48\n");
    let p = pipeline::prepare(&desc, Path::new("."), false).unwrap();
    assert!(p.droplets > 800, "{} droplets", p.droplets);
    let camera = "[camera]\nposition = [0.2, 0.9, 1.6]\nlook_at = [0, 0.1, 0]\nfov = 25\n";
    let fresh_desc = scene(camera, "width = 96\nheight = 64\n");
    let fresh = pipeline::prepare(&fresh_desc, Path::new("."), false).unwrap();
    let mut shot = p.aimed(&fresh_desc).unwrap();
    (shot.settings.width, shot.settings.height) = (96, 64);
    let out = pipeline::render(&p, &shot).unwrap();
    let want = pipeline::render(&fresh, &fresh.shot).unwrap();
    assert!(
        out.droplets.iter().any(|&c| c > 0.0 && c < 1.0),
        "droplets smaller than a pixel"
    );
    assert!(
        bits(&out) == bits(&want),
        "the shot differs from a fresh preparation"
    );
    assert!(out.droplets == want.droplets);
}
