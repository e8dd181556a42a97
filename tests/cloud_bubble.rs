//! The bubble sample against independent expectations: its particles sample the sphere's area
//! uniformly (Archimedes' hat-box theorem) and its disks leave no hole; its thickness follows
//! the drainage law's distribution (area-preserving swirls move thickness, never change how
//! much area has which thickness); thinning scales it as √(τ/(τ+t)); seeds and time behave.
//! The sample is y up (gravity −y).

use filmsplat::pointcloud::validate::validate;
use filmsplat::samples::{BubbleParams, bubble};
use glam::Vec3;

fn params(seed: u64, time: f32) -> BubbleParams {
    BubbleParams {
        particles: 20_000,
        radius: 1.5,
        time,
        seed,
    }
}

/// A seeded stream of uniform numbers in [0, 1) (SplitMix64), independent of the crate's.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn particles_sample_the_sphere_uniformly_with_outward_normals() {
    let p = params(1, 0.0);
    let c = bubble(&p);
    validate(&c).unwrap();
    assert_eq!(c.len(), p.particles);
    let normals = c.normals.as_ref().unwrap();
    for (x, n) in c.positions.iter().zip(normals) {
        assert!(
            (x.length() - p.radius).abs() < 1e-5 * p.radius,
            "on the sphere: {x}"
        );
        assert!((n.length() - 1.0).abs() < 1e-6, "unit normal {n}");
        assert!(
            n.dot(*x / p.radius) > 1.0 - 1e-6,
            "radial, outward: {n} at {x}"
        );
    }
    // Archimedes: a band a < z/R < b holds the fraction (b - a)/2 of the sphere's area, along
    // any axis. Binomial s.d. of a fraction f is sqrt(f(1-f)/n) <= 0.0036; a lattice does better.
    for axis in [Vec3::Z, Vec3::X, Vec3::new(1.0, 1.0, 1.0).normalize()] {
        for (a, b) in [
            (-1.0, -0.8),
            (-0.3, 0.1),
            (0.5, 0.55),
            (0.9, 1.0),
            (-1.0, 0.0),
        ] {
            let inside = c
                .positions
                .iter()
                .filter(|x| (a..b).contains(&(x.dot(axis) / p.radius)))
                .count();
            let f = inside as f32 / c.len() as f32;
            let want = (b - a) / 2.0;
            assert!(
                (f - want).abs() < 0.01,
                "{axis} band {a}..{b}: {f} vs {want}"
            );
        }
    }
}

/// Every point of the sphere lies under some particle's disk: probes at random directions are
/// each within a disk radius of a particle centre (brute force over all particles).
#[test]
fn disks_cover_the_sphere_without_holes() {
    let p = params(4, 0.0);
    let c = bubble(&p);
    let radii = c.radius.as_ref().unwrap();
    let mut u = uniform(11);
    let mut worst = 0.0f32;
    for _ in 0..1500 {
        let z = 2.0 * u() - 1.0;
        let phi = std::f64::consts::TAU * u();
        let s = (1.0 - z * z).sqrt();
        let q = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32) * p.radius;
        // How far the probe is inside the nearest covering disk: distance / radius, smallest.
        let best = c
            .positions
            .iter()
            .zip(radii)
            .map(|(x, r)| x.distance(q) / r)
            .fold(f32::INFINITY, f32::min);
        worst = worst.max(best);
    }
    assert!(
        worst < 0.95,
        "a probe {worst} disk radii from the nearest particle: a hole"
    );
}

