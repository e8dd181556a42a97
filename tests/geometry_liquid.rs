//! The liquid surface ([`LiquidSurface`]): ray crossings against a brute-force oracle (the same
//! field marched in steps of 0.01 spacings through `field_at`, sign changes bisected), a lone
//! particle as the sphere of its volume, a cubic block's faces half a spacing out, and the
//! classification of real 3D particles.

use filmsplat::geometry::{LiquidField, LiquidSurface, Ray, VOLUME_RADIUS};
use filmsplat::pointcloud::liquid::classify;
use glam::Vec3;

/// A tiny deterministic generator (xorshift), uniform in [0, 1).
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.f(), self.f(), self.f()) * 2.0 - Vec3::ONE;
            if v.length_squared() > 1e-3 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

fn lattice(n: i32, s: f32, jitter: f32, rng: &mut Rng) -> Vec<Vec3> {
    let mut v = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let p = Vec3::new(i as f32, j as f32, k as f32) * s;
                v.push(p + (Vec3::new(rng.f(), rng.f(), rng.f()) - 0.5) * jitter * s);
            }
        }
    }
    v
}

/// The first sign change of φ along the ray within `(t0, t1)` by a march of `step`, bisected.
fn oracle(l: &LiquidSurface, ray: &Ray, t0: f32, t1: f32, step: f32) -> Option<f32> {
    let inside = |t: f32| l.field_at(ray.at(t)).phi < 0.0;
    let mut t = t0;
    let mut a = inside(t);
    while t < t1 {
        let tn = (t + step).min(t1);
        if inside(tn) != a {
            let (mut lo, mut hi) = (t, tn);
            for _ in 0..40 {
                let m = 0.5 * (lo + hi);
                if inside(m) == a { lo = m } else { hi = m }
            }
            return Some(0.5 * (lo + hi));
        }
        (t, a) = (tn, inside(tn));
    }
    None
}

/// Rays from random points around `points`' box toward random points inside it: the
/// intersection and the oracle agree on each crossing along the ray (entering, then the exit
/// found from just past the entry) to 10⁻³ spacings; returns how many crossings were compared.
/// Both fields: the exact march's crossings to 10⁻³ spacings along the ray, the grid's within
/// 0.03 spacings of the exact surface (|φ| there; along a grazing ray that can be far more), or
/// 0.1 spacings along the ray where the field is steep (a neck between a body and a particle
/// beside it, where the weighted mean swings from one to the other).
fn agree_with_oracle(points: &[Vec3], s: f32, rays: usize, seed: u64) -> usize {
    let (n, missed) = agree_on(points, s, rays, seed, LiquidField::Exact);
    assert_eq!(missed, 0);
    // The grid's surface lies up to 0.02 spacings off the exact one: a ray grazing either may
    // cross one and not the other (a sliver thinner than the march's step), rarely.
    let (g, missed) = agree_on(points, s, rays, seed, LiquidField::Grid);
    assert!(
        g + missed >= n * 9 / 10 && missed <= 1 + n / 30,
        "grid: {g} agreed, {missed} not, exact {n}"
    );
    n
}

/// [`agree_with_oracle`] for one field: crossings compared, and rays given up where one of
/// the two crossed and the other did not (the exact field never may).
fn agree_on(points: &[Vec3], s: f32, rays: usize, seed: u64, field: LiquidField) -> (usize, usize) {
    let l = LiquidSurface::build_with(points, s, field).unwrap();
    let exact = LiquidSurface::build_with(points, s, LiquidField::Exact).unwrap();
    let (lo, hi) = points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| {
            (a.min(*p), b.max(*p))
        });
    let (c, half) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5 + 3.0 * s);
    let mut rng = Rng(seed);
    let (mut compared, mut missed) = (0, 0);
    for _ in 0..rays {
        let origin = c + rng.unit() * half;
        let target = lo + (hi - lo) * Vec3::new(rng.f(), rng.f(), rng.f());
        let ray = Ray::new(origin, target - origin);
        let t_end = 2.0 * half + 3.0 * s;
        let mut t = 0.0;
        for _ in 0..6 {
            let fast = l.intersect(&ray, t, t_end).map(|h| h.t);
            let slow = oracle(&exact, &ray, t, t_end, 0.01 * s);
            match (fast, slow) {
                (None, None) => break,
                (Some(a), Some(b)) => {
                    let off = exact.field_at(ray.at(a)).phi.abs();
                    assert!(
                        match field {
                            LiquidField::Exact => (a - b).abs() < 1e-3 * s,
                            LiquidField::Grid => off < 0.03 * s || (a - b).abs() < 0.1 * s,
                        },
                        "{field:?} ray {ray:?} from {t}: {a} vs oracle {b} (|φ| {off})"
                    );
                    compared += 1;
                    // Past both crossings (the grid's may lie before or after the exact one).
                    t = a.max(b) + 2e-3 * s;
                }
                // A crossing pair closer than the march's smallest step (0.05 s) may be missed
                // by both or either; nothing else may.
                (a, b) if field == LiquidField::Exact => {
                    panic!("ray {ray:?} from {t}: intersect {a:?}, oracle {b:?}")
                }
                _ => {
                    missed += 1;
                    break;
                }
            }
        }
    }
    (compared, missed)
}

#[test]
fn crossings_match_the_brute_force_oracle() {
    let mut rng = Rng(7);
    let s = 0.01;
    // A cubic block, a jittered block and two lone particles beside it, a loose cluster.
    let mut pts = lattice(5, s, 0.0, &mut rng);
    assert!(agree_with_oracle(&pts, s, 60, 1) > 60);
    pts = lattice(5, s, 0.6, &mut rng);
    pts.extend([Vec3::new(-0.03, 0.02, 0.02), Vec3::new(0.07, 0.0, 0.04)]);
    assert!(agree_with_oracle(&pts, s, 60, 2) > 60);
    let cluster: Vec<Vec3> = (0..40)
        .map(|_| Vec3::new(rng.f(), rng.f(), rng.f()) * 4.0 * s)
        .collect();
    assert!(agree_with_oracle(&cluster, s, 60, 3) > 30);
}

