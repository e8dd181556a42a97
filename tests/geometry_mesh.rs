//! Mesh geometry: closest hits against a brute-force Möller–Trumbore oracle in f64, smooth
//! interpolation, and thin-shell detection and merging.

mod geometry_support;

use filmsplat::geometry::{MeshGeometry, MeshSides, Ray};
use filmsplat::samples::icosphere;
use geometry_support::Rng;
use glam::Vec3;

/// Möller–Trumbore in f64: `(t, u, v)` (weights of b and c) for a hit at `t > 0`.
fn mt(ray: &Ray, a: Vec3, b: Vec3, c: Vec3) -> Option<(f64, f64, f64)> {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-14 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (t > 0.0).then_some((t, u, v))
}

#[test]
fn closest_hits_match_brute_force_on_random_rays() {
    let mut rng = Rng(7);
    let mut pos = Vec::new();
    let mut tris = Vec::new();
    for i in 0..400u32 {
        let c = rng.in_box(-1.0, 1.0);
        for _ in 0..3 {
            pos.push(c + 0.15 * rng.unit());
        }
        tris.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let thickness: Vec<f32> = (0..pos.len()).map(|i| 100.0 + i as f32).collect();
    let g = MeshGeometry::build(&pos, &tris, &[], &thickness).unwrap();
    let (mut agreed, mut hits) = (0, 0);
    for _ in 0..3000 {
        let ray = Ray::new(rng.in_box(-1.5, 1.5), rng.unit());
        // Brute force: every triangle, with its barycentric margin.
        let mut best: Option<(f64, usize, f64, f64)> = None;
        let mut margin = f64::INFINITY;
        for (k, t) in tris.iter().enumerate() {
            let [a, b, c] = t.map(|v| pos[v as usize]);
            if let Some((tt, u, v)) = mt(&ray, a, b, c) {
                margin = margin.min(u.abs()).min(v.abs()).min((1.0 - u - v).abs());
                if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && best.is_none_or(|b| tt < b.0) {
                    best = Some((tt, k, u, v));
                }
            }
        }
        if margin < 1e-4 {
            continue; // too close to an edge for the two methods to be compared exactly
        }
        let got = g.intersect(&ray, 0.0, f32::INFINITY);
        match (best, got) {
            (None, None) => {}
            (Some((t, k, u, v)), Some(h)) => {
                assert_eq!(h.particle as usize, k);
                assert!((h.t as f64 - t).abs() < 1e-4 * t.max(1.0), "{} vs {t}", h.t);
                let [ia, ib, ic] = tris[k];
                let want = (1.0 - u - v) * thickness[ia as usize] as f64
                    + u * thickness[ib as usize] as f64
                    + v * thickness[ic as usize] as f64;
                assert!((h.thickness_nm as f64 - want).abs() < 1e-2);
                assert!((h.position - ray.at(h.t)).length() < 1e-5);
                assert!(g.intersect(&ray, 0.0, h.t * 0.999).is_none());
                hits += 1;
            }
            (b, h) => panic!("{ray:?}: brute force {b:?}, bvh {h:?}"),
        }
        agreed += 1;
    }
    assert!(agreed > 2900 && hits > 300, "{agreed} {hits}");
}

#[test]
fn smooth_normals_follow_the_sphere_and_computed_normals_match_given_ones() {
    let m = icosphere(1.0, 3);
    let p = &m.vertices.positions;
    let t = vec![500.0; p.len()];
    let given =
        MeshGeometry::build(p, &m.triangles, m.vertices.normals.as_ref().unwrap(), &t).unwrap();
    let computed = MeshGeometry::build(p, &m.triangles, &[], &t).unwrap();
    let mut rng = Rng(3);
    for _ in 0..500 {
        let ray = Ray::new(3.0 * rng.unit(), Vec3::ZERO - 3.0 * rng.unit() * 0.3);
        let Some(h) = given.intersect(&ray, 0.0, f32::INFINITY) else {
            continue;
        };
        let exact = h.position.normalize();
        // Interpolated vertex normals are far closer to the sphere than the facets (~4.6°).
        assert!(h.normal.dot(exact) > 0.9995, "{}", h.normal.dot(exact));
        let c = computed.intersect(&ray, 0.0, f32::INFINITY).unwrap();
        assert!(c.normal.dot(h.normal) > 0.999);
        assert!((h.thickness_nm - 500.0).abs() < 1e-3);
    }
}

/// Two concentric icospheres of radii 1 ± w/2, the inner one turned inside out: the closed
/// shell an iso-surface makes around one layer of particles.
fn shell(w: f32) -> MeshGeometry {
    let outer = icosphere(1.0 + w / 2.0, 3);
    let inner = icosphere(1.0 - w / 2.0, 3);
    let mut pos = outer.vertices.positions.clone();
    let n0 = pos.len() as u32;
    pos.extend(&inner.vertices.positions);
    let mut tris = outer.triangles.clone();
    tris.extend(
        inner
            .triangles
            .iter()
            .map(|t| [t[0] + n0, t[2] + n0, t[1] + n0]),
    );
    let th = vec![400.0; pos.len()];
    MeshGeometry::build(&pos, &tris, &[], &th).unwrap()
}

#[test]
fn thin_shells_are_detected_and_merge_into_one_crossing() {
    let w = 0.02;
    let mut g = shell(w);
    let found = g.shell_width(500).expect("a shell");
    assert!((found - w).abs() < 0.1 * w, "{found}");
    // A single sphere (an open film: both ways lead far) is not a shell.
    let s = icosphere(1.0, 3);
    let single = MeshGeometry::build(
        &s.vertices.positions,
        &s.triangles,
        &[],
        &vec![1.0; s.vertices.len()],
    )
    .unwrap();
    assert_eq!(single.shell_width(500), None);

    let crossings = |g: &MeshGeometry, ray: &Ray| {
        let mut t = 0.0;
        let mut n = 0;
        while let Some(h) = g.intersect(ray, t, f32::INFINITY) {
            n += 1;
            t = h.t_exit + 1e-5;
        }
        n
    };
    let ray = Ray::new(Vec3::new(0.1, 0.2, -5.0), Vec3::Z);
    assert_eq!(crossings(&g, &ray), 4);
    g.set_sides(MeshSides::Merge(1.5 * found));
    assert_eq!(crossings(&g, &ray), 2);
}

#[test]
fn bad_meshes_are_refused_with_the_culprit_named() {
    let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let e = |r: filmsplat::Result<MeshGeometry>| r.unwrap_err().to_string();
    assert!(e(MeshGeometry::build(&p, &[[0, 1, 3]], &[], &[1.0; 3])).contains("triangle 0"));
    assert!(e(MeshGeometry::build(&p, &[[0, 1, 2]], &[], &[1.0; 2])).contains("thickness"));
    assert!(
        e(MeshGeometry::build(
            &p,
            &[[0, 1, 2]],
            &[],
            &[1.0, -1.0, 0.0]
        ))
        .contains("vertex 1")
    );
    let nan = [Vec3::ZERO, Vec3::NAN, Vec3::Y];
    assert!(e(MeshGeometry::build(&nan, &[[0, 1, 2]], &[], &[1.0; 3])).contains("vertex 1"));
}
