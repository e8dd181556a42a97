//! Statistical checks of the noisy estimators, as Mitsuba's test suite does: each estimator
//! renders a tiny known scene many times with different seeds; every pixel's mean and its
//! variance over those runs are compared with a reference (the deterministic or lower-variance
//! estimator of the same integral, also with its own runs) by a two-sample z-score. A biased
//! estimator moves the means; an unbiased one keeps every |z| within a Bonferroni bound and
//! the pooled z (all pixels' z summed over √n) near zero. Seeds are fixed, so a result never
//! changes between runs. Checked by breaking each estimator (see the commit message).

use filmsplat::geometry::{DiskGeometry, FilmGeometry, Shape, SphereGeometry};
use filmsplat::render::{
    AreaLight, Camera, Environment, FilmShader, LightShape, Material, Prop, Props, RenderSettings,
    Scene, ShadingMode, Staging, render,
};
use filmsplat::samples::{BubbleParams, bubble};
use filmsplat::spectrum::WavelengthStrategy;
use glam::Vec3;

/// Image size of every check: 16×12 pixels, 3 channels each.
const W: usize = 16;
const H: usize = 12;
/// Largest |z| a pixel channel may show. Over ~600 channels, a two-sided normal tail beyond
/// 5.5 has probability 4e-8 each (2e-5 in all); the variances are estimated from 24 runs,
/// whose heavier t tails still keep a false alarm below ~1e-3 for the whole test.
const Z_PIXEL: f64 = 5.5;
/// Largest |pooled z| (Σz/√n): the test that sees a small bias shared by many pixels.
const Z_POOLED: f64 = 4.5;

/// Per-pixel, per-channel mean of `runs` renders (seeds `seed0..`) and the variance of that
/// mean (sample variance / runs).
fn pixel_stats(
    scene: &Scene,
    shader: &FilmShader,
    settings: &RenderSettings,
    runs: u64,
    seed0: u64,
) -> (Vec<f64>, Vec<f64>) {
    let n = W * H * 3;
    let (mut sum, mut sq) = (vec![0.0f64; n], vec![0.0f64; n]);
    for k in 0..runs {
        let s = RenderSettings {
            width: W,
            height: H,
            seed: seed0 + k,
            ..settings.clone()
        };
        let out = render(scene, shader, &s).unwrap();
        for (i, c) in out.rgb.iter().enumerate() {
            for (j, v) in c.to_array().into_iter().enumerate() {
                sum[3 * i + j] += v as f64;
                sq[3 * i + j] += (v as f64).powi(2);
            }
        }
    }
    let r = runs as f64;
    let mean: Vec<f64> = sum.iter().map(|s| s / r).collect();
    let var = sq
        .iter()
        .zip(&mean)
        .map(|(q, m)| ((q / r - m * m) * r / (r - 1.0)).max(0.0) / r)
        .collect();
    (mean, var)
}

/// Asserts two estimates of the same image agree pixel by pixel: |z| ≤ [`Z_PIXEL`] where
/// z = (a − b − allowance)/√(var a + var b) (`allowance`: a known systematic difference the
/// reference may have, absolute), and the pooled z within [`Z_POOLED`]. Returns the pooled z.
fn assert_same_mean(
    what: &str,
    a: &(Vec<f64>, Vec<f64>),
    b: &(Vec<f64>, Vec<f64>),
    allowance: f64,
) -> f64 {
    let (mut pooled, mut n, mut worst) = (0.0, 0usize, (0.0f64, 0usize));
    for i in 0..a.0.len() {
        let d = a.0[i] - b.0[i];
        let d = d.signum() * (d.abs() - allowance).max(0.0);
        let sd = (a.1[i] + b.1[i]).sqrt();
        if sd < 1e-9 {
            assert!(
                d.abs() < 1e-6,
                "{what}: pixel {} channel {}: {} vs {} with no noise",
                i / 3,
                i % 3,
                a.0[i],
                b.0[i]
            );
            continue;
        }
        let z = d / sd;
        if z.abs() > worst.0.abs() {
            worst = (z, i);
        }
        pooled += z;
        n += 1;
    }
    let pooled = pooled / (n as f64).sqrt();
    let i = worst.1;
    eprintln!(
        "{what}: {n} noisy channels, worst z {:.2} (pixel {}), pooled z {pooled:.2}",
        worst.0,
        i / 3
    );
    assert!(
        n > W * H,
        "{what}: only {n} noisy pixel channels; the scene tests nothing"
    );
    assert!(
        worst.0.abs() <= Z_PIXEL,
        "{what}: pixel {} channel {}: {:.5} vs {:.5}, z = {:.2}",
        i / 3,
        i % 3,
        a.0[i],
        b.0[i],
        worst.0
    );
    assert!(
        pooled.abs() <= Z_POOLED,
        "{what}: pooled z = {pooled:.2}: a bias shared by the pixels"
    );
    pooled
}

