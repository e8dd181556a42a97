//! The gallery generators: geometry, normals, thickness, determinism, smooth motion, and the
//! analytic shapes (catenoid, hemisphere, frames).

use filmsplat::pointcloud::PointCloud;
use filmsplat::pointcloud::validate::validate;
use filmsplat::samples::catenoid::{neck, separation};
use filmsplat::samples::drip::{H_DROP_NM, T_SEPARATE, shape};
use filmsplat::samples::{SampleKind, SampleParams, sparse};
use glam::Vec3;

const N: usize = 3000;

fn make(kind: SampleKind, seed: u64, time: f32) -> PointCloud {
    kind.generate(&SampleParams {
        particles: N,
        time,
        seed,
    })
}

fn normals(c: &PointCloud) -> &[Vec3] {
    c.normals.as_deref().unwrap()
}

fn thickness(c: &PointCloud) -> &[f32] {
    c.thickness_nm.as_deref().unwrap()
}

/// Nearest-neighbour distance of every particle (brute force).
fn nn_distances(p: &[Vec3]) -> Vec<f32> {
    p.iter()
        .enumerate()
        .map(|(i, a)| {
            p.iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, b)| a.distance(*b))
                .fold(f32::INFINITY, f32::min)
        })
        .collect()
}

#[test]
fn every_generator_gives_valid_evenly_spaced_particles_with_plausible_thickness() {
    for kind in SampleKind::ALL {
        let c = make(kind, 3, 0.7);
        let name = kind.name();
        validate(&c).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(c.len(), N, "{name}");
        assert!(
            c.positions
                .iter()
                .all(|p| p.is_finite() && p.length() < 3.0)
        );
        assert!(
            normals(&c).iter().all(|n| (n.length() - 1.0).abs() < 1e-5),
            "{name}: unit normals"
        );
        let hmax = if kind == SampleKind::Drip {
            H_DROP_NM
        } else {
            1.16 * 1100.0
        };
        assert!(
            thickness(&c)
                .iter()
                .all(|&h| (24.0..=hmax + 1e-3).contains(&h)),
            "{name}: thickness range"
        );
        // Drainage: the top fifth (by height) is thinner than the bottom fifth.
        let mut by_y: Vec<(f32, f32)> = c
            .positions
            .iter()
            .map(|p| p.y)
            .zip(thickness(&c).iter().copied())
            .collect();
        by_y.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mean = |s: &[(f32, f32)]| s.iter().map(|x| x.1).sum::<f32>() / s.len() as f32;
        let (bottom, top) = (mean(&by_y[..N / 5]), mean(&by_y[N - N / 5..]));
        assert!(
            top < 0.6 * bottom,
            "{name}: top {top} nm vs bottom {bottom} nm"
        );
        // Roughly uniform spacing: the spread of nearest-neighbour distances is small, and the
        // splats (radius) cover the gaps.
        let mut nn = nn_distances(&c.positions);
        nn.sort_by(f32::total_cmp);
        let (p5, p95) = (nn[N / 20], nn[N - N / 20]);
        assert!(p95 < 2.0 * p5, "{name}: spacing {p5}..{p95}");
        let r = c.radius.as_deref().unwrap();
        let rmed = {
            let mut r = r.to_vec();
            r.sort_by(f32::total_cmp);
            r[N / 2]
        };
        assert!(
            rmed > 0.6 * nn[N / 2] && rmed < 1.5 * nn[N / 2],
            "{name}: radius {rmed}"
        );
    }
}

#[test]
fn generators_are_deterministic_for_a_seed_and_differ_between_seeds() {
    for kind in SampleKind::ALL {
        let (a, b, c) = (make(kind, 5, 0.3), make(kind, 5, 0.3), make(kind, 6, 0.3));
        assert_eq!(a.positions, b.positions, "{}", kind.name());
        assert_eq!(thickness(&a), thickness(&b), "{}", kind.name());
        assert_ne!(thickness(&a), thickness(&c), "{}", kind.name());
    }
}

#[test]
fn particles_move_smoothly_in_time() {
    // One frame at 240 fps: no particle jumps, and the thickness of most particles changes
    // little (the field is advected continuously).
    for kind in SampleKind::ALL {
        for t in [0.5f32, 1.5, 2.6] {
            let (a, b) = (make(kind, 2, t), make(kind, 2, t + 1.0 / 240.0));
            let moved = a
                .positions
                .iter()
                .zip(&b.positions)
                .map(|(p, q)| p.distance(*q))
                .fold(0.0f32, f32::max);
            assert!(
                moved < 0.02,
                "{} at {t}: a particle moved {moved}",
                kind.name()
            );
            let changed = thickness(&a)
                .iter()
                .zip(thickness(&b))
                .filter(|(x, y)| (*x - *y).abs() > 30.0)
                .count();
            assert!(
                changed < N / 50,
                "{} at {t}: {changed} thickness jumps",
                kind.name()
            );
        }
    }
}

