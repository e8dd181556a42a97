//! Image properties of small scenes with known answers.

use filmsplat::geometry::{DiskGeometry, FilmGeometry, Primitive};
use filmsplat::optics::FilmFresnel;
use filmsplat::render::{
    Camera, Environment, FilmShader, RenderSettings, Scene, ShadingMode, render,
};
use filmsplat::samples::{BubbleParams, bubble};
use filmsplat::spectrum::{
    SpectralWeights, WavelengthStrategy, film_rgb_reference, reference_grid_nm,
};
use glam::Vec3;

fn settings(w: usize, h: usize, spp: u32) -> RenderSettings {
    RenderSettings {
        width: w,
        height: h,
        spp,
        ..RenderSettings::default()
    }
}

/// One big disk of `thickness` nm in the z = 0 plane, seen head-on from +z.
fn big_disk_scene(thickness: f32, env: Environment) -> Scene {
    let geometry = DiskGeometry::build(&[Vec3::ZERO], &[Vec3::Z], &[10.0], &[thickness]).unwrap();
    Scene {
        geometry: geometry.into(),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 10.0),
        environment: env,
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Default::default(),
    }
}

fn front_white_back_black() -> Environment {
    Environment::Hemispheres {
        axis: Vec3::Z,
        toward: Vec3::ONE,
        away: Vec3::ZERO,
    }
}

#[test]
fn a_disk_seen_head_on_has_the_colour_of_its_film() {
    for thickness in [120.0f32, 300.0, 550.0, 900.0] {
        let want = film_rgb_reference(1.0, thickness as f64, 1.33, &reference_grid_nm());
        let scene = big_disk_scene(thickness, front_white_back_black());
        for (mode, tol) in [(ShadingMode::Lut, 3e-3), (ShadingMode::Rgb, 4e-3)] {
            let shader = FilmShader::new(1.33, mode, 32, WavelengthStrategy::Jittered);
            let out = render(&scene, &shader, &settings(9, 9, 64)).unwrap();
            let c = out.rgb[4 * 9 + 4];
            for k in 0..3 {
                assert!(
                    (c[k] as f64 - want[k]).abs() < tol,
                    "{mode} h={thickness}: pixel {c:?} vs film --rgb {want:?}"
                );
            }
            assert_eq!(out.alpha[40], 1.0);
            assert!((out.thickness[40] - thickness).abs() < 1e-3);
            assert!((out.depth[40] - 5.0).abs() < 1e-3);
        }
    }
}

#[test]
fn a_white_furnace_makes_a_lossless_film_vanish() {
    let scene = bubble_scene(Primitive::Disk, Environment::Uniform(Vec3::ONE));
    for mode in [ShadingMode::Lut, ShadingMode::Rgb] {
        let shader = FilmShader::new(1.33, mode, 8, WavelengthStrategy::Hero);
        let out = render(&scene, &shader, &settings(32, 24, 2)).unwrap();
        let hit = out.alpha.iter().filter(|a| **a > 0.0).count();
        assert!(
            hit > 200,
            "the bubble should cover much of the frame: {hit}"
        );
        for c in &out.rgb {
            assert!((*c - Vec3::ONE).abs().max_element() < 1e-4, "{mode}: {c:?}");
        }
    }
}

/// Spectral transport conserves energy as the RGB modes do: in a uniform white environment a
/// lossless film vanishes. Every pixel has the colour the empty environment has under the same
/// camera samples (the films draw no random numbers), within 1e-4. With stratified
/// (white-balanced) wavelengths that colour is white in every pixel to within Smits' fit of
/// white (|basis − 1| ≤ 8e-4 over 380–720 nm), 2e-3; with jittered ones each sample's white
/// is noisy and only the frame mean is white, within 2e-2.
#[test]
fn a_white_furnace_makes_a_lossless_film_vanish_in_spectral_transport() {
    let scene = bubble_scene(Primitive::Disk, Environment::Uniform(Vec3::ONE));
    let mut empty = bubble_scene(Primitive::Disk, Environment::Uniform(Vec3::ONE));
    empty.geometry = DiskGeometry::build(&[], &[], &[], &[]).unwrap().into();
    for strategy in [WavelengthStrategy::Stratified, WavelengthStrategy::Jittered] {
        let shader = FilmShader::new(1.33, ShadingMode::Spectral, 16, strategy);
        let out = render(&scene, &shader, &settings(32, 24, 2)).unwrap();
        let env = render(&empty, &shader, &settings(32, 24, 2)).unwrap();
        let hit = out.alpha.iter().filter(|a| **a > 0.0).count();
        assert!(
            hit > 200,
            "the bubble should cover much of the frame: {hit}"
        );
        for (c, e) in out.rgb.iter().zip(&env.rgb) {
            assert!(
                (*c - *e).abs().max_element() < 1e-4,
                "{strategy}: film {c} vs environment {e}"
            );
            if strategy == WavelengthStrategy::Stratified {
                assert!(
                    (*c - Vec3::ONE).abs().max_element() < 2e-3,
                    "{strategy}: {c}"
                );
            }
        }
        let mean = out.rgb.iter().copied().sum::<Vec3>() / out.rgb.len() as f32;
        assert!(
            (mean - Vec3::ONE).abs().max_element() < 2e-2,
            "{strategy}: mean {mean}"
        );
    }
}

