//! Property tests (proptest, with shrinking to a minimal counter-example): the BVH answers
//! what a brute-force loop answers on random primitives and rays; the thin-film optics conserve
//! energy and have the film's symmetries; the colour pipeline keeps white white and its
//! matrices invert the standard ones. Case counts are modest so the suite stays fast.

use filmsplat::geometry::primitives::{intersect_disk, intersect_sphere};
use filmsplat::geometry::{FilmGeometry, Primitive, Ray};
use filmsplat::optics::{FilmFresnel, film_rt};
use filmsplat::spectrum::{
    SpectralWeights, XYZ_TO_LINEAR_SRGB, film_rgb_reference, linear_to_srgb, srgb_to_linear,
    xyz_to_linear_srgb,
};
use glam::Vec3;
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// `cases` cases from a fixed seed, so CI runs the same cases every time (a random seed made a
/// run fail on a case the others never drew; that case is kept in
/// `properties.proptest-regressions` and replayed first). Change the seed to explore further.
fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        rng_seed: RngSeed::Fixed(0x5eed_f11e),
        ..ProptestConfig::with_cases(cases)
    }
}

fn vec3(lo: f32, hi: f32) -> impl Strategy<Value = Vec3> {
    (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A non-zero direction (not normalised: the code under test must cope).
fn direction() -> impl Strategy<Value = Vec3> {
    vec3(-1.0, 1.0).prop_filter("non-zero", |v| v.length() > 1e-3)
}

/// Up to 40 primitives in the unit box: (centre, normal, radius).
fn primitives() -> impl Strategy<Value = Vec<(Vec3, Vec3, f32)>> {
    prop::collection::vec((vec3(0.0, 1.0), direction(), 0.01f32..0.4), 1..40)
}

/// Brute force: the closest hit (t, index), ties to the lowest index.
fn brute(prim: Primitive, ps: &[(Vec3, Vec3, f32)], ray: &Ray, t_max: f32) -> Option<(f32, u32)> {
    let mut best: Option<(f32, u32)> = None;
    for (i, (c, n, r)) in ps.iter().enumerate() {
        let t = match prim {
            Primitive::Disk => intersect_disk(ray, *c, n.normalize(), *r, 0.0, t_max).map(|h| h.0),
            Primitive::Sphere => intersect_sphere(ray, *c, *r, 0.0, t_max),
            Primitive::Mls => unreachable!("MLS surfaces have their own tests (geometry_mls)"),
        };
        if let Some(t) = t
            && best.is_none_or(|b| t < b.0)
        {
            best = Some((t, i as u32));
        }
    }
    best
}

fn check_bvh(
    prim: Primitive,
    ps: &[(Vec3, Vec3, f32)],
    rays: &[(Vec3, Vec3, bool)],
) -> Result<(), TestCaseError> {
    let pos: Vec<Vec3> = ps.iter().map(|p| p.0).collect();
    let nrm: Vec<Vec3> = ps.iter().map(|p| p.1).collect();
    let rad: Vec<f32> = ps.iter().map(|p| p.2).collect();
    let g = FilmGeometry::particles(prim, &pos, &nrm, &rad, &vec![300.0; ps.len()]).unwrap();
    for (k, (o, d, bounded)) in rays.iter().enumerate() {
        // Every other ray aims at a primitive, so hits (and overlaps) are common.
        let dir = if k % 2 == 0 {
            *d
        } else {
            pos[k % pos.len()] + 0.05 * *d - *o
        };
        let ray = Ray::new(*o, dir);
        let t_max = if *bounded { 0.8 } else { f32::INFINITY };
        let want = brute(prim, ps, &ray, t_max);
        let got = g.intersect_single(&ray, 0.0, t_max);
        match (want, got) {
            (None, None) => {}
            (Some((t, i)), Some(h)) => {
                prop_assert!((h.t - t).abs() <= 1e-5 * t.max(1e-3), "t {} vs {t}", h.t);
                prop_assert_eq!(h.particle, i);
            }
            (w, g) => prop_assert!(false, "brute {:?} vs bvh {:?}", w, g.map(|h| h.t)),
        }
        prop_assert_eq!(g.intersect(&ray, 0.0, t_max).is_some(), want.is_some());
    }
    Ok(())
}

fn rays() -> impl Strategy<Value = Vec<(Vec3, Vec3, bool)>> {
    prop::collection::vec((vec3(-0.5, 1.5), direction(), any::<bool>()), 24)
}

proptest! {
    #![proptest_config(config(96))]

    #[test]
    fn bvh_disks_equal_brute_force(ps in primitives(), rs in rays()) {
        check_bvh(Primitive::Disk, &ps, &rs)?;
    }

    #[test]
    fn bvh_spheres_equal_brute_force(ps in primitives(), rs in rays()) {
        check_bvh(Primitive::Sphere, &ps, &rs)?;
    }

    /// Coplanar overlapping disks (one film sampled by many splats): the hardest ties.
    #[test]
    fn bvh_coplanar_disks_equal_brute_force(
        xy in prop::collection::vec((0.0f32..1.0, 0.0f32..1.0, 0.02f32..0.3, any::<bool>()), 1..40),
        rs in rays(),
    ) {
        let ps: Vec<(Vec3, Vec3, f32)> = xy
            .iter()
            .map(|&(x, y, r, up)| (Vec3::new(x, y, 0.5), if up { Vec3::Z } else { -Vec3::Z }, r))
            .collect();
        check_bvh(Primitive::Disk, &ps, &rs)?;
    }
}

proptest! {
    #![proptest_config(config(512))]

    /// A lossless film: R + T = 1 for each polarisation; 0 <= R <= 1; at normal incidence s
    /// and p are the same wave.
    #[test]
    fn film_conserves_energy(cos_i in 0.0f64..=1.0, h in 0.0f64..1e5, ior in 1.0f64..3.0,
                             lambda in 360.0f64..830.0) {
        let f = film_rt(cos_i, h, ior, lambda);
        prop_assert!((f.rs + f.ts - 1.0).abs() < 1e-9, "{f:?}");
        prop_assert!((f.rp + f.tp - 1.0).abs() < 1e-9, "{f:?}");
        prop_assert!((0.0..=1.0 + 1e-12).contains(&f.r()), "{f:?}");
        let n = film_rt(1.0, h, ior, lambda);
        prop_assert!((n.rs - n.rp).abs() < 1e-12, "{n:?}");
    }

    /// The film's optical path repeats: adding λ / (2 n cos θt) to the thickness changes the
    /// round-trip phase by exactly 2π, so R is unchanged; and an index-1 film is no film.
    #[test]
    fn film_reflectance_is_periodic_in_thickness(cos_i in 0.05f64..=1.0, h in 0.0f64..5000.0,
                                                  ior in 1.0f64..3.0, lambda in 360.0f64..830.0) {
        let cos_t = (1.0 - (1.0 - cos_i * cos_i) / (ior * ior)).sqrt();
        let period = lambda / (2.0 * ior * cos_t);
        let a = film_rt(cos_i, h, ior, lambda).r();
        let b = film_rt(cos_i, h + period, ior, lambda).r();
        prop_assert!((a - b).abs() < 1e-7, "{a} vs {b} (period {period} nm)");
        prop_assert!(film_rt(cos_i, h, 1.0, lambda).r() < 1e-12);
    }

    /// The f32 fast path agrees with the f64 reference.
    #[test]
    fn fast_film_agrees_with_reference(cos_i in 0.0f32..=1.0, h in 0.0f32..3000.0,
                                       ior in 1.0f32..3.0, lambda in 360.0f32..830.0) {
        let fast = FilmFresnel::new(cos_i, ior).reflectance(h, 1.0 / lambda);
        let exact = film_rt(cos_i as f64, h as f64, ior as f64, lambda as f64).r();
        prop_assert!((fast as f64 - exact).abs() < 2e-3, "{fast} vs {exact}");
    }
}

/// sRGB (linear) → XYZ, IEC 61966-2-1: the standard's forward matrix.
const SRGB_TO_XYZ: [[f64; 3]; 3] = [
    [0.412_456_4, 0.357_576_1, 0.180_437_5],
    [0.212_672_9, 0.715_152_2, 0.072_175_0],
    [0.019_333_9, 0.119_192_0, 0.950_304_1],
];

fn mul(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

proptest! {
    #![proptest_config(config(256))]

    /// linear sRGB → XYZ (standard matrix) → linear sRGB (ours) is the identity, and XYZ →
    /// sRGB → XYZ too: our matrix is the inverse of the standard's.
    #[test]
    fn xyz_srgb_round_trip(r in -0.5f64..2.0, g in -0.5f64..2.0, b in -0.5f64..2.0) {
        let rgb = [r, g, b];
        let back = xyz_to_linear_srgb(mul(&SRGB_TO_XYZ, rgb));
        for c in 0..3 {
            prop_assert!((back[c] - rgb[c]).abs() < 1e-5, "{rgb:?} -> {back:?}");
        }
        let xyz = rgb; // any triple is also an XYZ
        let again = mul(&SRGB_TO_XYZ, mul(&XYZ_TO_LINEAR_SRGB, xyz));
        for c in 0..3 {
            prop_assert!((again[c] - xyz[c]).abs() < 1e-5, "{xyz:?} -> {again:?}");
        }
    }

    /// The sRGB transfer curve round-trips and is monotonic.
    #[test]
    fn srgb_curve_round_trips(v in 0.0f32..=1.0, w in 0.0f32..=1.0) {
        prop_assert!((srgb_to_linear(linear_to_srgb(v)) - v).abs() < 1e-5);
        if v < w {
            prop_assert!(linear_to_srgb(v) <= linear_to_srgb(w));
        }
    }

    /// White stays white: with any stratified set of 8..64 wavelengths, a perfect reflector is
    /// exactly (1, 1, 1) and a grey one (c, c, c) in every channel whose weights sum positive
    /// (white balance divides by that sum). Where a channel's weights cancel or go negative (a
    /// few jittered wavelengths in the negative lobe of sRGB red), `set_normalised` falls back to
    /// the exact white integral: the channel is then the unbiased estimate, which the test checks
    /// against `set_unbiased`. A film that reflects nothing is black.
    #[test]
    fn white_and_grey_spectra_stay_neutral(n in 8usize..64, jitter in prop::collection::vec(0.0f32..1.0, 64),
                                           grey in 0.0f32..1.0) {
        let lambda: Vec<f32> = (0..n)
            .map(|i| 360.0 + 470.0 * (i as f32 + jitter[i]) / n as f32)
            .collect();
        let w = SpectralWeights::new(&lambda);
        let white = w.spectrum_rgb(&vec![1.0; n]);
        let g = w.spectrum_rgb(&vec![grey; n]);
        let mut u = SpectralWeights::new(&lambda);
        u.set_unbiased(&lambda);
        let unbiased = u.spectrum_rgb(&vec![1.0; n]);
        for c in 0..3 {
            // The unbiased weights are the raw ones over a positive constant: same sign of sum.
            let sum: f32 = u.weights().iter().map(|x| x[c]).sum();
            if sum > 1e-6 {
                prop_assert!((white[c] - 1.0).abs() < 1e-4, "{white:?}");
                prop_assert!((g[c] - grey).abs() < 1e-4, "{g:?}");
            } else {
                prop_assert!((white[c] - unbiased[c]).abs() < 1e-6, "{white:?} vs {unbiased:?}");
                prop_assert!((g[c] - grey * unbiased[c]).abs() < 1e-5, "{g:?}");
            }
        }
        let none = w.film_reflectance_rgb(&FilmFresnel::new(0.7, 1.0), 500.0);
        prop_assert!(none.iter().all(|c| c.abs() < 1e-6), "{none:?}");
    }
}

proptest! {
    #![proptest_config(config(24))]

    /// White light on a film several µm thick: the interference fringes are far finer than the
    /// eye's colour matching functions, so the reflection is neutral (R ≈ G ≈ B), as for a
    /// thick pane of glass.
    #[test]
    fn thick_films_reflect_white_light_white(h in 5000.0f64..8000.0, cos_i in 0.3f64..=1.0,
                                             ior in 1.2f64..1.6) {
        let grid = filmsplat::spectrum::reference_grid_nm();
        let rgb = film_rgb_reference(cos_i, h, ior, &grid);
        let mean = (rgb[0] + rgb[1] + rgb[2]) / 3.0;
        let spread = rgb.iter().map(|c| (c - mean).abs()).fold(0.0, f64::max);
        prop_assert!(mean > 0.01 && spread < 0.03 * mean, "{rgb:?}");
    }
}
