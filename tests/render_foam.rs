//! A foam written one particle set per bubble (MELP's foam driver, tests/data/melp/foam3/50):
//! the wall two bubbles share is stored in both sets; it must be drawn as one film.
//!
//! The camera sits inside bubble 0 and looks at its wall with bubble 1, so the first film
//! every pixel meets is that wall (0.9 m away). The reference comes from the files alone: the
//! two copies' thickness near the line of sight.

mod cli_support;

use cli_support::{data, filmsplat, tmp};
use filmsplat::io::{ReadOptions, read_parts};
use glam::Vec3;

/// Inside bubble 0 (its particles' centroid).
const CAMERA: Vec3 = Vec3::new(0.08, 0.78, 0.01);
/// On the wall between bubbles 0 and 1.
const LOOK_AT: Vec3 = Vec3::new(0.9, 0.37, 0.0);
/// Vertical field of view of the test renders, degrees (the wall fills it).
const FOV: f32 = 24.0;

/// The median thickness (nm) of region `r`'s particles within the view cone, 0.6..1.2 m away.
fn copy_median(r: usize) -> f32 {
    let parts = read_parts(
        std::path::Path::new(&data("melp/foam3/50")),
        &ReadOptions::default(),
    )
    .unwrap();
    let c = &parts[r].cloud;
    let axis = (LOOK_AT - CAMERA).normalize();
    let half = (0.5 * FOV).to_radians().tan();
    let mut t: Vec<f32> = (0..c.len())
        .filter(|&i| {
            let v = c.positions[i] - CAMERA;
            let s = v.dot(axis);
            (0.6..1.2).contains(&s) && (v - s * axis).length() < half * s
        })
        .map(|i| c.thickness_nm.as_ref().unwrap()[i])
        .collect();
    assert!(t.len() > 10, "region {r}: {} particles in view", t.len());
    t.sort_by(f32::total_cmp);
    t[t.len() / 2]
}

/// Renders the foam at 1 spp, 48×48, from inside bubble 0 towards `look_at`; returns stderr
/// the notes and the EXR's (depth, thickness, hits) of the pixels that hit a film.
fn render(primitive: &str, look_at: Vec3, name: &str) -> (String, Vec<(f32, f32, f32)>) {
    render_fov(primitive, look_at, FOV, name)
}

/// [`render`] with a vertical field of view of `fov` degrees.
fn render_fov(
    primitive: &str,
    look_at: Vec3,
    fov: f32,
    name: &str,
) -> (String, Vec<(f32, f32, f32)>) {
    let out = tmp(&format!("foam-{name}-{primitive}.exr"));
    let v = |p: Vec3| format!("{},{},{}", p.x, p.y, p.z);
    let (code, data, said) = filmsplat(&[
        "render",
        &data("melp/foam3/50"),
        "-o",
        out.to_str().unwrap(),
        "--primitive",
        primitive,
        "--preset",
        "preview",
        "--size",
        "48x48",
        "--fov",
        &fov.to_string(),
        "--camera",
        &v(CAMERA),
        "--look-at",
        &v(look_at),
    ]);
    assert_eq!(code, 0, "{said}");
    assert!(data.is_empty(), "{data}");
    let l = filmsplat::image::read_exr(&out).unwrap();
    let (d, t, h) = (l.depth.unwrap(), l.thickness.unwrap(), l.hit_count.unwrap());
    let hits = (0..d.len())
        .filter(|&i| d[i] > 0.0)
        .map(|i| (d[i], t[i], h[i]))
        .collect();
    (said, hits)
}

/// The `q` quantile of `v`.
fn quantile(mut v: Vec<f32>, q: f32) -> f32 {
    v.sort_by(f32::total_cmp);
    v[((v.len() - 1) as f32 * q).round() as usize]
}

#[test]
fn a_shared_wall_is_one_film_with_one_thickness() {
    // The copies as stored: ≈ 590 nm in bubble 0's set, ≈ 385 nm in bubble 1's.
    let (h0, h1) = (copy_median(0), copy_median(1));
    assert!(h0 - h1 > 150.0, "{h0} {h1}");
    let mean = 0.5 * (h0 + h1);
    let gap = h0 - h1;
    for primitive in ["disk", "mls"] {
        let (said, px) = render(primitive, LOOK_AT, "wall");
        assert!(
            said.contains("foam: 3 walls shared by two bubbles drawn once"),
            "{said}"
        );
        // Every pixel meets the wall first (0.9 m away), not a film behind it.
        assert_eq!(px.len(), 48 * 48, "{primitive}");
        let depth: Vec<f32> = px.iter().map(|p| p.0).collect();
        assert!(
            quantile(depth, 0.98) < 1.0,
            "{primitive}: rays went through"
        );
        // One thickness, the copies' mean: not a patchwork of the two (which spreads over
        // half their difference), nor one copy.
        let t: Vec<f32> = px.iter().map(|p| p.1).collect();
        let (p2, p50, p98) = (
            quantile(t.clone(), 0.02),
            quantile(t.clone(), 0.5),
            quantile(t, 0.98),
        );
        assert!(
            (p50 - mean).abs() < 0.1 * gap,
            "{primitive}: median {p50} nm, copies {h0} | {h1}"
        );
        assert!(
            p98 - p2 < 0.2 * gap,
            "{primitive}: {p2}..{p98} nm, copies {h0} | {h1}"
        );
    }
}

