//! The BVH answers exactly what a brute-force loop over all primitives answers: closest hit (same
//! `t`, same particle, ties to the lowest index), and for disks the layer blending (same
//! cluster: coverage, exit distance, thickness, normal, heaviest particle).

use filmsplat::geometry::primitives::{intersect_disk, intersect_sphere};
use filmsplat::geometry::{DiskGeometry, FilmGeometry, LayerBlend, Primitive, Ray, SphereGeometry};
use glam::Vec3;

mod geometry_support;
use geometry_support::Rng;

struct Scene {
    name: &'static str,
    prim: Primitive,
    pos: Vec<Vec3>,
    nrm: Vec<Vec3>,
    rad: Vec<f32>,
    thk: Vec<f32>,
}

impl Scene {
    fn geometry(&self) -> FilmGeometry {
        FilmGeometry::particles(self.prim, &self.pos, &self.nrm, &self.rad, &self.thk).unwrap()
    }

    /// Brute-force closest hit: (t, particle, squared distance to centre for disks).
    fn brute_closest(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32, f32)> {
        let mut best: Option<(f32, u32, f32)> = None;
        for i in 0..self.pos.len() {
            let h = match self.prim {
                Primitive::Disk => intersect_disk(
                    ray,
                    self.pos[i],
                    self.nrm[i].normalize(),
                    self.rad[i],
                    t_min,
                    t_max,
                ),
                Primitive::Sphere => {
                    intersect_sphere(ray, self.pos[i], self.rad[i], t_min, t_max).map(|t| (t, 0.0))
                }
                Primitive::Mls => unreachable!("splat scenes only"),
            };
            if let Some((t, d2)) = h
                && best.is_none_or(|b| t < b.0)
            {
                best = Some((t, i as u32, d2));
            }
        }
        best
    }

