//! The bubble sample: geometry, thickness field, determinism.

use filmsplat::pointcloud::validate::validate;
use filmsplat::samples::bubble::{H_BLACK_NM, H_BOTTOM_NM};
use filmsplat::samples::{BubbleParams, bubble, fibonacci_spacing};

fn params(seed: u64, time: f32) -> BubbleParams {
    BubbleParams {
        particles: 20_000,
        radius: 1.5,
        time,
        seed,
    }
}

#[test]
fn defaults() {
    let p = BubbleParams::default();
    assert_eq!((p.particles, p.radius, p.time), (200_000, 1.0, 0.0));
}

#[test]
fn geometry_normals_and_radius() {
    let p = params(1, 0.0);
    let c = bubble(&p);
    validate(&c).unwrap();
    assert_eq!(c.len(), p.particles);
    let normals = c.normals.as_ref().unwrap();
    for (x, n) in c.positions.iter().zip(normals) {
        assert!(
            (x.length() - p.radius).abs() < 1e-5 * p.radius,
            "on the sphere"
        );
        assert!((n.length() - 1.0).abs() < 1e-6, "unit normal");
        assert!(n.dot(*x / p.radius) > 1.0 - 1e-6, "radial, outward");
    }
    let d = fibonacci_spacing(p.particles, p.radius);
    assert!(
        c.radius
            .as_ref()
            .unwrap()
            .iter()
            .all(|&r| (r / d - 0.9).abs() < 1e-4)
    );
}

#[test]
fn thickness_range_and_drainage() {
    let p = params(2, 0.0);
    let c = bubble(&p);
    let h = c.thickness_nm.as_ref().unwrap();
    let (lo, hi) = h
        .iter()
        .fold((f32::INFINITY, 0.0f32), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(
        lo >= H_BLACK_NM - 1e-3 && hi <= 1.16 * H_BOTTOM_NM,
        "range {lo}..{hi}"
    );
    let band_mean = |zlo: f32, zhi: f32| {
        let (s, n) = c
            .positions
            .iter()
            .zip(h)
            .filter(|(x, _)| (zlo..zhi).contains(&(x.y / p.radius)))
            .fold((0.0f64, 0usize), |(s, n), (_, &t)| (s + t as f64, n + 1));
        s / n as f64
    };
    let top = band_mean(0.6, 1.01);
    let bottom = band_mean(-1.01, -0.6);
    assert!(top < 450.0 && top < 0.5 * bottom, "thin top: {top}");
    assert!(bottom > 800.0, "thick bottom: {bottom}");
    // Black film exists near the apex (a few tens of nm).
    let black = c
        .positions
        .iter()
        .zip(h)
        .filter(|(x, t)| x.y > 0.7 * p.radius && **t < 40.0)
        .count();
    assert!(black > 0);
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
