//! Studio rendering: area lights, props lit by next-event estimation, spectral transport.

use filmsplat::geometry::{DiskGeometry, Shape};
use filmsplat::render::{
    AreaLight, Camera, Environment, FilmShader, LightShape, Material, Prop, Props, RenderOutput,
    RenderSettings, Scene, ShadingMode, Staging, render,
};
use filmsplat::spectrum::WavelengthStrategy;
use glam::Vec3;

fn settings(w: usize, h: usize, spp: u32) -> RenderSettings {
    RenderSettings {
        width: w,
        height: h,
        spp,
        ..RenderSettings::default()
    }
}

fn no_films() -> DiskGeometry {
    DiskGeometry::build(&[], &[], &[], &[]).unwrap()
}

fn lut() -> FilmShader {
    FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered)
}

fn mean(out: &RenderOutput) -> Vec3 {
    out.rgb.iter().copied().sum::<Vec3>() / out.rgb.len() as f32
}

/// A camera at height 2 looking straight down at the ground y = 0.
fn ground_scene(env: Environment, albedo: f32, lights: Vec<AreaLight>) -> Scene {
    let material = Material::Diffuse {
        albedo: Vec3::splat(albedo),
    };
    ground_scene_with(env, material, lights)
}

/// [`ground_scene`] with a ground of any material.
fn ground_scene_with(env: Environment, material: Material, lights: Vec<AreaLight>) -> Scene {
    Scene {
        geometry: no_films().into(),
        camera: Camera::look_at(Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO, Vec3::Z, 30.0),
        environment: env,
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging {
            lights: lights.into_iter().map(Into::into).collect(),
            props: Props::new(
                vec![Prop {
                    shape: Shape::Plane {
                        point: Vec3::ZERO,
                        normal: Vec3::Y,
                    },
                    material,
                }],
                1e-5,
            ),
            ..Staging::default()
        },
    }
}

#[test]
fn an_area_light_seen_directly_has_its_radiance() {
    let radiance = Vec3::new(3.0, 2.0, 0.5);
    // A rectangle facing the camera fills the view; a sphere light is seen in the middle.
    let rect = AreaLight {
        shape: LightShape::Rect {
            centre: Vec3::ZERO,
            u: Vec3::new(5.0, 0.0, 0.0),
            v: Vec3::new(0.0, 5.0, 0.0),
        },
        radiance,
        blackbody: None,
    };
    let mut scene = ground_scene(
        Environment::Uniform(Vec3::splat(0.1)),
        0.5,
        vec![rect.clone()],
    );
    scene.staging = Staging {
        lights: vec![rect.into()],
        ..Staging::default()
    };
    scene.camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 30.0);
    for mode in [ShadingMode::Lut, ShadingMode::Spectral] {
        let shader = FilmShader::new(1.33, mode, 16, WavelengthStrategy::Jittered);
        let out = render(&scene, &shader, &settings(16, 12, 64)).unwrap();
        let m = mean(&out);
        let tol = if mode == ShadingMode::Lut { 1e-5 } else { 0.06 };
        assert!(
            (m - radiance).abs().max_element() < tol * radiance.max_element(),
            "{mode}: {m}"
        );
    }
    // From behind, a rectangle is black (it emits from its front only).
    scene.camera = Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 30.0);
    let out = render(&scene, &lut(), &settings(8, 6, 1)).unwrap();
    assert_eq!(mean(&out), Vec3::ZERO);
}

#[test]
fn white_furnace_ground_returns_the_environment() {
    let scene = ground_scene(Environment::Uniform(Vec3::ONE), 1.0, vec![]);
    let out = render(&scene, &lut(), &settings(64, 48, 4)).unwrap();
    let m = mean(&out);
    // 12288 samples of a weighted estimator with per-sample spread well under 1.
    assert!((m - Vec3::ONE).abs().max_element() < 0.01, "{m}");
    for c in &out.rgb {
        assert!(
            c.is_finite() && c.min_element() > 0.2 && c.max_element() < 2.0,
            "{c}"
        );
    }
}

#[test]
fn light_sampling_and_material_sampling_agree_in_the_mean() {
    let light = AreaLight {
        shape: LightShape::Disk {
            centre: Vec3::new(0.8, 1.5, 0.3),
            normal: Vec3::new(-0.3, -1.0, 0.0).normalize(),
            radius: 0.8,
        },
        radiance: Vec3::new(2.0, 1.5, 1.0),
        blackbody: None,
    };
    let env = Environment::Hemispheres {
        axis: Vec3::new(0.3, 1.0, 0.2).normalize(),
        toward: Vec3::new(0.3, 0.4, 0.6),
        away: Vec3::ZERO,
    };
    let glossy = Material::Glossy {
        albedo: Vec3::splat(0.7),
        roughness: 0.5,
    };
    let scene = ground_scene_with(env, glossy, vec![light]);
    let nee = render(&scene, &lut(), &settings(32, 24, 16)).unwrap();
    let bsdf = render(
        &scene,
        &lut(),
        &RenderSettings {
            next_event: false,
            ..settings(32, 24, 64)
        },
    )
    .unwrap();
    let (a, b) = (mean(&nee), mean(&bsdf));
    assert!(
        (a - b).abs().max_element() < 0.03 * a.max_element(),
        "{a} vs {b}"
    );
    // And light sampling is the less noisy of the two.
    let var = |o: &RenderOutput, m: Vec3| {
        o.rgb.iter().map(|c| (*c - m).length_squared()).sum::<f32>() / o.rgb.len() as f32
    };
    assert!(var(&nee, a) < var(&bsdf, b), "NEE should reduce noise");
}