    /// Brute-force layer blending for disks: (coverage, t_exit, thickness, normal, particle).
    fn brute_layer(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(u32, f32, f32, Vec3, u32)> {
        let (t0, i0, _) = self.brute_closest(ray, t_min, t_max)?;
        let n0 = self.nrm[i0 as usize].normalize();
        let r0 = self.rad[i0 as usize];
        let t_end = (t0 + LayerBlend::default().band(r0, n0.dot(ray.dir).abs())).min(t_max);
        let (mut count, mut t_exit, mut sw, mut sh, mut sn) = (0, t0, 0.0, 0.0, Vec3::ZERO);
        let (mut best_w, mut best_i) = (-1.0f32, 0u32);
        for j in 0..self.pos.len() {
            let nj = self.nrm[j].normalize();
            if j as u32 != i0 && (nj.dot(n0).abs() <= 0.5 || t_end <= t0) {
                continue;
            }
            let hi = if j as u32 == i0 { t_max } else { t_end };
            let Some((t, d2)) = intersect_disk(ray, self.pos[j], nj, self.rad[j], t_min, hi) else {
                continue;
            };
            let x = (1.0 - d2 / (self.rad[j] * self.rad[j])).max(0.0);
            let w = x * x;
            count += 1;
            t_exit = t_exit.max(t);
            sw += w;
            sh += w * self.thk[j];
            sn += w * nj.dot(n0).signum() * nj;
            if w > best_w || (w == best_w && (j as u32) < best_i) {
                best_w = w;
                best_i = j as u32;
            }
        }
        if sw > 1e-12 {
            Some((count, t_exit, sh / sw, sn.normalize(), best_i))
        } else {
            Some((count, t_exit, self.thk[i0 as usize], n0, i0))
        }
    }
}

fn random_scene(rng: &mut Rng, name: &'static str, prim: Primitive, n: usize) -> Scene {
    Scene {
        name,
        prim,
        pos: (0..n).map(|_| rng.in_box(0.0, 1.0)).collect(),
        nrm: (0..n).map(|_| rng.unit() * rng.range(0.5, 2.0)).collect(),
        rad: (0..n).map(|_| rng.range(0.02, 0.15)).collect(),
        thk: (0..n).map(|_| rng.range(100.0, 900.0)).collect(),
    }
}

fn scenes() -> Vec<Scene> {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut v = vec![
        random_scene(&mut rng, "random disks", Primitive::Disk, 800),
        random_scene(&mut rng, "random spheres", Primitive::Sphere, 800),
        random_scene(&mut rng, "single disk", Primitive::Disk, 1),
        random_scene(&mut rng, "single sphere", Primitive::Sphere, 1),
    ];
    for (name, prim) in [
        ("disks at one point", Primitive::Disk),
        ("spheres at one point", Primitive::Sphere),
    ] {
        let mut s = random_scene(&mut rng, name, prim, 300);
        s.pos.iter_mut().for_each(|p| *p = Vec3::splat(0.5));
        v.push(s);
    }
    // Coplanar disks in z = 0.4, normals ±z, overlapping.
    let mut s = random_scene(&mut rng, "coplanar disks", Primitive::Disk, 600);
    for (p, n) in s.pos.iter_mut().zip(&mut s.nrm) {
        p.z = 0.4;
        *n = if n.x > 0.0 { Vec3::Z } else { -Vec3::Z };
    }
    v.push(s);
    v
}

fn rays(rng: &mut Rng, s: &Scene, count: usize) -> Vec<(Ray, f32, f32)> {
    let mut out = Vec::with_capacity(count);
    for k in 0..count {
        let (t_min, t_max) = if k % 3 == 0 {
            (rng.range(0.0, 0.5), rng.range(0.5, 3.0))
        } else {
            (0.0, f32::INFINITY)
        };
        let ray = match k % 6 {
            // Random origin and direction.
            0 | 1 => Ray::new(rng.in_box(-0.5, 1.5), rng.unit()),
            // Aimed at a random particle (hits likely, often several overlapping).
            2 | 3 => {
                let target = s.pos[k % s.pos.len()] + rng.unit() * 0.05;
                let o = rng.in_box(-0.5, 1.5);
                Ray::new(o, target - o)
            }
            // Parallel to the z = 0.4 plane, in it or near it.
            4 => {
                let d = Vec3::new(rng.range(-1., 1.), rng.range(-1., 1.), 0.0);
                let z = if k % 12 == 4 {
                    0.4
                } else {
                    rng.range(0.3, 0.5)
                };
                Ray::new(Vec3::new(rng.range(-0.5, 1.5), rng.range(-0.5, 1.5), z), d)
            }
            // Starting at a particle centre (inside a sphere, on a disk).
            _ => Ray::new(s.pos[(k * 7) % s.pos.len()], rng.unit()),
        };
        out.push((ray, t_min, t_max));
    }
    out
}

#[test]
fn bvh_matches_brute_force() {
    let mut rng = Rng(42);
    for s in scenes() {
        let g = s.geometry();
        assert_eq!(g.len(), s.pos.len());
        let mut hits = 0;
        let mut blended = 0;
        for (ray, t_min, t_max) in rays(&mut rng, &s, 3000) {
            let brute = s.brute_closest(&ray, t_min, t_max);
            let single = g.intersect_single(&ray, t_min, t_max);
            let ctx = || format!("{}: ray {ray:?} t in ({t_min}, {t_max})", s.name);
            match (brute, single) {
                (None, None) => {}
                (Some((t, i, _)), Some(h)) => {
                    hits += 1;
                    assert!(
                        (h.t - t).abs() <= 1e-5 * t.abs().max(1e-3),
                        "{}: t {} vs {t}",
                        ctx(),
                        h.t
                    );
                    assert_eq!(h.particle, i, "{}", ctx());
                    assert!(h.t > t_min && h.t < t_max, "{}", ctx());
                    if s.prim == Primitive::Sphere {
                        let n = (ray.at(t) - s.pos[i as usize]) / s.rad[i as usize];
                        assert!((h.normal - n).length() < 1e-3, "{}", ctx());
                        assert_eq!(h.thickness_nm, s.thk[i as usize], "{}", ctx());
                    }
                }
                (b, h) => panic!("{}: brute {b:?} vs bvh {h:?}", ctx()),
            }

            let hit = g.intersect(&ray, t_min, t_max);
            assert_eq!(hit.is_some(), brute.is_some(), "{}", ctx());
            let Some(hit) = hit else { continue };
            assert!(
                hit.t > t_min && hit.t < t_max && hit.t <= hit.t_exit,
                "{}",
                ctx()
            );
            assert!((hit.position - ray.at(hit.t)).length() < 1e-5, "{}", ctx());
            assert!((hit.normal.length() - 1.0).abs() < 1e-5, "{}", ctx());
            if s.prim == Primitive::Sphere {
                assert_eq!(hit, single.unwrap(), "{}", ctx());
                continue;
            }
            let (cov, t_exit, thk, nrm, part) = s.brute_layer(&ray, t_min, t_max).unwrap();
            blended += (cov > 1) as usize;
            assert_eq!(hit.coverage, cov, "{}", ctx());
            assert_eq!(hit.t_exit, t_exit, "{}", ctx());
            assert!(
                (hit.thickness_nm - thk).abs() < 1e-3 * thk,
                "{}: {} vs {thk}",
                ctx(),
                hit.thickness_nm
            );
            assert!(
                (hit.normal - nrm).length() < 1e-4,
                "{}: {} vs {nrm}",
                ctx(),
                hit.normal
            );
            assert_eq!(hit.particle, part, "{}", ctx());
        }
        // The test must exercise hits (and, for overlapping disks, real blending).
        let want = if s.pos.len() == 1 { 20 } else { 300 };
        assert!(hits >= want, "{}: only {hits} hits", s.name);
        if s.prim == Primitive::Disk && s.pos.len() > 1 {
            assert!(blended >= 50, "{}: only {blended} blended hits", s.name);
        }
    }
}

#[test]
fn rays_parallel_to_coplanar_disks_miss_without_nan() {
    let s = scenes()
        .into_iter()
        .find(|s| s.name == "coplanar disks")
        .unwrap();
    let g = s.geometry();
    let mut rng = Rng(7);
    for _ in 0..500 {
        let d = Vec3::new(rng.range(-1., 1.), rng.range(-1., 1.), 0.0);
        let ray = Ray::new(Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), 0.4), d);
        assert!(g.intersect(&ray, 0.0, f32::INFINITY).is_none());
    }
}

