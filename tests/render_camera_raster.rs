//! The renderer's camera rays from the disks' raster (one sample a pixel, pinhole, disks): the
//! auxiliary buffers of a render hold, pixel by pixel, the first crossing that
//! `DiskGeometry::intersect` gives along the camera ray through the pixel centre.

use filmsplat::geometry::DiskGeometry;
use filmsplat::render::{
    Camera, Environment, FilmShader, RenderSettings, Scene, ShadingMode, Staging, render,
};
use filmsplat::spectrum::WavelengthStrategy;
use glam::Vec3;

/// A Fibonacci shell of `n` disks around the origin, radii 1.2× the spacing, thickness
/// varying with height.
fn shell(n: usize) -> DiskGeometry {
    let spacing = (4.0 * std::f32::consts::PI / n as f32).sqrt();
    let pos = filmsplat::samples::fibonacci_sphere(n, 1.0);
    let thk: Vec<f32> = pos.iter().map(|p| 500.0 + 300.0 * p.y).collect();
    DiskGeometry::build(&pos, &pos, &vec![1.2 * spacing; n], &thk).unwrap()
}

#[test]
fn one_sample_renders_see_the_first_crossing_intersect_sees() {
    let geometry = shell(3000);
    // Partly out of frame, with the silhouette and sky in view; a size that cuts tiles.
    let camera = Camera::look_at(
        Vec3::new(0.4, 0.3, 2.2),
        Vec3::new(0.5, 0.2, 0.0),
        Vec3::Y,
        45.0,
    );
    let scene = Scene {
        geometry: geometry.clone().into(),
        camera,
        environment: Environment::Uniform(Vec3::splat(0.5)),
        layer_skip: 1e-3,
        epsilon: 1e-5,
        staging: Staging::default(),
    };
    let shader = FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered);
    let (w, h) = (70, 45);
    let settings = RenderSettings {
        width: w,
        height: h,
        spp: 1,
        ..RenderSettings::default()
    };
    let out = render(&scene, &shader, &settings).unwrap();
    let aspect = w as f32 / h as f32;
    let (mut hits, mut misses) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let ray = camera.ray(
                (x as f32 + 0.5) / w as f32,
                (y as f32 + 0.5) / h as f32,
                aspect,
            );
            let k = y * w + x;
            let at = format!("pixel ({x}, {y})");
            match geometry.intersect(&ray, 0.0, f32::INFINITY) {
                None => {
                    misses += 1;
                    assert_eq!((out.alpha[k], out.hits[k]), (0.0, 0.0), "{at}");
                }
                Some(f) => {
                    hits += 1;
                    let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * a.abs().max(b.abs());
                    assert_eq!(
                        (out.alpha[k], out.hits[k]),
                        (1.0, f.coverage as f32),
                        "{at}"
                    );
                    assert!(
                        close(out.depth[k], f.t),
                        "{at}: depth {} {}",
                        out.depth[k],
                        f.t
                    );
                    assert!(close(out.thickness[k], f.thickness_nm), "{at}: thickness");
                    assert!((out.normal[k] - f.normal).length() < 1e-5, "{at}: normal");
                }
            }
        }
    }
    assert!(hits > 1000 && misses > 300, "{hits} hits, {misses} misses");
}
