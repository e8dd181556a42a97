//! Auto-framing of a simulator's own flat film (issue 28): drawn as disks, spheres or an MLS
//! surface, the Rayleigh–Taylor film (`tests/data/thin-film-sph/rayleigh_taylor/100`, a flat
//! disk in the plane y = 0; see tests/data/ATTRIBUTION.md) is seen from the same direction,
//! [`FLAT_ELEVATION_DEG`] above its plane, and looked at in the same point.

use std::path::{Path, PathBuf};

use filmsplat::pipeline;
use filmsplat::pipeline::framing::FLAT_ELEVATION_DEG;
use filmsplat::scene::SceneDesc;
use glam::Vec3;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

#[test]
fn a_flat_film_is_seen_from_the_same_steep_direction_whatever_draws_it() {
    // Before `framing::surface_box`, the MLS surface's box held its support spheres (0.048
    // thick across a 0.318-wide film, more than the 10 % that makes a film flat): the MLS
    // picture saw the film 16° above its plane, the disks' from 50°.
    let mut desc = SceneDesc::default();
    desc.input.cloud = Some(data("thin-film-sph/rayleigh_taylor/100"));
    desc.render.preset = Some("preview".into());
    let mut seen = Vec::new();
    for primitive in ["disk", "sphere", "mls"] {
        desc.film.primitive = Some(primitive.into());
        let p = pipeline::prepare(&desc, Path::new(""), false).unwrap();
        let cam = pipeline::camera(&desc, &p.framing, p.aspect).unwrap();
        let view = -cam.forward().normalize();
        // The film's plane is y = 0: the elevation of the view above it.
        let elevation = view.y.abs().asin().to_degrees();
        eprintln!(
            "{primitive}: from {view}, {elevation:.2}° above the film, box {} .. {}",
            p.framing.min, p.framing.max
        );
        assert!(
            elevation >= FLAT_ELEVATION_DEG - 1e-3,
            "{primitive}: {elevation:.2}°"
        );
        seen.push((primitive, view, p.framing.centre, p.framing.reach));
    }
    let (_, v0, c0, r0) = seen[0];
    for (primitive, v, c, _) in &seen[1..] {
        assert!(
            v.dot(v0) > (0.5f32).to_radians().cos(),
            "{primitive}: {v} vs {v0}"
        );
        assert!(
            (*c - c0).length() < 0.02 * r0,
            "{primitive}: looks at {c}, disks at {c0}"
        );
    }
    assert!(
        seen.iter()
            .all(|s| s.3 > 0.0 && Vec3::ZERO.distance(s.2) < s.3)
    );
}