#[test]
fn ray_from_inside_a_sphere_hits_its_exit() {
    let pos = [Vec3::ZERO, Vec3::new(5.0, 0.0, 0.0)];
    let g = SphereGeometry::build(&pos, &[], &[2.0, 1.0], &[100.0, 200.0]).unwrap();
    let mut rng = Rng(3);
    for _ in 0..200 {
        let o = rng.unit() * rng.range(0.0, 1.9);
        let d = rng.unit();
        let h = g.intersect(&Ray::new(o, d), 0.0, f32::INFINITY).unwrap();
        assert_eq!(h.particle, 0);
        assert!(((o + h.t * d).length() - 2.0).abs() < 1e-5);
        // Outward normal at the exit: along the ray, not flipped.
        assert!((h.normal - (o + h.t * d) / 2.0).length() < 1e-4 && h.normal.dot(d) > 0.0);
        assert_eq!((h.coverage, h.t_exit), (1, h.t));
    }
}

#[test]
fn empty_and_invalid_input() {
    let g = DiskGeometry::build(&[], &[], &[], &[]).unwrap();
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    assert!(g.is_empty() && g.intersect(&ray, 0.0, f32::INFINITY).is_none());
    assert!(g.bounds().is_empty());

    let p = vec![Vec3::ZERO; 4];
    let n = vec![Vec3::Z; 4];
    let r = vec![0.1; 4];
    let h = vec![300.0; 4];
    let err = |prim, p: &[Vec3], n: &[Vec3], r: &[f32], h: &[f32]| {
        FilmGeometry::particles(prim, p, n, r, h)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    assert!(err(Primitive::Disk, &p, &n[..3], &r, &h).contains("normals has 3 entries"));
    assert!(err(Primitive::Disk, &p, &n, &r[..2], &h).contains("radii has 2 entries"));
    assert!(err(Primitive::Sphere, &p, &n, &r, &h[..1]).contains("thickness has 1 entries"));
    let mut bad = p.clone();
    bad[2].y = f32::NAN;
    assert!(err(Primitive::Disk, &bad, &n, &r, &h).contains("particle 2"));
    let mut bad = n.clone();
    bad[3] = Vec3::ZERO;
    assert!(err(Primitive::Disk, &p, &bad, &r, &h).contains("particle 3 has an unusable normal"));
    let mut bad = r.clone();
    bad[1] = 0.0;
    assert!(err(Primitive::Sphere, &p, &[], &bad, &h).contains("particle 1 has an invalid radius"));
    let mut bad = h.clone();
    bad[0] = -1.0;
    assert!(
        err(Primitive::Sphere, &p, &[], &r, &bad).contains("particle 0 has an invalid thickness")
    );
    // Spheres need no normals; a zero ray direction hits nothing.
    let g = FilmGeometry::particles(Primitive::Sphere, &p, &[], &r, &h).unwrap();
    assert_eq!(g.primitive(), Some(Primitive::Sphere));
    let zero = Ray {
        origin: Vec3::new(0.0, 0.0, -1.0),
        dir: Vec3::ZERO,
    };
    assert!(g.intersect(&zero, 0.0, f32::INFINITY).is_none());
    assert!(
        g.intersect(
            &Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z),
            0.0,
            f32::INFINITY
        )
        .is_some()
    );
}