/// A film seen from its back (camera behind it, environment mirrored) looks as from its front:
/// the transport hands the optics |cos θ| and mirrors about the normal facing the ray. Pixels
/// agree with their mirror images across the vertical axis, and the centre has the film's
/// normal-incidence colour.
#[test]
fn a_disk_seen_from_behind_looks_as_from_the_front() {
    let shader = FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered);
    for thickness in [120.0f32, 550.0] {
        let front = big_disk_scene(thickness, front_white_back_black());
        let mut back = big_disk_scene(
            thickness,
            Environment::Hemispheres {
                axis: Vec3::NEG_Z,
                toward: Vec3::ONE,
                away: Vec3::ZERO,
            },
        );
        back.camera = Camera::look_at(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 10.0);
        let a = render(&front, &shader, &settings(9, 9, 1)).unwrap();
        let b = render(&back, &shader, &settings(9, 9, 1)).unwrap();
        for y in 0..9 {
            for x in 0..9 {
                let (p, q) = (a.rgb[y * 9 + x], b.rgb[y * 9 + 8 - x]);
                assert!(
                    (p - q).abs().max_element() < 1e-5,
                    "h={thickness} ({x}, {y}): {p} vs {q}"
                );
            }
        }
        let want = film_rgb_reference(1.0, thickness as f64, 1.33, &reference_grid_nm());
        let c = b.rgb[4 * 9 + 4];
        for k in 0..3 {
            assert!(
                (c[k] as f64 - want[k]).abs() < 3e-3,
                "h={thickness}: {c} vs {want:?}"
            );
        }
    }
}

#[test]
fn renders_are_deterministic_for_a_seed_and_independent_of_threads() {
    let scene = big_disk_scene(400.0, Environment::Studio(Default::default()));
    let shader = FilmShader::new(1.33, ShadingMode::Rgb, 8, WavelengthStrategy::Jittered);
    let s = RenderSettings {
        seed: 7,
        ..settings(24, 16, 4)
    };
    let a = render(&scene, &shader, &s).unwrap();
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let b = one_thread.install(|| render(&scene, &shader, &s).unwrap());
    assert_eq!(a.rgb, b.rgb);
    let c = render(
        &scene,
        &shader,
        &RenderSettings {
            seed: 8,
            ..s.clone()
        },
    )
    .unwrap();
    assert_ne!(a.rgb, c.rgb, "another seed jitters differently");
}

#[test]
fn overlapping_splats_make_one_seamless_film() {
    // A flat film of jittered, overlapping disks with a thickness gradient along x, seen
    // head-on: every pixel must show the colour of the analytic thickness at that point — no
    // seams where splats start or stop overlapping, and no double application of the film.
    let mut positions = Vec::new();
    let mut thickness = Vec::new();
    let mut state = 12345u64;
    let mut rnd = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let h_of = |x: f32| 200.0 + 300.0 * (x + 1.5) / 3.0;
    let spacing = 0.05;
    for i in 0..70 {
        for j in 0..70 {
            let x = -1.75 + i as f32 * spacing + 0.3 * spacing * (rnd() - 0.5);
            let y = -1.75 + j as f32 * spacing + 0.3 * spacing * (rnd() - 0.5);
            positions.push(Vec3::new(x, y, 0.0));
            thickness.push(h_of(x));
        }
    }
    let n = positions.len();
    let geometry = DiskGeometry::build(
        &positions,
        &vec![Vec3::Z; n],
        &vec![1.5 * spacing; n],
        &thickness,
    )
    .unwrap();
    let scene = Scene {
        geometry: geometry.into(),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 20.0), Vec3::ZERO, Vec3::Y, 7.0),
        environment: front_white_back_black(),
        layer_skip: 0.5 * spacing,
        epsilon: 1e-5,
        staging: Default::default(),
    };
    let shader = FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered);
    let (w, h) = (64, 48);
    let out = render(&scene, &shader, &settings(w, h, 1)).unwrap();
    let grid: Vec<f32> = (360..=830).map(|l| l as f32).collect();
    let weights = SpectralWeights::new(&grid);
    let mut worst = 0.0f32;
    let mut multi = 0;
    for py in 0..h {
        for px in 0..w {
            let k = py * w + px;
            assert_eq!(out.alpha[k], 1.0, "hole at {px},{py}");
            if out.hits[k] > 1.0 {
                multi += 1;
            }
            // The point this pixel sees on the plane z = 0.
            let ray = scene.camera.ray(
                (px as f32 + 0.5) / w as f32,
                (py as f32 + 0.5) / h as f32,
                w as f32 / h as f32,
            );
            let p = ray.origin + ray.dir * (-ray.origin.z / ray.dir.z);
            let cos_i = ray.dir.z.abs();
            let want = weights.film_reflectance_rgb(&FilmFresnel::new(cos_i, 1.33), h_of(p.x));
            for (c, w) in want.iter().enumerate() {
                worst = worst.max((out.rgb[k][c] - w).abs());
            }
        }
    }
    assert!(
        multi > w * h / 2,
        "most pixels should blend several splats ({multi})"
    );
    // Blending by jittered splat centres gives the thickness to within a few nm, ~0.005 in colour.
    assert!(
        worst < 0.012,
        "worst colour deviation from the analytic film: {worst}"
    );
}

