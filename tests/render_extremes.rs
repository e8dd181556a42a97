//! Numerical extremes: scenes at 1e-6 and 1e6 scale, a camera inside the bubble, films of
//! 0 nm and 100 µm, ior 1 and 3, rays grazing a flat sheet of disks. Each renders to EXR at
//! 32x24 and every channel of every layer read back must be finite. Zero samples and zero
//! size are clear errors.

mod scratch;

use filmsplat::image::read_exr;
use filmsplat::io::write_ply;
use filmsplat::pipeline;
use filmsplat::pointcloud::PointCloud;
use filmsplat::samples::{BubbleParams, bubble};
use filmsplat::scene::SceneDesc;
use glam::Vec3;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    scratch::dir("extremes").join(name)
}

/// A bubble of `radius` scene units with `particles` particles.
fn sphere(radius: f32, particles: usize) -> PointCloud {
    bubble(&BubbleParams {
        particles,
        radius,
        ..BubbleParams::default()
    })
}

/// A flat 40x40 sheet of disks in the y = 0 plane, spacing 0.05, normals +y.
fn sheet() -> PointCloud {
    let mut positions = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            positions.push(Vec3::new(i as f32 * 0.05 - 1.0, 0.0, j as f32 * 0.05 - 1.0));
        }
    }
    let n = positions.len();
    PointCloud {
        positions,
        normals: Some(vec![Vec3::Y; n]),
        thickness_nm: Some(vec![350.0; n]),
        radius: Some(vec![0.04; n]),
        extra: Vec::new(),
    }
}

/// Renders `cloud` with `edit` applied to the description to a 32x24 EXR; returns the number
/// of pixels whose alpha shows film, after checking every value of every layer is finite.
fn render_finite(name: &str, cloud: &PointCloud, edit: impl FnOnce(&mut SceneDesc)) -> usize {
    let ply = scratch(&format!("{name}.ply"));
    write_ply(&ply, cloud).unwrap();
    let mut d = SceneDesc::default();
    d.input.cloud = Some(ply);
    d.render.width = Some(32);
    d.render.height = Some(24);
    d.render.spp = Some(2);
    edit(&mut d);
    let prepared =
        pipeline::prepare(&d, Path::new(""), false).unwrap_or_else(|e| panic!("{name}: {e}"));
    let out = pipeline::render(&prepared, &prepared.shot).unwrap();
    let exr = scratch(&format!("{name}.exr"));
    pipeline::write_image(&prepared.shot, &out, &exr).unwrap();
    let l = read_exr(&exr).unwrap();
    assert_eq!((l.width, l.height), (32, 24), "{name}");
    let mut values: Vec<(&str, f32)> = Vec::new();
    values.extend(l.rgba.iter().flatten().map(|v| ("rgba", *v)));
    for (layer, v) in [
        ("depth", &l.depth),
        ("thickness", &l.thickness),
        ("hits", &l.hit_count),
    ] {
        let v = v
            .as_ref()
            .unwrap_or_else(|| panic!("{name}: no {layer} layer"));
        assert_eq!(v.len(), 32 * 24);
        values.extend(v.iter().map(|x| (layer, *x)));
    }
    let normal = l.normal.as_ref().expect("normal layer");
    values.extend(normal.iter().flatten().map(|v| ("normal", *v)));
    if let Some((layer, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
        panic!("{name}: {layer} holds {v}");
    }
    // (Linear sRGB may be slightly negative: saturated film colours lie outside its gamut.)
    assert!(
        l.rgba.iter().all(|p| (0.0..=1.0).contains(&p[3])),
        "{name}: alpha out of 0..1"
    );
    l.rgba.iter().filter(|p| p[3] > 0.0).count()
}

#[test]
fn extreme_scales_cameras_films_and_grazing_rays_give_finite_images() {
    let pixels = 32 * 24;
    // The same bubble at 1e-6, 1 and 1e6 scene units: auto-framed, it must look the same.
    let coverage: Vec<usize> = [1e-6f32, 1.0, 1e6]
        .iter()
        .map(|&s| render_finite(&format!("scale_{s:e}"), &sphere(s, 3000), |_| {}))
        .collect();
    assert!(coverage[1] > pixels / 4, "{coverage:?}");
    for c in &coverage {
        assert!(
            c.abs_diff(coverage[1]) <= pixels / 50,
            "coverage by scale {coverage:?}"
        );
    }
    let tiny_spheres = render_finite("spheres_1e-6", &sphere(1e-6, 3000), |d| {
        d.film.primitive = Some("sphere".into());
    });
    assert!(tiny_spheres > pixels / 8, "{tiny_spheres}");

    // Inside the bubble every camera ray meets the film.
    let inside = render_finite("inside", &sphere(1.0, 3000), |d| {
        d.camera.position = Some([0.0, 0.0, 0.0]);
        d.camera.look_at = Some([0.0, 0.0, -1.0]);
        d.camera.fov = Some(90.0);
    });
    assert_eq!(
        inside, pixels,
        "a camera inside a closed bubble sees film everywhere"
    );

    // Film thickness 0 and 100 µm, ior 1 (no film at all) and 3, both shading modes.
    for (name, thickness, ior, shading) in [
        ("h0", 0.0, 1.33, "lut"),
        ("h100um", 1e5, 1.33, "lut"),
        ("h100um_rgb", 1e5, 1.33, "rgb"),
        ("ior1", 500.0, 1.0, "rgb"),
        ("ior3", 500.0, 3.0, "lut"),
        ("ior3_h100um", 1e5, 3.0, "rgb"),
    ] {
        let mut c = sphere(1.0, 3000);
        c.thickness_nm = Some(vec![thickness; c.len()]);
        let seen = render_finite(name, &c, |d| {
            d.film.ior = Some(ior);
            d.render.shading = Some(shading.into());
        });
        assert!(seen > pixels / 4, "{name}: {seen}");
    }

    // Grazing incidence: the camera just above, and exactly in, the plane of a flat sheet.
    for (name, height) in [
        ("graze_1e-4", 1e-4f32),
        ("graze_0", 0.0),
        ("graze_1e-7", 1e-7),
    ] {
        render_finite(name, &sheet(), |d| {
            d.camera.position = Some([0.0, height, 3.0]);
            d.camera.look_at = Some([0.0, height, 0.0]);
        });
    }
    // A camera lying on the sheet, looking along it: rays start on a surface.
    render_finite("on_surface", &sheet(), |d| {
        d.camera.position = Some([0.0, 0.0, 0.0]);
        d.camera.look_at = Some([1.0, 0.01, 0.3]);
        d.camera.fov = Some(120.0);
    });
}

#[test]
fn zero_samples_or_zero_size_are_clear_errors() {
    let ply = scratch("zero.ply");
    write_ply(&ply, &sphere(1.0, 500)).unwrap();
    for (edit, want) in [
        ((0, 24, 1), "image size must be between 1x1"),
        ((32, 0, 1), "image size must be between 1x1"),
        ((32, 24, 0), "spp must be between 1 and 65536"),
    ] {
        let mut d = SceneDesc::default();
        d.input.cloud = Some(ply.clone());
        d.render.width = Some(edit.0);
        d.render.height = Some(edit.1);
        d.render.spp = Some(edit.2);
        let err = pipeline::prepare(&d, Path::new(""), false).unwrap_err();
        assert!(err.to_string().contains(want), "{err}");
        assert_eq!(err.exit_code(), 2);
    }
}
