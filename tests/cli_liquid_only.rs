//! A thin-film SPH run of bulk liquid alone (`sph_bubble -test 49`, a block of 980 3D particles
//! under surface tension; tests/data/thin-film-sph/liquid_only): the simulator stores a
//! stand-in film of one particle 10 km away with a thickness of 1 m. The frame renders with no
//! flags: the stand-in is named and not drawn, the camera frames the liquid, and the droplets
//! take the volume the run stored for its 3D particles (their mass), not the stand-in's.

mod cli_support;
use cli_support::{filmsplat, tmp};

const FRAME: &str = "tests/data/thin-film-sph/liquid_only/20";

#[test]
fn a_liquid_only_frame_renders_its_liquid_and_names_the_stand_in_film() {
    let exr = tmp("liquid_only.exr");
    let png = tmp("liquid_only.png");
    let (code, _, err) = filmsplat(&[
        "render",
        FRAME,
        "--size",
        "64x48",
        "--spp",
        "1",
        "-o",
        png.to_str().unwrap(),
        "--exr",
        exr.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("(film): its one particle, at (0, 10000, 0)") && err.contains("stand-in film"),
        "{err}"
    );
    // 8e-8 kg a particle (the run's snapshot 0, 3d/m.bin) over water: r = (3V/4π)^⅓.
    assert!(
        err.contains("radius 2.673e-4 m") && err.contains("of a 3D particle"),
        "{err}"
    );
    // The camera frames the liquid, not a point 10 km away: the water covers a good share of
    // the picture (a block a few cm wide filling the default view).
    let layers = filmsplat::image::read_exr(&exr).unwrap();
    let covered = layers.rgba.iter().filter(|p| p[3] > 0.5).count();
    let share = covered as f32 / layers.rgba.len() as f32;
    assert!(
        share > 0.1,
        "liquid covers {:.1} % of the picture",
        share * 100.0
    );
}

/// The water drawn from the field's grid (the default) and from the exact field: the same
/// body, so the same coverage and about the same light (refraction inside the ball is chaotic,
/// so pixels differ one by one, not in their statistics).
#[test]
fn the_grid_and_the_exact_field_draw_the_same_body() {
    let render = |field: &str| {
        let exr = tmp(&format!("liquid_field_{field}.exr"));
        let png = tmp(&format!("liquid_field_{field}.png"));
        let (code, _, err) = filmsplat(&[
            "render",
            FRAME,
            "--size",
            "96x72",
            "--spp",
            "4",
            "--liquid-field",
            field,
            "-o",
            png.to_str().unwrap(),
            "--exr",
            exr.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let layers = filmsplat::image::read_exr(&exr).unwrap();
        let n = layers.rgba.len() as f32;
        let alpha: f32 = layers.rgba.iter().map(|p| p[3]).sum::<f32>() / n;
        let light: f32 = layers.rgba.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / n;
        (alpha, light)
    };
    let (grid, exact) = (render("grid"), render("exact"));
    assert!(grid.0 > 0.1, "coverage {grid:?}");
    assert!(
        (grid.0 - exact.0).abs() < 0.005,
        "coverage: grid {grid:?}, exact {exact:?}"
    );
    assert!(
        (grid.1 / exact.1 - 1.0).abs() < 0.05,
        "mean light: grid {grid:?}, exact {exact:?}"
    );
}

#[test]
fn an_unknown_liquid_field_is_refused_in_one_line() {
    let (code, _, err) = filmsplat(&["render", FRAME, "--liquid-field", "voxels", "-o", "-"]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("liquid_field") && err.contains("'voxels'"),
        "{err}"
    );
}