fn lut() -> FilmShader {
    FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered)
}

/// A bubble of 600 overlapping sphere films (every sphere two film crossings: long ray trees)
/// under a sky brighter above than below, filling the view.
fn sphere_bubble() -> Scene {
    let c = bubble(&BubbleParams {
        particles: 600,
        radius: 1.0,
        time: 0.0,
        seed: 3,
    });
    let radii = c.radius.as_ref().unwrap();
    let h = c.thickness_nm.as_ref().unwrap();
    let g = SphereGeometry::build(&c.positions, &[], radii, h).unwrap();
    Scene {
        geometry: FilmGeometry::from(g),
        camera: Camera::look_at(Vec3::new(0.0, 0.3, 3.2), Vec3::ZERO, Vec3::Y, 40.0),
        environment: Environment::Hemispheres {
            axis: Vec3::new(0.2, 1.0, 0.1).normalize(),
            toward: Vec3::new(1.0, 0.9, 0.7),
            away: Vec3::new(0.05, 0.1, 0.2),
        },
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging::default(),
    }
}

/// The graded film of [`graded_film`] in front of a white diffuse wall (behind the camera,
/// facing the film), lit from beyond the film; the sky toward the wall is black. Whatever the
/// film reflects comes from the wall, while a pruned reflected branch's escape view is the
/// black sky: the control variate does not hide a wrongly weighted roulette here.
fn film_before_a_wall() -> Scene {
    let mut scene = graded_film();
    scene.environment = Environment::Hemispheres {
        axis: Vec3::NEG_Z,
        toward: Vec3::new(1.0, 0.9, 0.8),
        away: Vec3::ZERO,
    };
    let wall = Prop {
        shape: Shape::Plane {
            point: Vec3::new(0.0, 0.0, 3.0),
            normal: Vec3::NEG_Z,
        },
        material: Material::Diffuse {
            albedo: Vec3::splat(0.8),
        },
    };
    scene.staging.props = Props::new(vec![wall], 1e-5);
    scene
}

/// Russian roulette (with the escape view as control variate) against the full ray tree: the
/// same mean at every pixel, on a bubble of spheres (long trees; threshold 0.2) and on a film
/// whose reflections show a wall (every reflected branch plays; threshold 0.5).
#[test]
fn russian_roulette_is_unbiased_per_pixel() {
    for (name, scene, threshold) in [
        ("sphere bubble", sphere_bubble(), 0.2),
        ("film before a wall", film_before_a_wall(), 0.5),
    ] {
        let base = RenderSettings {
            spp: 4,
            max_depth: 10,
            min_weight: 1e-5,
            ..RenderSettings::default()
        };
        let full = pixel_stats(&scene, &lut(), &base, 24, 1000);
        let rr = RenderSettings {
            roulette: threshold,
            ..base.clone()
        };
        let played = pixel_stats(&scene, &lut(), &rr, 24, 2000);
        assert_same_mean(
            &format!("{name}: roulette {threshold} vs full tree"),
            &played,
            &full,
            0.0,
        );
    }
}