/// One big disk film of `thickness` nm, head-on, lit from the front only: the image is the
/// film's reflectance colour.
fn film_scene(thickness: f32) -> Scene {
    let geometry = DiskGeometry::build(&[Vec3::ZERO], &[Vec3::Z], &[10.0], &[thickness]).unwrap();
    Scene {
        geometry: geometry.into(),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 10.0),
        environment: Environment::Hemispheres {
            axis: Vec3::Z,
            toward: Vec3::splat(0.8),
            away: Vec3::splat(0.2),
        },
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging::default(),
    }
}

#[test]
fn spectral_transport_of_a_grey_environment_matches_rgb() {
    for thickness in [250.0, 480.0] {
        let scene = film_scene(thickness);
        let rgb = FilmShader::new(1.33, ShadingMode::Rgb, 16, WavelengthStrategy::Jittered);
        let spectral = FilmShader::new(
            1.33,
            ShadingMode::Spectral,
            16,
            WavelengthStrategy::Jittered,
        );
        let a = mean(&render(&scene, &rgb, &settings(16, 12, 16)).unwrap());
        let b = mean(&render(&scene, &spectral, &settings(16, 12, 16)).unwrap());
        let reference = mean(&render(&scene, &lut(), &settings(4, 3, 1)).unwrap());
        assert!(
            (a - reference).abs().max_element() < 0.01,
            "{thickness}: rgb {a} vs {reference}"
        );
        assert!(
            (b - reference).abs().max_element() < 0.01,
            "{thickness}: spectral {b} vs {reference}"
        );
    }
}

/// Two small sphere lights, one on the plane of focus and one twice as far: through a thin
/// lens the first keeps the pinhole's footprint while the second spreads over many more pixels
/// at a lower peak; the light each delivers to the image is unchanged.
#[test]
fn depth_of_field_keeps_the_focal_plane_sharp_and_blurs_the_rest() {
    let light = |x: f32, z: f32, radius: f32| AreaLight {
        shape: LightShape::Sphere {
            centre: Vec3::new(x, 0.0, z),
            radius,
        },
        radiance: Vec3::splat(10.0),
        blackbody: None,
    };
    let mut scene = Scene {
        geometry: no_films().into(),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 20.0),
        environment: Environment::Uniform(Vec3::ZERO),
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging {
            lights: vec![light(-0.4, 0.0, 0.03).into(), light(0.8, -5.0, 0.06).into()],
            ..Staging::default()
        },
    };
    let s = settings(64, 48, 256);
    // Footprint (lit pixels), peak and total of the left and right halves.
    let measure = |out: &RenderOutput| {
        let mut r = [(0usize, 0.0f32, 0.0f32); 2];
        for (i, c) in out.rgb.iter().enumerate() {
            let half = usize::from(i % out.width >= out.width / 2);
            if c.x > 0.05 {
                r[half].0 += 1;
            }
            r[half].1 = r[half].1.max(c.x);
            r[half].2 += c.x;
        }
        r
    };
    let pin = measure(&render(&scene, &lut(), &s).unwrap());
    scene.camera = scene.camera.with_lens(0.15, 5.0);
    let lens = measure(&render(&scene, &lut(), &s).unwrap());
    // In focus: the same footprint and total.
    assert!(lens[0].0.abs_diff(pin[0].0) <= 2, "{pin:?} {lens:?}");
    assert!(
        (lens[0].2 - pin[0].2).abs() < 0.05 * pin[0].2,
        "{pin:?} {lens:?}"
    );
    // Out of focus: blur disc of ~2·0.15·5/10 = 0.15 units ≈ 5 px wide: more pixels, lower peak.
    assert!(lens[1].0 > 3 * pin[1].0, "{pin:?} {lens:?}");
    assert!(lens[1].1 < 0.5 * pin[1].1, "{pin:?} {lens:?}");
    assert!(
        (lens[1].2 - pin[1].2).abs() < 0.1 * pin[1].2,
        "{pin:?} {lens:?}"
    );
}

/// A black-body light seen directly: spectral transport carries its Planck spectrum, and the
/// pixel's colour matches the RGB of that spectrum the RGB modes use.
#[test]
fn a_black_body_light_has_the_same_colour_in_spectral_and_rgb() {
    for kelvin in [2700.0, 9000.0] {
        let mut b = filmsplat::spectrum::Blackbody::new(kelvin);
        b.scale *= 2.0;
        let light = AreaLight {
            shape: LightShape::Rect {
                centre: Vec3::ZERO,
                u: Vec3::new(5.0, 0.0, 0.0),
                v: Vec3::new(0.0, 5.0, 0.0),
            },
            radiance: Vec3::from(b.rgb) * 2.0,
            blackbody: Some(b),
        };
        let mut scene = ground_scene(Environment::Uniform(Vec3::ZERO), 0.5, vec![]);
        scene.staging = Staging {
            lights: vec![light.into()],
            ..Staging::default()
        };
        scene.camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 30.0);
        let rgb = mean(&render(&scene, &lut(), &settings(8, 6, 1)).unwrap());
        let spectral = FilmShader::new(
            1.33,
            ShadingMode::Spectral,
            16,
            WavelengthStrategy::Jittered,
        );
        let s = mean(&render(&scene, &spectral, &settings(16, 12, 64)).unwrap());
        assert!(
            (s - rgb).abs().max_element() < 0.03 * rgb.max_element(),
            "{kelvin} K: {s} vs {rgb}"
        );
        assert!(
            kelvin > 5000.0 || rgb.x > rgb.z,
            "warm light is red-heavy: {rgb}"
        );
    }
}
