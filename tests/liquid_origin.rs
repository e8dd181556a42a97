//! `--liquid auto` (the default) on thin-film SPH runs: the run's frame 0 tells bulk liquid the
//! case set up (3D particles already there) from spray shed by a rupture (frame 0 holds none).
//! Each test builds a fake run `<tmp>/run/{0,5}` from the real frame `drops_on_film/105`
//! (tests/data; 1,956 3D particles in four packed blocks, which positions alone call bodies).

mod scratch;

use filmsplat::pipeline::{self, Prepared};
use filmsplat::scene::SceneDesc;
use std::path::{Path, PathBuf};

const FRAME: &str = "tests/data/thin-film-sph/drops_on_film/105";
const PARTICLES: usize = 1956;

/// A fresh run folder `<tmp>/filmsplat-liquid-origin-<pid>-<name>/run` with frame 5 a copy of
/// [`FRAME`], and frame 0 as `first` makes it (`None`: no frame 0).
fn run(name: &str, first: Option<fn(&Path)>) -> PathBuf {
    let root = scratch::dir("liquid-origin").join(name).join("run");
    let _ = std::fs::remove_dir_all(&root);
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join(FRAME);
    let copy = |to: &Path| {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(&src).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    };
    copy(&root.join("5"));
    if let Some(make) = first {
        copy(&root.join("0"));
        make(&root.join("0"));
    }
    root
}

/// Frame 0 before any rupture: the film, and `tracker_points_3d` of count 0 as the simulator
/// writes it (as in bursting_bubble/0).
fn no_3d_particles(dir: &Path) {
    std::fs::write(dir.join("tracker_points_3d"), 0i32.to_le_bytes()).unwrap();
    for f in ["rh_bin_3d", "norm_bin_3d"] {
        std::fs::write(dir.join(f), 0u32.to_le_bytes()).unwrap();
    }
}

/// Frame 0 with the case's drops already there: the copy as it is.
fn with_3d_particles(_: &Path) {}

/// Frame 0 whose `tracker_points_3d` header disagrees with its size.
fn unreadable(dir: &Path) {
    std::fs::write(dir.join("tracker_points_3d"), [9, 0, 0, 0, 1]).unwrap();
}

fn prepare(run: &Path, liquid: Option<&str>) -> Prepared {
    let key = liquid
        .map(|l| format!("liquid = \"{l}\"\n"))
        .unwrap_or_default();
    let text = format!(
        "[input]\ncloud = {:?}\n{key}[render]\nwidth = 64\nheight = 48\nspp = 1\n",
        run.join("5").display().to_string()
    );
    let d = SceneDesc::from_toml(&text, "origin.toml").unwrap();
    pipeline::prepare(&d, run, false).unwrap()
}

fn notes(p: &Prepared) -> String {
    p.notes
        .iter()
        .map(|n| n.text.clone())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn shed_after_an_empty_frame_0_stays_droplets() {
    let r = run("shed", Some(no_3d_particles));
    let p = prepare(&r, None);
    assert!(p.scene.staging.liquid.is_empty(), "{}", notes(&p));
    assert_eq!(p.droplets, PARTICLES);
    let n = notes(&p);
    assert!(
        n.contains("shed after frame 0") && n.contains("holds none") && n.contains("1956 droplets"),
        "{n}"
    );
    // The explicit mode still forces bodies on the same frame; "auto" spelled out is the default.
    let forced = prepare(&r, Some("surface"));
    assert_eq!(forced.scene.staging.liquid.len(), PARTICLES);
    assert_eq!(forced.droplets, 0);
    assert_eq!(prepare(&r, Some("auto")).droplets, PARTICLES);
}

#[test]
fn present_since_frame_0_becomes_bodies_of_water() {
    let r = run("setup", Some(with_3d_particles));
    let p = prepare(&r, None);
    assert_eq!(p.scene.staging.liquid.len(), PARTICLES);
    assert_eq!(p.droplets, 0);
    let n = notes(&p);
    assert!(
        n.contains("present since frame 0")
            && n.contains("holds 1956")
            && n.contains("bodies of water"),
        "{n}"
    );
}

#[test]
fn without_a_readable_frame_0_positions_decide() {
    for (name, first) in [("none", None), ("bad", Some(unreadable as fn(&Path)))] {
        let r = run(name, first);
        let p = prepare(&r, None);
        assert_eq!(p.scene.staging.liquid.len(), PARTICLES, "{name}");
        assert_eq!(p.droplets, 0, "{name}");
        let n = notes(&p);
        let why = if first.is_none() {
            "no frame 0"
        } else {
            "frame 0 unreadable"
        };
        assert!(
            n.contains(why) && n.contains("positions decide"),
            "{name}: {n}"
        );
    }
}

#[test]
fn without_frame_0_spray_is_told_by_its_own_thicknesses() {
    // bursting_bubble/60 (tests/data, no frame 0 beside it): 792 3D particles shed by the
    // rupture, each holding the thickness of the film particle it came from (no two alike).
    // Positions alone packed 651 of them into six bodies of water of 1.8e-4 m³, where their
    // stored mass holds 7.1e-9 m³; their own rh tells they are droplets. (The drops above,
    // which share one rh, still become bodies: `without_a_readable_frame_0_positions_decide`.)
    let frame =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/thin-film-sph/bursting_bubble/60");
    let text = format!(
        "[input]\ncloud = {:?}\n[render]\nwidth = 64\nheight = 48\nspp = 1\n",
        frame.display().to_string()
    );
    let d = SceneDesc::from_toml(&text, "spray.toml").unwrap();
    let p = pipeline::prepare(&d, Path::new(""), false).unwrap();
    assert!(p.scene.staging.liquid.is_empty(), "{}", notes(&p));
    assert_eq!(p.droplets, 792);
    let n = notes(&p);
    assert!(
        n.contains("no two alike") && n.contains("792 droplets"),
        "{n}"
    );
}
