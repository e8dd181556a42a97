//! CLI: a mistake anywhere in a scene file or the flags is refused before any particle is
//! read. Each scene's input is a file no reader accepts (a PLY header promising four billion
//! vertices, and none after it), so an error about anything else proves its check ran first.

mod cli_support;
use cli_support::{filmsplat, tmp};
use std::path::PathBuf;

/// A PLY no reader accepts: four billion binary vertices promised, none given.
fn hostile(name: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::write(
        &p,
        "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n\
         property float x\nproperty float y\nproperty float z\nend_header\n",
    )
    .unwrap();
    p
}

/// Renders `scene` (its `[input]` the hostile file) with `flags`; returns (code, stderr).
fn render(name: &str, scene: &str, flags: &[&str]) -> (i32, String) {
    let input = hostile(&format!("{name}.ply"));
    let text = format!(
        "[input]\ncloud = \"{}\"\n{scene}",
        input.file_name().unwrap().to_string_lossy()
    );
    let file = tmp(&format!("{name}.toml"));
    std::fs::write(&file, text).unwrap();
    let out = tmp(&format!("{name}.png"));
    let (f, o) = (file.to_string_lossy(), out.to_string_lossy());
    let mut args = vec!["render", &*f, "-o", &*o, "-q"];
    args.extend_from_slice(flags);
    let (code, _, err) = filmsplat(&args);
    (code, err)
}

/// Each bad key with the words its error must hold (and never the input's problem).
const CASES: &[(&str, &str, &[&str])] = &[
    (
        "light_without_radiance",
        "[[light]]\nshape = \"rect\"\nposition = [0, 2, 0]\nsize = [1, 1]\n",
        &["light 1 (line 4)", "needs radiance"],
    ),
    (
        "light_point",
        "[[light]]\nshape = \"point\"\nposition = [0, 2, 0]\nradiance = [1, 1, 1]\n",
        &["light 1", "sphere"],
    ),
    (
        "light_looking_at_itself",
        "[[light]]\nshape = \"disk\"\nposition = [0, 2, 0]\nlook_at = [0, 2, 0]\n\
         radius = 1\nradiance = [1, 1, 1]\n",
        &["light 1", "look_at must differ from position"],
    ),
    (
        "prop_unknown_shape",
        "[[prop]]\nshape = \"cone\"\nposition = [0, 0, 0]\n",
        &["prop 1", "unknown 'cone'"],
    ),
    (
        "prop_bad_material",
        "[[prop]]\nshape = \"plane\"\nposition = [0, 0, 0]\nmaterial = \"velvet\"\n",
        &["prop 1", "velvet"],
    ),
    (
        "prop_mesh_missing",
        "[[prop]]\nshape = \"mesh\"\nposition = [0, 0, 0]\nfile = \"no-such-mesh.obj\"\n",
        &["prop 1", "no-such-mesh.obj"],
    ),
    (
        "environment_map_missing",
        "[environment]\nmap = \"no-such-map.exr\"\n",
        &["no-such-map.exr"],
    ),
    (
        "camera_on_its_target",
        "[camera]\nposition = [1, 2, 3]\nlook_at = [1, 2, 3]\n",
        &["camera.position and camera.look_at are the same point"],
    ),
    ("liquid_mode", "liquid = \"soup\"\n", &["soup"]),
    ("melp_set", "melp_set = \"both-ish\"\n", &["input.melp_set"]),
    (
        "thickness_unit",
        "[film]\nthickness_unit = \"furlong\"\n",
        &["furlong"],
    ),
];

#[test]
fn every_mistake_is_refused_before_the_particles_are_read() {
    for (name, scene, words) in CASES {
        let (code, err) = render(name, scene, &[]);
        assert_eq!(code, 2, "{name}: {err}");
        for w in *words {
            assert!(err.contains(w), "{name}: expected '{w}' in: {err}");
        }
        assert!(
            !err.contains("4000000000"),
            "{name}: the input was read: {err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{name}: one line: {err}");
    }
}

#[test]
fn a_memory_limit_does_not_read_the_input_before_the_scene_is_checked() {
    // --max-memory makes the render estimate its peak from the inputs' headers first.
    let (code, err) = render("limit", CASES[0].1, &["--max-memory", "1G"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("needs radiance"), "{err}");
}

#[test]
fn a_bad_scene_fails_before_the_first_frame_of_a_sequence() {
    let dir = tmp("seq");
    std::fs::create_dir_all(&dir).unwrap();
    for f in 0..2 {
        std::fs::copy(
            hostile(&format!("seq_{f}.ply")),
            dir.join(format!("f_{f:04}.ply")),
        )
        .unwrap();
    }
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[input]\ncloud = \"f_{:04}.ply\"\n[[prop]]\nshape = \"torus\"\nposition = [0, 0, 0]\n\
         radius = 1\nminor_radius = 2\n",
    )
    .unwrap();
    let out = dir.join("out_{:04}.png");
    let (code, _, err) = filmsplat(&[
        "render",
        &scene.to_string_lossy(),
        "--frames",
        "0..2",
        "-o",
        &out.to_string_lossy(),
        "-q",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("prop 1") && err.contains("minor_radius"),
        "{err}"
    );
    assert!(!err.contains("frame 0"), "no frame was read: {err}");
}

/// `input.clouds` with `input.sample` is refused: the sample would be drawn and the clouds
/// dropped without a word.
#[test]
fn clouds_and_a_sample_are_refused_not_one_dropped() {
    let input = hostile("clouds_and_sample.ply");
    let file = tmp("clouds_and_sample.toml");
    let text = format!(
        "[input]\nclouds = [\"{}\"]\nsample = \"bubble\"\n",
        input.file_name().unwrap().to_string_lossy()
    );
    std::fs::write(&file, text).unwrap();
    let out = tmp("clouds_and_sample.png");
    let (code, _, err) = filmsplat(&[
        "render",
        &file.to_string_lossy(),
        "-o",
        &out.to_string_lossy(),
        "--size",
        "16x12",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("either clouds or sample"), "{err}");
    assert!(!out.exists());
}