#[test]
fn no_nan_or_inf_reaches_the_image_at_extremes() {
    for (thickness, ior) in [
        (0.0f32, 1.0f32),
        (0.0, 1.33),
        (100_000.0, 1.33),
        (1e-6, 3.0),
    ] {
        let scene = big_disk_scene(thickness, Environment::Studio(Default::default()));
        let shader = FilmShader::new(ior, ShadingMode::Rgb, 8, WavelengthStrategy::Jittered);
        let out = render(&scene, &shader, &settings(16, 12, 2)).unwrap();
        // Finite and bounded. (Single samples of the spectral estimator may dip slightly below
        // zero in one channel, as any unbiased estimate of an out-of-gamut colour can.)
        let bad: Vec<_> = out
            .rgb
            .iter()
            .filter(|c| !(c.is_finite() && c.abs().max_element() < 10.0))
            .collect();
        assert!(
            bad.is_empty(),
            "h {thickness} ior {ior}: {:?}",
            &bad[..bad.len().min(3)]
        );
        assert!(
            out.depth
                .iter()
                .chain(&out.thickness)
                .chain(&out.hits)
                .all(|v| v.is_finite())
        );
    }
    let scene = big_disk_scene(300.0, Environment::Uniform(Vec3::ONE));
    let shader = FilmShader::new(1.33, ShadingMode::Lut, 8, WavelengthStrategy::Jittered);
    assert!(render(&scene, &shader, &settings(0, 10, 1)).is_err());
    assert!(render(&scene, &shader, &settings(10, 10, 0)).is_err());
}

/// The 4000-particle bubble sample drawn as `primitive`, framed by a camera at 4:3.
fn bubble_scene(primitive: Primitive, env: Environment) -> Scene {
    let cloud = bubble(&BubbleParams {
        particles: 4000,
        ..BubbleParams::default()
    });
    let geometry = FilmGeometry::particles(
        primitive,
        &cloud.positions,
        cloud.normals.as_ref().unwrap(),
        cloud.radius.as_ref().unwrap(),
        cloud.thickness_nm.as_ref().unwrap(),
    )
    .unwrap();
    Scene {
        geometry,
        camera: Camera::frame(
            Vec3::ZERO,
            1.05,
            Vec3::new(0.3, 0.2, 1.0),
            Vec3::Y,
            40.0,
            4.0 / 3.0,
        ),
        environment: env,
        layer_skip: 0.005,
        epsilon: 1e-5,
        staging: Default::default(),
    }
}

/// Russian roulette in the ray tree traces far fewer rays through a sphere bubble and keeps the
/// image's mean (it is unbiased: over four seeds the means agree to within 1.5%, where
/// leaving out the 1/q weight darkens the image by 4%); in a white furnace, where every branch
/// sees what it would see escaping, the control variate makes it exact (plain roulette, which
/// returns black for a branch it drops, is not).
#[test]
fn russian_roulette_keeps_the_mean_with_fewer_rays() {
    let shader = FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered);
    let scene = bubble_scene(Primitive::Sphere, Environment::Studio(Default::default()));
    let run = |roulette: f32| {
        let (mut sum, mut rays) = (Vec3::ZERO, 0u64);
        let mut first = Vec::new();
        for seed in 0..4 {
            let s = RenderSettings {
                roulette,
                seed,
                ..settings(32, 24, 16)
            };
            let out = render(&scene, &shader, &s).unwrap();
            sum += out.rgb.iter().copied().sum::<Vec3>() / out.rgb.len() as f32;
            rays += out.rays;
            if seed == 0 {
                first = out.rgb;
            }
        }
        (sum / 4.0, rays, first)
    };
    let (tree, tree_rays, tree_img) = run(0.0);
    let (rr, rr_rays, rr_img) = run(0.25);
    assert!(
        (rr_rays as f64) < 0.3 * tree_rays as f64,
        "roulette traced {rr_rays} rays, the tree {tree_rays}"
    );
    assert!(
        ((tree - rr) / tree).abs().max_element() < 0.015,
        "mean {tree} (tree) against {rr} (roulette)"
    );
    assert_ne!(tree_img, rr_img, "roulette follows some branches at random");

    let furnace = bubble_scene(Primitive::Sphere, Environment::Uniform(Vec3::ONE));
    let s = RenderSettings {
        roulette: 0.25,
        ..settings(32, 24, 4)
    };
    let out = render(&furnace, &shader, &s).unwrap();
    for c in &out.rgb {
        assert!((*c - Vec3::ONE).abs().max_element() < 1e-4, "{c:?}");
    }
}
