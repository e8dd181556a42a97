//! `--preset` / `render.preset`: a preset fills the knobs left unset, explicit flags win, and an
//! unknown preset is a one-line error.

mod cli_support;
use cli_support::{filmsplat, tmp};

/// Renders a small bubble scene file (which sets spp = 4) with `extra` flags.
fn summary(extra: &[&str]) -> (i32, String, String) {
    let scene = tmp("preset.toml");
    std::fs::write(
        &scene,
        "[input]\nsample = \"bubble\"\nparticles = 3000\n[render]\nspp = 4\n",
    )
    .unwrap();
    let out = tmp("preset.png");
    let scene = scene.to_str().unwrap();
    let mut args = vec![
        "render",
        scene,
        "-o",
        out.to_str().unwrap(),
        "--size",
        "32x24",
    ];
    args.extend(extra);
    filmsplat(&args)
}

#[test]
fn presets_set_samples_and_flags_override_them() {
    // The scene file says spp = 4; --preset replaces it, --spp beats the preset.
    for (flags, want) in [
        (vec![], "at 4 spp"),
        (vec!["--preset", "preview"], "at 1 spp"),
        (vec!["--preset", "final"], "at 16 spp"),
        (vec!["--preset", "preview", "--spp", "2"], "at 2 spp"),
    ] {
        let (code, out, err) = summary(&flags);
        assert_eq!(code, 0, "{flags:?}: {err}");
        assert!(out.is_empty() && err.contains(want), "{flags:?}: {err}");
    }
    let (code, _, err) = summary(&["--preset", "fast"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("unknown preset 'fast'") && err.lines().count() == 1,
        "{err}"
    );
}

/// Spheres get Russian roulette from the balanced and final presets (their ray trees are long);
/// disks, MLS and the preview preset do not, and `render.roulette` given in the scene wins.
#[test]
fn sphere_presets_play_roulette_unless_told_otherwise() {
    use filmsplat::pipeline::prepare;
    use filmsplat::scene::SceneDesc;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (extra, want) in [
        ("[film]\nprimitive = \"sphere\"\n", 0.1),
        (
            "[film]\nprimitive = \"sphere\"\n[render]\npreset = \"final\"\n",
            0.1,
        ),
        (
            "[film]\nprimitive = \"sphere\"\n[render]\npreset = \"preview\"\n",
            0.0,
        ),
        (
            "[film]\nprimitive = \"sphere\"\n[render]\nroulette = 0.0\n",
            0.0,
        ),
        (
            "[film]\nprimitive = \"disk\"\n[render]\npreset = \"final\"\n",
            0.0,
        ),
        ("[film]\nprimitive = \"mls\"\n", 0.0),
        (
            "[film]\nprimitive = \"disk\"\n[render]\nroulette = 0.3\n",
            0.3,
        ),
    ] {
        let text = format!("[input]\nsample = \"bubble\"\nparticles = 2000\n{extra}");
        let desc = SceneDesc::from_toml(&text, "test.toml").unwrap();
        let p = prepare(&desc, root, false).unwrap();
        assert_eq!(p.shot.settings.roulette, want, "{extra}");
    }
}

/// The preview preset skips the disks' first-order detail (16 bytes a disk) unless the scene
/// asks for it; the other presets build it.
#[test]
fn preview_skips_first_order_detail_unless_asked() {
    use filmsplat::pipeline::prepare;
    use filmsplat::scene::SceneDesc;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let bytes = |extra: &str| {
        let text = format!("[input]\nsample = \"bubble\"\nparticles = 2000\n{extra}");
        let desc = SceneDesc::from_toml(&text, "test.toml").unwrap();
        prepare(&desc, root, false)
            .unwrap()
            .scene
            .geometry
            .memory_bytes()
    };
    let balanced = bytes("");
    let preview = bytes("[render]\npreset = \"preview\"\n");
    let asked = bytes("[film]\ncurvature = true\n[render]\npreset = \"preview\"\n");
    let refused = bytes("[film]\ncurvature = false\n");
    assert_eq!(balanced - preview, 16 * 2000);
    assert_eq!(asked, balanced);
    assert_eq!(refused, preview);
}