#[test]
fn real_drops_match_the_oracle() {
    // The 3D particles of drops_on_film/105 (tests/data), classified and built as the pipeline
    // does.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/thin-film-sph/drops_on_film/105/tracker_points_3d");
    let bytes = std::fs::read(dir).unwrap();
    let n = i32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
    let f: Vec<f32> = bytes[4..4 + 4 * n]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let pts: Vec<Vec3> = f
        .chunks_exact(4)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect();
    assert_eq!(pts.len(), 1956);
    let split = classify(&pts);
    // Four blocks of bulk liquid: every particle is in a body; the spacing is the packing's.
    assert_eq!(
        split.liquid.len(),
        1956,
        "{} droplets",
        split.droplets.len()
    );
    assert!(
        split.spacing > 2.5e-3 && split.spacing < 3.0e-3,
        "{}",
        split.spacing
    );
    // One body (the 8×8×8 block, the last 512) against the oracle.
    assert!(agree_with_oracle(&pts[1444..], split.spacing, 25, 4) > 25);
}

#[test]
fn a_lone_particle_is_the_sphere_of_its_volume() {
    let s = 0.02;
    let c = Vec3::new(0.3, -0.1, 0.2);
    let l = LiquidSurface::build_with(&[c], s, LiquidField::Exact).unwrap();
    let mut rng = Rng(11);
    let mut mean_r = 0.0;
    for _ in 0..200 {
        let d = rng.unit();
        let ray = Ray::new(c + d * 5.0 * s, -d);
        let h = l.intersect(&ray, 0.0, 1.0).unwrap();
        let r = (ray.at(h.t) - c).length();
        assert!(h.entering && (h.normal - d).length() < 1e-3);
        mean_r += r / 200.0;
    }
    let volume = 4.0 / 3.0 * std::f32::consts::PI * mean_r.powi(3);
    assert!(
        (volume / (s * s * s) - 1.0).abs() < 0.01,
        "volume {volume} vs {}",
        s * s * s
    );
    assert!((mean_r - VOLUME_RADIUS * s).abs() < 1e-4 * s);
}

#[test]
fn a_cubic_block_ends_half_a_spacing_past_its_outer_particles() {
    let s = 0.005;
    let mut rng = Rng(5);
    let n = 8;
    let pts = lattice(n, s, 0.0, &mut rng);
    let l = LiquidSurface::build(&pts, s).unwrap();
    let top = (n - 1) as f32 * s;
    // Rays straight down onto the top face and along -x onto the side face, over the face's
    // middle (away from edges): where they enter, how far past the outer layer.
    let mut worst: f32 = 0.0;
    let mut offsets = Vec::new();
    for i in 0..9 {
        for j in 0..9 {
            let (u, v) = (2.0 * s + i as f32 * 0.4 * s, 2.0 * s + j as f32 * 0.4 * s);
            for (origin, dir, axis) in [
                (Vec3::new(u, top + 5.0 * s, v), -Vec3::Y, Vec3::Y),
                (Vec3::new(top + 5.0 * s, u, v), -Vec3::X, Vec3::X),
            ] {
                let h = l.intersect(&Ray::new(origin, dir), 0.0, 1.0).unwrap();
                let past = (origin + dir * h.t).dot(axis) - top;
                offsets.push(past / s);
                worst = worst.max((h.normal - axis).length());
            }
        }
    }
    let (lo, hi) = offsets
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &o| (a.min(o), b.max(o)));
    // Half a spacing (the outer particles' cells end there), flat to a hundredth of one.
    assert!(
        lo > 0.45 && hi < 0.6 && hi - lo < 0.02,
        "faces at {lo}..{hi} spacings"
    );
    assert!(worst < 0.05, "face normals off by {worst}");
}

#[test]
fn a_long_rod_and_a_block_past_a_gap_match_the_oracle() {
    // Rays along a 24-spacing rod cross it in many of the march's gathering windows (4
    // spacings each), and then a gap of 6 spacings to a second block: every window's spheres
    // and the jump across the gap must agree with the oracle.
    let s = 0.01;
    let mut pts = Vec::new();
    for i in 0..24 {
        for j in 0..3 {
            for k in 0..3 {
                pts.push(Vec3::new(i as f32, j as f32, k as f32) * s);
            }
        }
    }
    let mut rng = Rng(11);
    pts.extend(
        lattice(3, s, 0.3, &mut rng)
            .iter()
            .map(|p| *p + Vec3::X * 30.0 * s),
    );
    assert!(agree_with_oracle(&pts, s, 80, 5) > 80);
    // Along the axis from outside: in at the rod's end, out at its far end, in at the block.
    let l = LiquidSurface::build_with(&pts, s, LiquidField::Exact).unwrap();
    let ray = Ray::new(Vec3::new(-5.0 * s, 1.1 * s, 0.9 * s), Vec3::X);
    let mut t = 0.0;
    for _ in 0..4 {
        let fast = l.intersect(&ray, t, 50.0 * s).map(|h| h.t);
        let slow = oracle(&l, &ray, t, 50.0 * s, 0.01 * s);
        match (fast, slow) {
            (Some(a), Some(b)) => {
                assert!((a - b).abs() < 1e-3 * s, "from {t}: {a} vs oracle {b}");
                t = a + 2e-3 * s;
            }
            (a, b) => panic!("from {t}: intersect {a:?}, oracle {b:?}"),
        }
    }
}
