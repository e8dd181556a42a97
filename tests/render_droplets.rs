//! Droplets are clear water spheres: lossless (a white furnace stays white through them), and
//! seen against a sky over a dark ground they show the sky and ground swapped, as a ball lens
//! inverts the world behind it.

use filmsplat::geometry::{DiskGeometry, Droplets};
use filmsplat::render::{
    Camera, Environment, FilmShader, RenderSettings, Scene, ShadingMode, Staging, render,
};
use filmsplat::spectrum::WavelengthStrategy;
use glam::Vec3;

fn scene(environment: Environment) -> Scene {
    Scene {
        geometry: DiskGeometry::build(&[], &[], &[], &[]).unwrap().into(),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 8.0), Vec3::ZERO, Vec3::Y, 30.0),
        environment,
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging {
            droplets: Droplets::build(&[Vec3::ZERO], &[1.0]).unwrap(),
            ..Staging::default()
        },
    }
}

fn settings(depth: u32) -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 48,
        spp: 1,
        max_depth: depth,
        min_weight: 1e-4,
        ..RenderSettings::default()
    }
}

fn shader() -> FilmShader {
    FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered)
}

#[test]
fn a_droplet_in_a_white_furnace_vanishes() {
    let out = render(
        &scene(Environment::Uniform(Vec3::ONE)),
        &shader(),
        &settings(12),
    )
    .unwrap();
    for c in &out.rgb {
        assert!((*c - Vec3::ONE).abs().max_element() < 1e-4, "{c}");
    }
}

#[test]
fn a_droplet_turns_the_world_behind_it_upside_down() {
    // Bright above the horizon, dark below: through the centre of a ball lens the camera sees
    // the ground above the ball's middle and the sky below it (and itself only faintly in the
    // 2 % Fresnel reflection).
    let sky = |d: Vec3| {
        if d.y > 0.0 {
            Vec3::ONE
        } else {
            Vec3::splat(0.02)
        }
    };
    let w = 64;
    let texels: Vec<Vec3> = (0..w * w / 2)
        .map(|k| {
            let v = (k / w) as f32 + 0.5;
            let theta = v / (w / 2) as f32 * std::f32::consts::PI;
            sky(Vec3::new(0.0, theta.cos(), 0.0))
        })
        .collect();
    let env = Environment::Map(filmsplat::render::LatLongMap::new(
        w,
        w / 2,
        texels,
        0.0,
        1.0,
    ));
    let out = render(&scene(env), &shader(), &settings(12)).unwrap();
    let at = |x: usize, y: usize| out.rgb[y * 48 + x].x;
    // Inside the droplet (it spans rows ~13..35), a little above and below its centre.
    let (upper, lower) = (at(24, 18), at(24, 30));
    assert!(lower > 0.5 && upper < 0.3, "upper {upper}, lower {lower}");
    // Outside, the sky is bright above and dark below, the other way round.
    assert!(
        at(24, 2) > 0.5 && at(24, 45) < 0.3,
        "{} {}",
        at(24, 2),
        at(24, 45)
    );
}
