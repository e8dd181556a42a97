//! Several inputs in one scene (`render A B`, `input.clouds`, `.pvd`), attribute views, and
//! their error paths.

mod cli_support;

use cli_support::{data, filmsplat, tmp};
use filmsplat::io::{ReadOptions, read_parts};

fn folder(name: &str) -> std::path::PathBuf {
    let d = tmp(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_pvd_collection_reads_every_data_set_of_its_first_timestep() {
    let d = folder("pvd");
    let vtu = data("fluid_250_particles.vtu");
    let enc = data("fluid_encoded_250_particles.vtu");
    let pvd = d.join("run.pvd");
    std::fs::write(
        &pvd,
        format!(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n\
             <DataSet timestep=\"0.5\" part=\"1\" file=\"{enc}\"/>\n\
             <DataSet timestep=\"0\" part=\"0\" file=\"{vtu}\"/>\n\
             <DataSet timestep=\"0\" part=\"1\" file=\"{enc}\"/>\n</Collection>\n</VTKFile>\n"
        ),
    )
    .unwrap();
    let parts = read_parts(&pvd, &ReadOptions::default()).unwrap();
    assert_eq!(
        parts.iter().map(|p| p.cloud.len()).collect::<Vec<_>>(),
        [250, 250]
    );
    let steps = filmsplat::io::pvd::timesteps(&pvd).unwrap();
    assert_eq!(
        steps.iter().map(|(t, f)| (*t, f.len())).collect::<Vec<_>>(),
        [(0.0, 2), (0.5, 1)]
    );
    // Not a collection, a data set without a file: one-line errors naming the file.
    std::fs::write(&pvd, "<VTKFile type=\"UnstructuredGrid\"></VTKFile>").unwrap();
    let e = read_parts(&pvd, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("run.pvd") && e.contains("Collection"), "{e}");
    std::fs::write(
        &pvd,
        "<VTKFile type=\"Collection\"><DataSet timestep=\"1\"/></VTKFile>",
    )
    .unwrap();
    let e = read_parts(&pvd, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("without a file"), "{e}");
}

#[test]
fn a_scene_file_lists_its_clouds() {
    let d = folder("clouds-scene");
    let scene = d.join("s.toml");
    let foam = data("melp/foam3/50");
    let shell = data("splishsplash_sphere_shell.ply");
    std::fs::write(
        &scene,
        format!("[input]\nclouds = [\"{foam}\", \"{shell}\"]\n[render]\npreset = \"preview\"\nwidth = 64\nheight = 48\n"),
    )
    .unwrap();
    let out = d.join("s.png");
    let (code, data, said) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{said}");
    assert!(data.is_empty(), "{data}");
    // Three bubbles and the shell (one duplicate position drawn once); the bubbles' three
    // shared walls are drawn once (312 + 497 + 444 particles of their second copies removed).
    assert!(said.contains("foam: 3 walls shared"), "{said}");
    assert!(
        said.contains(&format!("{} particles", 14_997 - 1_253 + 12_393)),
        "{said}"
    );
    // A scene file is rendered alone.
    let (code, _, err) = filmsplat(&[
        "render",
        scene.to_str().unwrap(),
        shell.as_str(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("s.toml") && err.contains("input.clouds"),
        "{err}"
    );
}

#[test]
fn attribute_views_colour_by_any_stored_attribute() {
    let d = folder("attribute-view");
    let snap = data("thin-film-sph/bursting_bubble/snapshot/100");
    let out = d.join("v.png");
    let run = |view: &str, extra: &[&str]| {
        let mut a = vec![
            "render",
            snap.as_str(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "96x64",
            "--view",
            view,
        ];
        a.extend_from_slice(extra);
        filmsplat(&a)
    };
    let (code, data, said) = run("attribute:v", &[]);
    assert_eq!(code, 0, "{said}");
    assert!(data.is_empty(), "{data}");
    assert!(said.contains("attribute view"), "{said}");
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    let (code, _, err) = run("attribute:vrt", &["--view-range", "-1,1"]);
    assert_eq!(code, 0, "{err}");
    // A name the particles do not have lists the ones they do; a bad range is refused.
    let (code, _, err) = run("attribute:nope", &[]);
    assert_eq!(code, 2);
    assert!(
        err.contains("no attribute 'nope'") && err.contains("vrt"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);
    let (code, _, err) = run("attribute:v", &["--view-range", "2,1"]);
    assert_eq!(code, 2);
    assert!(err.contains("MIN < MAX"), "{err}");
}

#[test]
fn a_folder_of_numbered_particle_files_is_refused_with_the_sequence_that_renders_it() {
    // MELP writes one VTK XML file per frame and set (e_/l_particles_0100.vtp, ...) into one
    // folder: no frame folder, so `render` refuses it, naming what it holds and the pattern.
    let d = folder("melp_run");
    for (set, n) in [("e", 7), ("l", 7), ("l", 8)] {
        let src = data(&format!("melp/bubble/{set}_particles_0100.vtp"));
        std::fs::copy(src, d.join(format!("{set}_particles_{n:04}.vtp"))).unwrap();
    }
    let dir = d.to_str().unwrap();
    let png = d.join("x.png");
    let (code, out, err) = filmsplat(&["render", dir, "-o", png.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty() && !png.exists());
    assert_eq!(err.lines().count(), 1, "{err}");
    let pattern = format!("{dir}/l_particles_{{:04}}.vtp");
    assert!(
        err.contains(dir) && err.contains("2 numbered particle files"),
        "{err}"
    );
    assert!(
        err.contains(&format!("'{pattern}' --frames 7..=8")),
        "{err}"
    );
    // The sequence it names renders both Lagrangian frames.
    let frames = format!("{dir}/f_{{}}.png");
    let (code, _, err) = filmsplat(&[
        "render", &pattern, "--frames", "7..=8", "-o", &frames, "--size", "32x24", "--spp", "1",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(d.join("f_7.png").exists() && d.join("f_8.png").exists());
    // A run's folder of numbered frame folders is named the same way.
    let run = data("thin-film-sph/bursting_bubble");
    let (code, _, err) = filmsplat(&["info", &run]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("'{run}/{{}}' --frames")), "{err}");
}
