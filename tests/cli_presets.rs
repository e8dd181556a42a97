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
        assert!(out.contains(want), "{flags:?}: {out}");
    }
    let (code, _, err) = summary(&["--preset", "fast"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("unknown preset 'fast'") && err.lines().count() == 1,
        "{err}"
    );
}