#[test]
fn closed_shapes_have_outward_normals() {
    for kind in [
        SampleKind::Bubble,
        SampleKind::IrregularBubble,
        SampleKind::OscillatingBubble,
    ] {
        for t in [0.0f32, 0.4, 1.1] {
            let c = make(kind, 4, t);
            let centroid = c.positions.iter().sum::<Vec3>() / N as f32;
            for (p, n) in c.positions.iter().zip(normals(&c)) {
                assert!(n.dot((*p - centroid).normalize()) > 0.5, "{}", kind.name());
            }
        }
    }
    // The drip after the drop has separated: two closed pieces, each with outward normals.
    let t = T_SEPARATE as f32 + 0.5;
    let c = make(SampleKind::Drip, 4, t);
    let sh = shape(t as f64);
    let drop_centre = Vec3::new(0.0, sh.drop_z as f32, 0.0);
    let mut in_drop = 0;
    for (p, n) in c.positions.iter().zip(normals(&c)) {
        let centre = if p.y < -1.01 {
            in_drop += 1;
            drop_centre
        } else {
            Vec3::ZERO
        };
        assert!(n.dot((*p - centre).normalize()) > 0.9, "drip at {p}");
    }
    // The drop's share of the particles is its share of the area.
    let share = sh.drop_radius.powi(2) / (1.0 + sh.drop_radius.powi(2));
    assert!(
        (in_drop as f64 / N as f64 - share).abs() < 0.01,
        "{in_drop}"
    );
}

#[test]
fn the_catenoid_is_a_cosh_z_over_a_between_its_rings() {
    for t in [0.0f32, 2.0, 9.0] {
        let h = separation(t as f64);
        let a = neck(h).unwrap();
        let c = make(SampleKind::Catenoid, 1, t);
        let mut top = f32::NEG_INFINITY;
        for (p, n) in c.positions.iter().zip(normals(&c)) {
            let r = (p.x * p.x + p.z * p.z).sqrt() as f64;
            assert!(
                (r - a * (p.y as f64 / a).cosh()).abs() < 1e-5,
                "off the catenoid at {p}"
            );
            assert!(p.y.abs() as f64 <= h / 2.0 + 1e-6);
            // Normal ⟂ the profile (dr/dz = sinh(z/a)) and away from the axis.
            let radial = Vec3::new(p.x, 0.0, p.z).normalize();
            let expect = (radial - Vec3::Y * (p.y as f64 / a).sinh() as f32).normalize();
            assert!(n.dot(expect) > 1.0 - 1e-5, "normal at {p}");
            top = top.max(p.y);
        }
        // The film reaches its rings (within a particle spacing).
        assert!((h / 2.0 - top as f64) < 0.05, "top {top} of {h}");
    }
    // The rings are pulled apart over time, toward (not past) Goldschmidt's limit.
    assert!(separation(0.0) < separation(1.0) && separation(100.0) < 1.3255);
}

#[test]
fn open_films_have_their_boundaries_where_expected() {
    let d = (8.0 / (3f32.sqrt() * N as f32)).sqrt();
    // Square frame: x, y ∈ [−1, 1], film reaching every side; the bulge is gentle.
    let c = make(SampleKind::SquareFilm, 1, 0.3);
    let (lo, hi) = c
        .positions
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| {
            (a.min(*p), b.max(*p))
        });
    assert!(lo.x >= -1.0 && lo.y >= -1.0 && hi.x <= 1.0 && hi.y <= 1.0);
    assert!(lo.x < -1.0 + d && lo.y < -1.0 + d && hi.x > 1.0 - d && hi.y > 1.0 - d);
    assert!(lo.z > -0.01 && hi.z < 0.1, "bulge {lo} {hi}");
    assert!(normals(&c).iter().all(|n| n.z > 0.9), "facing +z");
    // Circle frame: inside the unit circle, reaching it.
    let c = make(SampleKind::CircleFilm, 1, 0.3);
    let rmax = c
        .positions
        .iter()
        .map(|p| p.truncate().length())
        .fold(0.0f32, f32::max);
    assert!(rmax <= 1.0 + 1e-6 && rmax > 1.0 - d, "{rmax}");
    assert!(normals(&c).iter().all(|n| n.z > 0.9), "facing +z");
    // Half bubble: the unit hemisphere above y = 0, reaching the surface.
    let c = make(SampleKind::HalfBubble, 1, 0.3);
    assert!(
        c.positions
            .iter()
            .all(|p| p.y >= -1e-6 && (p.length() - 1.0).abs() < 1e-5)
    );
    let ymin = c.positions.iter().map(|p| p.y).fold(1.0f32, f32::min);
    assert!(ymin < d, "{ymin}");
    for (p, n) in c.positions.iter().zip(normals(&c)) {
        assert!(n.dot(*p) > 1.0 - 1e-5, "outward at {p}");
    }
}

#[test]
fn sparse_keeps_a_random_fraction_and_widens_the_splats() {
    let c = make(SampleKind::CircleFilm, 1, 0.0);
    let s = sparse(&c, 0.25, 9);
    let f = s.len() as f64 / c.len() as f64;
    assert!((f - 0.25).abs() < 0.03, "{f}");
    assert_eq!(s.len(), s.normals.as_ref().unwrap().len());
    assert_eq!(s.len(), s.thickness_nm.as_ref().unwrap().len());
    let (r0, r1) = (c.radius.as_ref().unwrap()[0], s.radius.as_ref().unwrap()[0]);
    assert!((r1 / r0 - 2.0).abs() < 1e-5);
    assert!(s.positions.iter().all(|p| c.positions.contains(p)));
    assert_eq!(sparse(&c, 0.25, 9).positions, s.positions);
    assert_eq!(sparse(&c, 1.0, 9).len(), c.len());
}
