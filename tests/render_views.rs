//! Views tell the truth: a view with a colour bar is exactly the requested size, and each end
//! of its bar has the colour of the pixels whose value it is labelled with.

use filmsplat::figure::colour_bar_width;
use filmsplat::geometry::SurfaceHit;
use filmsplat::pipeline;
use filmsplat::scene::SceneDesc;
use std::path::Path;

const W: usize = 320;
const H: usize = 180;

/// The bubble sample seen with `view`, prepared at 320×180.
fn prepared(view: &str) -> pipeline::Prepared {
    let toml = format!(
        "[input]\nsample = \"half-bubble\"\nparticles = 4000\n\n[render]\nview = \"{view}\"\n\
         width = {W}\nheight = {H}\n"
    );
    let desc = SceneDesc::from_toml(&toml, "inline").unwrap();
    pipeline::prepare(&desc, Path::new("."), false).unwrap()
}

/// For each scene pixel (the columns left of the bar), the first crossing, traced here with
/// the prepared camera and geometry.
fn hits(p: &pipeline::Prepared, scene_w: usize) -> Vec<Option<SurfaceHit>> {
    let aspect = scene_w as f32 / H as f32;
    (0..scene_w * H)
        .map(|k| {
            let (x, y) = (k % scene_w, k / scene_w);
            let ray = p.scene.camera.ray(
                (x as f32 + 0.5) / scene_w as f32,
                (y as f32 + 0.5) / H as f32,
                aspect,
            );
            p.scene.geometry.intersect(&ray, 0.0, f32::INFINITY)
        })
        .collect()
}

/// Checks that the bar's bottom end (labelled with the smallest value) has the colour of the
/// pixel with the smallest `value`, and the top end that of the largest.
fn bar_ends_match(view: &str, value: fn(&SurfaceHit) -> f32) {
    let p = prepared(view);
    let v = pipeline::render_view(&p, &p.shot).unwrap().unwrap();
    assert_eq!((v.width, v.height), (W, H), "{view}: exactly --size");
    assert_eq!(v.rgb.len(), W * H);
    let panel = colour_bar_width(W, H);
    let scene_w = W - panel;
    let legend = v.legend.clone().unwrap();
    let hits = hits(&p, scene_w);
    let (mut lo, mut hi) = ((f32::INFINITY, 0), (f32::NEG_INFINITY, 0));
    for (k, h) in hits.iter().enumerate() {
        if let Some(h) = h {
            let t = value(h);
            if t < lo.0 {
                lo = (t, k);
            }
            if t > hi.0 {
                hi = (t, k);
            }
        }
    }
    assert!(hi.0 > lo.0, "{view}: the values should vary");
    // The labels are the real range.
    assert!(
        (legend.min - lo.0).abs() <= 1e-4 * lo.0.abs().max(1.0),
        "{view}: {legend:?} vs {lo:?}"
    );
    assert!((legend.max - hi.0).abs() <= 1e-4 * hi.0.abs().max(1.0));
    let pixel = |k: usize| v.rgb[(k / scene_w) * W + k % scene_w];
    // The bar: a column through its middle, its bottom and top rows (it spans 10..90 % of
    // the height).
    let s = panel as f32 / 150.0;
    let x = scene_w + (36.0 * s) as usize;
    let bottom = v.rgb[((0.9 * H as f32) as usize - 1) * W + x];
    let top = v.rgb[((0.1 * H as f32).ceil() as usize) * W + x];
    let near = |a: glam::Vec3, b: glam::Vec3| (a - b).abs().max_element() < 0.02;
    assert!(
        near(bottom, pixel(lo.1)),
        "{view}: the bar's {} end is {bottom}, the pixels with that value are {}",
        legend.min,
        pixel(lo.1)
    );
    assert!(
        near(top, pixel(hi.1)),
        "{view}: the bar's {} end is {top}, the pixels with that value are {}",
        legend.max,
        pixel(hi.1)
    );
    assert!(!near(top, bottom), "{view}: a bar with two different ends");
}

#[test]
fn the_depth_bar_is_light_where_the_nearest_pixels_are() {
    bar_ends_match("depth", |h| h.t);
}

#[test]
fn the_thickness_bar_ends_match_the_thinnest_and_thickest_pixels() {
    bar_ends_match("thickness", |h| h.thickness_nm);
}

#[test]
fn every_view_is_exactly_the_requested_size() {
    for view in ["thickness", "normal", "depth", "particle-id", "coverage"] {
        let p = prepared(view);
        let v = pipeline::render_view(&p, &p.shot).unwrap().unwrap();
        assert_eq!((v.width, v.height, v.rgb.len()), (W, H, W * H), "{view}");
        assert_eq!(v.legend.is_some(), p.shot.view.has_legend(), "{view}");
        // A view with a bar frames the scene for the columns the bar leaves.
        let scene_w = if p.shot.view.has_legend() {
            W - colour_bar_width(W, H)
        } else {
            W
        };
        assert_eq!(p.aspect, scene_w as f32 / H as f32, "{view}");
    }
}