/// The fraction of particles (= of area) thinner than X, against the drainage law alone:
/// h = h_top + (h_bottom - h_top) s^0.75 with the depth s = (1 - z)/2 uniform in area, so
/// P(h < X) = ((X - 60)/1040)^(4/3) for 60 <= X <= 1100 nm. The swirls preserve area, so they
/// leave this distribution alone; the waves (a few %) and black patches (near the top, already
/// the thinnest) blur it a little.
#[test]
fn thickness_distribution_follows_the_drainage_law() {
    let c = bubble(&params(2, 0.0));
    let h = c.thickness_nm.as_ref().unwrap();
    let n = h.len() as f64;
    for x in [150.0f64, 300.0, 500.0, 678.4, 900.0, 1050.0] {
        let below = h.iter().filter(|&&t| (t as f64) < x).count() as f64 / n;
        let law = ((x - 60.0) / 1040.0).powf(4.0 / 3.0);
        assert!(
            (below - law).abs() < 0.04,
            "P(h < {x} nm) = {below}, law {law}"
        );
    }
    // Thin at the top, thick at the bottom, black film at the apex.
    let mean_where = |keep: &dyn Fn(f32) -> bool| {
        let v: Vec<f64> = c
            .positions
            .iter()
            .zip(h)
            .filter(|(x, _)| keep(x.y / 1.5))
            .map(|(_, &t)| t as f64)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (top, bottom) = (mean_where(&|z| z > 0.6), mean_where(&|z| z < -0.6));
    assert!(top < 0.5 * bottom, "top {top} nm, bottom {bottom} nm");
    let black = c
        .positions
        .iter()
        .zip(h)
        .filter(|(x, t)| x.y > 1.0 && **t < 40.0);
    assert!(black.count() > 0, "no black film near the apex");
}

/// Thinning: the film thins as √(τ/(τ+t)), τ = 60 s, so a minute later every quantile of the
/// thickness (above the black film) is 1/√2 of what it was.
#[test]
fn film_thins_as_the_square_root_law() {
    let quantile = |t: f32, q: f64| {
        let mut h = bubble(&params(5, t)).thickness_nm.unwrap();
        h.sort_by(f32::total_cmp);
        h[(q * h.len() as f64) as usize] as f64
    };
    for q in [0.5, 0.8] {
        let ratio = quantile(60.0, q) / quantile(0.0, q);
        let want = 0.5f64.sqrt();
        assert!(
            (ratio - want).abs() < 0.03,
            "quantile {q}: ratio {ratio}, want {want}"
        );
    }
}

#[test]
fn swirls_break_the_horizontal_layering() {
    // Pure drainage would make h a function of z; the swirled field varies a lot along a
    // latitude circle.
    let p = params(3, 0.0);
    let c = bubble(&p);
    let h = c.thickness_nm.as_ref().unwrap();
    let band: Vec<f64> = c
        .positions
        .iter()
        .zip(h)
        .filter(|(x, _)| (-0.05..0.05).contains(&(x.y / p.radius)))
        .map(|(_, &t)| t as f64)
        .collect();
    let mean = band.iter().sum::<f64>() / band.len() as f64;
    let sd = (band.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / band.len() as f64).sqrt();
    assert!(sd > 50.0, "equatorial thickness s.d. {sd} nm (mean {mean})");
}

#[test]
fn deterministic_per_seed() {
    let a = bubble(&params(7, 0.25));
    let b = bubble(&params(7, 0.25));
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.thickness_nm, b.thickness_nm);
    let c = bubble(&params(8, 0.25));
    assert_ne!(a.positions, c.positions);
    let (ha, hc) = (a.thickness_nm.unwrap(), c.thickness_nm.unwrap());
    let differ = ha
        .iter()
        .zip(&hc)
        .filter(|(x, y)| (*x - *y).abs() > 10.0)
        .count();
    assert!(differ > ha.len() / 4, "other seed, other film: {differ}");
}

#[test]
fn time_animates_smoothly() {
    let mean_abs_change = |t0: f32, t1: f32| {
        let a = bubble(&params(9, t0)).thickness_nm.unwrap();
        let b = bubble(&params(9, t1)).thickness_nm.unwrap();
        a.iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs() as f64)
            .sum::<f64>()
            / a.len() as f64
    };
    let small = mean_abs_change(1.0, 1.01);
    let large = mean_abs_change(1.0, 2.0);
    assert!(
        small > 0.0 && small < 5.0,
        "a 10 ms step barely changes the film: {small} nm"
    );
    assert!(
        large > 10.0 * small,
        "a second changes it much more: {large} vs {small}"
    );
}