/// The generic BVH on plain boxes: closest-entry query equals brute force, `visit_segment` visits
/// every box the segment overlaps, `any` agrees with brute force.
#[test]
fn generic_bvh_queries_on_boxes() {
    use filmsplat::geometry::{Aabb, Bvh};
    let mut rng = Rng(77);
    let boxes: Vec<Aabb> = (0..3000)
        .map(|_| {
            let c = rng.in_box(0.0, 1.0);
            let e = Vec3::new(
                rng.range(0.0, 0.05),
                rng.range(0.0, 0.05),
                rng.range(0.0, 0.05),
            );
            Aabb::new(c - e, c + e)
        })
        .collect();
    let bvh = Bvh::build(&boxes);
    assert_eq!(bvh.len(), boxes.len());
    let order = bvh.order();
    let mut visited = vec![false; boxes.len()];
    for _ in 0..1000 {
        let ray = Ray::new(rng.in_box(-0.5, 1.5), rng.unit());
        let (t0, t1) = (rng.range(0.0, 0.5), rng.range(0.5, 2.0));
        let brute: Vec<Option<f32>> = boxes
            .iter()
            .map(|b| b.intersect_ray(&ray, t0, t1).map(|(tn, _)| tn))
            .collect();
        let want = brute
            .iter()
            .flatten()
            .copied()
            .fold(f32::INFINITY, f32::min);
        let mut got = f32::INFINITY;
        bvh.closest(&ray, t0, t1, |s, lim| {
            if let Some((tn, _)) = boxes[order[s as usize] as usize].intersect_ray(&ray, t0, *lim) {
                got = got.min(tn);
                *lim = lim.min(tn);
            }
        });
        assert_eq!(got, want);
        visited.iter_mut().for_each(|v| *v = false);
        bvh.visit_segment(&ray, t0, t1, |s| visited[order[s as usize] as usize] = true);
        for (i, hit) in brute.iter().enumerate() {
            assert!(
                hit.is_none() || visited[i],
                "box {i} overlaps the segment but was not visited"
            );
        }
        let any = bvh.any(&ray, t0, t1, |s| {
            boxes[order[s as usize] as usize]
                .intersect_ray(&ray, t0, t1)
                .is_some()
        });
        assert_eq!(any, want.is_finite());
    }
}