#[test]
fn a_shared_wall_is_one_film_out_to_where_its_copies_part() {
    // Near the wall's rim, 0.47–0.6 m from its middle (its Plateau border is ≈ 0.65 m out),
    // where MELP's stored normals lean 20–30° off the wall while both copies still lie on it,
    // 6 mm apart: one thickness there too, not the patchwork of both copies (which the wall
    // test, judging the copies by their stored normals, left there: 397–529 nm). The removed
    // copy keeps its last row on the wall, against cracks where the copies part: 437–492 nm
    // (disks); the MLS surface, which blends that row as its own sheet: 390–493 (main 391–555).
    let (h0, h1) = (copy_median(0), copy_median(1));
    let gap = h0 - h1;
    let look_at = Vec3::new(0.905, 0.441, 0.53);
    for (primitive, spread) in [("disk", 0.3), ("mls", 0.55)] {
        let (_, px) = render_fov(primitive, look_at, 8.0, "wall-edge");
        assert_eq!(px.len(), 48 * 48, "{primitive}");
        let t: Vec<f32> = px.iter().map(|p| p.1).collect();
        let (p2, p98) = (quantile(t.clone(), 0.02), quantile(t, 0.98));
        assert!(
            p98 - p2 < spread * gap,
            "{primitive}: {p2}..{p98} nm, copies {h0} | {h1}"
        );
    }
}

#[test]
fn a_shared_wall_blends_as_many_splats_as_a_single_film() {
    // Disks blended into the first crossing: through the wall as many as through bubble 0's
    // own outer film (two stacked copies would give twice as many).
    let med = |px: &[(f32, f32, f32)]| quantile(px.iter().map(|p| p.2).collect(), 0.5);
    let (_, wall) = render("disk", LOOK_AT, "hits-wall");
    let (_, outer) = render("disk", Vec3::new(-0.6, 1.2, 0.3), "hits-outer");
    let (w, o) = (med(&wall), med(&outer));
    assert!(w <= 1.5 * o, "wall {w} splats, single film {o}");
}

#[test]
fn a_melp_frames_eulerian_and_lagrangian_files_together_draw_one_set() {
    let (e, l) = (
        data("melp/bubble/e_particles_0100.vtp"),
        data("melp/bubble/l_particles_0100.vtp"),
    );
    let out = tmp("melp-sets.png");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "render",
            &e,
            &l,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "32x24",
            "--preset",
            "preview",
        ];
        args.extend_from_slice(extra);
        filmsplat(&args)
    };
    let (code, data, said) = run(&[]);
    assert_eq!(code, 0, "{said}");
    assert!(data.is_empty(), "{data}");
    let note = |s: &str| {
        s.lines()
            .filter(|l| l.contains("Eulerian (e_) and Lagrangian (l_)"))
            .count()
    };
    assert_eq!(note(&said), 1, "{said}");
    assert!(said.contains("19995 particles"), "{said}");
    let (_, _, said) = run(&["--melp-set", "eulerian"]);
    assert!(
        said.contains("1199 particles") && note(&said) == 1,
        "{said}"
    );
    let (_, _, said) = run(&["--melp-set", "both"]);
    assert!(said.contains("21194 particles"), "{said}");
    let (code, _, err) = run(&["--melp-set", "lagrange"]);
    assert_eq!(code, 2);
    assert!(err.contains("lagrangian, eulerian or both"), "{err}");
    // One set alone: no note.
    let (_, _, said) = filmsplat(&[
        "render",
        &l,
        "-o",
        out.to_str().unwrap(),
        "--size",
        "32x24",
        "--preset",
        "preview",
    ]);
    assert_eq!(note(&said), 0, "{said}");
}

#[test]
fn a_melp_foam_folder_says_in_one_line_that_it_draws_the_lagrangian_set() {
    // The folder holds both sets of every bubble (e_…_R and l_…_R); the film drawn is the
    // Lagrangian one, and the render says so once, as for a pair of .vtp files.
    let dir = data("melp/foam3/50");
    let out = tmp("melp-foam-set.png");
    let args = [
        "render",
        &dir,
        "-o",
        out.to_str().unwrap(),
        "--size",
        "32x24",
    ];
    let (code, stdout, said) = filmsplat(&[&args[..], &["--preset", "preview"]].concat());
    assert_eq!(code, 0, "{said}");
    assert!(stdout.is_empty(), "{stdout}");
    let lines = |s: &str, what: &str| s.lines().filter(|l| l.contains(what)).count();
    assert_eq!(
        lines(&said, "Eulerian (e_) and Lagrangian (l_)"),
        1,
        "{said}"
    );
    assert!(said.contains("drawing the Lagrangian set only"), "{said}");
    // Another set asked for: the folder is still read as its Lagrangian set, and says so once.
    let eulerian = [
        &args[..],
        &["--preset", "preview", "--melp-set", "eulerian"],
    ]
    .concat();
    let (code, _, said) = filmsplat(&eulerian);
    assert_eq!(code, 0, "{said}");
    assert_eq!(lines(&said, "read as its Lagrangian set"), 1, "{said}");
    assert_eq!(
        lines(&said, "Eulerian (e_) and Lagrangian (l_)"),
        0,
        "{said}"
    );
    // info: one row for the Eulerian files, not one per file.
    let (code, info, err) = filmsplat(&["info", &dir]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(lines(&info, "Eulerian particles"), 1, "{info}");
    assert!(info.contains("e_*_R (12 files)"), "{info}");
}
