//! CLI: studio scenes (lights, props, lens, grading) render; their errors name key and line.

mod cli_support;
use cli_support::{filmsplat, tmp};

const STUDIO: &str = r#"[input]
sample = "bubble"
particles = 3000

[camera]
position = [0.0, 0.3, 5.0]
look_at = [0.0, -0.2, 0.0]
aperture = 0.05

[[light]]
shape = "rect"
position = [-2.0, 3.0, 2.0]
size = [1.5, 1.0]
radiance = [5.0, 5.0, 5.0]

[[light]]
shape = "sphere"
position = [2.0, 2.0, 1.0]
radius = 0.2
luminance = 800
colour = [1.0, 0.8, 0.6]

[[prop]]
shape = "plane"
position = [0.0, -1.3, 0.0]
material = "glossy"

[[prop]]
shape = "torus"
position = [0.0, -1.1, 0.0]
radius = 0.5
minor_radius = 0.03
material = "metal"
roughness = 0.0

[[prop]]
shape = "box"
position = [1.5, -1.0, -1.0]
size = [0.5, 0.6, 0.5]

[[prop]]
shape = "cylinder"
position = [-1.5, -1.3, -1.0]
height = 0.8
radius = 0.2

[[prop]]
shape = "sphere"
position = [-1.0, -1.0, 1.0]
radius = 0.3

[output]
white_balance = 5000
contrast = 1.1
saturation = 1.2
"#;

fn write(name: &str, text: &str) -> String {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn a_studio_scene_renders_in_every_shading_mode() {
    let scene = write("studio.toml", STUDIO);
    for mode in ["lut", "rgb", "spectral"] {
        let out = tmp(&format!("studio-{mode}.png"));
        let (code, _, err) = filmsplat(&[
            "render",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64x48",
            "--spp",
            "2",
            "--shading",
            mode,
            "--wavelengths",
            "8",
            "--light-samples",
            "2",
            "-q",
        ]);
        assert_eq!(code, 0, "{mode}: {err}");
        assert!(out.exists());
    }
}

#[test]
fn studio_errors_name_the_entry_line_and_key() {
    let with = |from: &str, to: &str| STUDIO.replacen(from, to, 1);
    let cases = [
        (
            with(
                "shape = \"sphere\"\nposition = [2.0",
                "shape = \"point\"\nposition = [2.0",
            ),
            vec!["light 2 (line 17)", "point", "sphere"],
        ),
        (
            with("size = [0.5, 0.6, 0.5]", "sise = [0.5, 0.6, 0.5]"),
            vec!["line 39", "sise"],
        ),
        (
            with("minor_radius = 0.03", "minor_radius = 0.7"),
            vec!["prop 2 (line 29)", "minor_radius"],
        ),
        (
            with("material = \"glossy\"", "material = \"velvet\""),
            vec!["prop 1", "velvet"],
        ),
        (
            with("radiance = [5.0, 5.0, 5.0]", ""),
            vec!["light 1 (line 11)", "radiance"],
        ),
        (with("aperture = 0.05", "aperture = -1"), vec!["aperture"]),
        (
            with("luminance = 800", "luminance = 800\ntemperature = 3000"),
            vec!["light 2 (line 17)", "temperature"],
        ),
        (
            with("white_balance = 5000", "white_balance = 100"),
            vec!["white_balance"],
        ),
    ];
    for (i, (text, needles)) in cases.iter().enumerate() {
        let scene = write(&format!("bad-studio-{i}.toml"), text);
        let out = tmp(&format!("bad-studio-{i}.png"));
        let (code, _, err) = filmsplat(&[
            "render",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "16x16",
        ]);
        assert_eq!(code, 2, "case {i}: {err}");
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "case {i}: {err}");
        for n in needles {
            assert!(lines[0].contains(n), "case {i}: '{n}' not in {err}");
        }
        assert!(!out.exists());
    }
    // Spectral transport carries at most 16 wavelengths.
    let scene = write("ok-studio.toml", STUDIO);
    let (code, _, err) = filmsplat(&[
        "render",
        &scene,
        "--shading",
        "spectral",
        "--wavelengths",
        "32",
        "--size",
        "8x8",
        "-o",
        tmp("never.png").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("wavelengths") && err.contains("16"), "{err}");
}

#[test]
fn mesh_props_render_and_bad_meshes_name_file_and_line() {
    let cube = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
                f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    write("cube.obj", cube);
    write("broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    let scene = |file: &str| {
        format!(
            "[input]\nsample = \"bubble\"\nparticles = 2000\n\n[[prop]]\nshape = \"mesh\"\n\
             file = \"{file}\"\nposition = [1.6, -0.8, 0.0]\nscale = 0.3\nmaterial = \"metal\"\n"
        )
    };
    // An OBJ and a PLY mesh (faces; the same readers as compared meshes) both work as props.
    let ply = tmp("ball.ply");
    let (code, _, err) = filmsplat(&[
        "sample",
        "bubble-mesh",
        "--subdivisions",
        "1",
        "-o",
        ply.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for (name, file) in [("mesh", "cube.obj"), ("mesh-ply", ply.to_str().unwrap())] {
        let ok = write(&format!("{name}.toml"), &scene(file));
        let out = tmp(&format!("{name}.png"));
        let (code, _, err) = filmsplat(&[
            "render",
            &ok,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "48x32",
            "--spp",
            "1",
            "-q",
        ]);
        assert_eq!(code, 0, "{file}: {err}");
        assert!(out.exists(), "{file}");
    }
    for (file, needles) in [
        (
            "broken.obj",
            vec!["prop 1 (line 6)", "broken.obj", "line 3", "out of range"],
        ),
        ("missing.obj", vec!["prop 1 (line 6)", "missing.obj"]),
    ] {
        let bad = write("bad-mesh.toml", &scene(file));
        let (code, _, err) = filmsplat(&["render", &bad, "-o", tmp("x.png").to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert_eq!(
            err.lines().filter(|l| !l.trim().is_empty()).count(),
            1,
            "{err}"
        );
        for n in needles {
            assert!(err.contains(n), "'{n}' not in {err}");
        }
    }
}
