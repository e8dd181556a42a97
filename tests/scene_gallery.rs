//! Every scene file in samples/ parses and renders (tiny, with few particles), and every
//! generator has one.

use filmsplat::pipeline::{prepare, render};
use filmsplat::samples::SampleKind;
use filmsplat::scene::SceneDesc;
use std::path::Path;

#[test]
fn every_sample_scene_renders_at_32x24() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples");
    let mut names = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let mut desc = SceneDesc::from_toml(&text, &path.to_string_lossy()).unwrap();
        if let Some(s) = &desc.input.sample {
            names.push(s.clone());
        }
        desc.input.particles = Some(3000);
        desc.render.width = Some(32);
        desc.render.height = Some(24);
        desc.render.spp = Some(1);
        let prepared = prepare(&desc, &dir, false).unwrap();
        let out = render(&prepared).unwrap();
        assert!(out.rgb.iter().all(|c| c.is_finite()), "{}", path.display());
        // The camera sees the film: a good part of the frame, not all of it.
        let hit = out.alpha.iter().filter(|&&a| a > 0.5).count() as f64 / out.alpha.len() as f64;
        assert!(
            (0.08..0.9).contains(&hit),
            "{}: film covers {hit}",
            path.display()
        );
    }
    for kind in SampleKind::ALL {
        assert!(
            names.iter().any(|n| n == kind.name()),
            "no samples/*.toml for {}",
            kind.name()
        );
    }
}

#[test]
fn a_scene_file_names_any_generator_and_can_thin_it() {
    let desc = SceneDesc::from_toml(
        "[input]\nsample = \"half-bubble\"\nparticles = 4000\ntime = 0.5\nsparse = 0.5\n",
        "inline",
    )
    .unwrap();
    let c = filmsplat::pipeline::load_cloud(&desc, Path::new(".")).unwrap();
    assert!((1800..2200).contains(&c.len()), "{}", c.len());
    let full = SampleKind::HalfBubble.generate(&filmsplat::samples::SampleParams {
        particles: 4000,
        time: 0.5,
        seed: 1,
    });
    assert!(c.positions.iter().all(|p| full.positions.contains(p)));
}