/// A glossy ground under a disk light and a two-tone sky, seen from above; one thin film disk
/// floats between them, so light reaches the ground both directly and through the film.
fn lit_ground() -> Scene {
    let film =
        DiskGeometry::build(&[Vec3::new(0.3, 0.8, 0.0)], &[Vec3::Y], &[0.5], &[350.0]).unwrap();
    let light = AreaLight {
        shape: LightShape::Disk {
            centre: Vec3::new(0.8, 1.5, 0.3),
            normal: Vec3::new(-0.3, -1.0, 0.0).normalize(),
            radius: 0.8,
        },
        radiance: Vec3::new(2.0, 1.5, 1.0),
        blackbody: None,
    };
    let ground = Prop {
        shape: Shape::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        material: Material::Glossy {
            albedo: Vec3::splat(0.7),
            roughness: 0.5,
        },
    };
    Scene {
        geometry: film.into(),
        camera: Camera::look_at(Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0),
        environment: Environment::Hemispheres {
            axis: Vec3::new(0.3, 1.0, 0.2).normalize(),
            toward: Vec3::new(0.3, 0.4, 0.6),
            away: Vec3::ZERO,
        },
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging {
            lights: vec![light.into()],
            props: Props::new(vec![ground], 1e-5),
            ..Staging::default()
        },
    }
}

/// Light sampling with MIS (next-event estimation: one sample per light, environment and
/// material, weighted by the balance heuristic) against material sampling alone, whose mean is
/// right by construction: the same mean at every pixel, and less noise.
#[test]
fn light_sampling_with_mis_is_unbiased_per_pixel() {
    let scene = lit_ground();
    let nee = RenderSettings {
        spp: 4,
        ..RenderSettings::default()
    };
    let bsdf = RenderSettings {
        spp: 16,
        next_event: false,
        ..RenderSettings::default()
    };
    let a = pixel_stats(&scene, &lut(), &nee, 24, 3000);
    let b = pixel_stats(&scene, &lut(), &bsdf, 24, 4000);
    assert_same_mean("light sampling + MIS vs material sampling", &a, &b, 0.0);
    // Per sample, light sampling is the less noisy (4× fewer samples, less variance of the mean).
    let total = |v: &[f64]| v.iter().sum::<f64>();
    assert!(
        total(&a.1) < 4.0 * total(&b.1),
        "MIS: {} vs {}",
        total(&a.1),
        4.0 * total(&b.1)
    );
}

/// One tilted film of graded thickness (a bubble's slice, 100–1000 nm) under a two-tone grey
/// sky: its colours are the whole interference sequence.
fn graded_film() -> Scene {
    let n = 400;
    let (mut pos, mut nrm, mut rad, mut h) = (vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let (x, y) = ((i % 20) as f32 / 19.0 - 0.5, (i / 20) as f32 / 19.0 - 0.5);
        pos.push(Vec3::new(x, y, 0.0));
        nrm.push(Vec3::new(0.0, 0.3, 1.0).normalize());
        rad.push(0.05);
        h.push(100.0 + 900.0 * (x + 0.5) * (y + 0.5).sqrt());
    }
    Scene {
        geometry: DiskGeometry::build(&pos, &nrm, &rad, &h).unwrap().into(),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 30.0),
        environment: Environment::Hemispheres {
            axis: Vec3::new(0.0, 0.4, 1.0).normalize(),
            toward: Vec3::splat(0.9),
            away: Vec3::splat(0.1),
        },
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging::default(),
    }
}

/// Spectral sampling (jittered, stratified and hero wavelengths, 4 a sample, carried through
/// the transport or reduced at the hit) against the colour table integrated at 1 nm: the same
/// mean at every pixel, up to the table's documented error (2e-3).
#[test]
fn spectral_sampling_is_unbiased_per_pixel() {
    let scene = graded_film();
    let settings = RenderSettings {
        spp: 4,
        ..RenderSettings::default()
    };
    let table = pixel_stats(&scene, &lut(), &settings, 24, 5000);
    for (mode, strategy) in [
        (ShadingMode::Spectral, WavelengthStrategy::Jittered),
        (ShadingMode::Spectral, WavelengthStrategy::Hero),
        (ShadingMode::Rgb, WavelengthStrategy::Jittered),
    ] {
        let shader = FilmShader::new(1.33, mode, 4, strategy);
        let sampled = pixel_stats(&scene, &shader, &settings, 24, 6000);
        assert_same_mean(
            &format!("{mode} {strategy:?} vs table"),
            &sampled,
            &table,
            2e-3,
        );
    }
}
