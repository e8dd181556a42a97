//! Geometry benchmarks: BVH build for 1M disks / spheres on a sphere shell, primary-ray
//! throughput (closest hit with layer blending) at 640×360, single-threaded and with rayon, and
//! memory per particle (printed once).
//!
//! Short runs: `cargo bench --bench geometry_bvh -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use filmsplat::geometry::{FilmGeometry, Primitive, Ray};
use glam::Vec3;
use rayon::prelude::*;

const N: usize = 1_000_000;
const W: usize = 640;
const H: usize = 360;

/// `n` points evenly spread on the unit sphere (Fibonacci lattice) and their spacing.
fn fibonacci_sphere(n: usize) -> (Vec<Vec3>, f32) {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let pts = (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).sqrt();
            let a = golden * i as f32;
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
        .collect();
    (pts, (4.0 * std::f32::consts::PI / n as f32).sqrt())
}

struct Cloud {
    pos: Vec<Vec3>,
    nrm: Vec<Vec3>,
    thk: Vec<f32>,
    disk_r: Vec<f32>,
    sphere_r: Vec<f32>,
}

fn cloud() -> Cloud {
    let (pos, spacing) = fibonacci_sphere(N);
    Cloud {
        nrm: pos.clone(),
        thk: pos.iter().map(|p| 500.0 + 300.0 * p.z).collect(),
        disk_r: vec![1.5 * spacing; N],
        sphere_r: vec![0.75 * spacing; N],
        pos,
    }
}

impl Cloud {
    fn build(&self, prim: Primitive) -> FilmGeometry {
        let r = if prim == Primitive::Disk {
            &self.disk_r
        } else {
            &self.sphere_r
        };
        FilmGeometry::particles(prim, &self.pos, &self.nrm, r, &self.thk).unwrap()
    }
}

/// Pinhole camera at (0, 0.4, 3) looking at the origin, 40° vertical field of view.
fn camera_ray(x: usize, y: usize) -> Ray {
    let eye = Vec3::new(0.0, 0.4, 3.0);
    let fwd = (-eye).normalize();
    let right = fwd.cross(Vec3::Y).normalize();
    let up = right.cross(fwd);
    let h = (20f32.to_radians()).tan();
    let sx = (2.0 * (x as f32 + 0.5) / W as f32 - 1.0) * h * W as f32 / H as f32;
    let sy = (1.0 - 2.0 * (y as f32 + 0.5) / H as f32) * h;
    Ray::new(eye, fwd + sx * right + sy * up)
}

/// Renders one frame of hit thicknesses; returns the sum (so nothing is optimised away).
fn frame_serial(g: &FilmGeometry) -> f32 {
    let mut s = 0.0;
    for y in 0..H {
        for x in 0..W {
            if let Some(h) = g.intersect(&camera_ray(x, y), 0.0, f32::INFINITY) {
                s += h.thickness_nm;
            }
        }
    }
    s
}

fn frame_parallel(g: &FilmGeometry) -> f32 {
    (0..H)
        .into_par_iter()
        .map(|y| {
            (0..W)
                .filter_map(|x| g.intersect(&camera_ray(x, y), 0.0, f32::INFINITY))
                .map(|h| h.thickness_nm)
                .sum::<f32>()
        })
        .sum()
}

fn report(c: &Cloud) {
    for prim in [Primitive::Disk, Primitive::Sphere] {
        let t = Instant::now();
        let g = c.build(prim);
        let build = t.elapsed().as_secs_f64();
        let nodes = g.bvh().nodes().len();
        let mut hits = 0usize;
        let mut coverage = 0u64;
        for y in 0..H {
            for x in 0..W {
                if let Some(h) = g.intersect(&camera_ray(x, y), 0.0, f32::INFINITY) {
                    hits += 1;
                    coverage += h.coverage as u64;
                }
            }
        }
        eprintln!(
            "{prim}: one build {build:.3} s, {:.1} bytes/particle, {nodes} nodes ({:.2} prims/leaf), \
             {hits} of {} pixels hit, mean coverage {:.2}",
            g.memory_bytes() as f64 / N as f64,
            N as f64 / (nodes.div_ceil(2)) as f64,
            W * H,
            coverage as f64 / hits.max(1) as f64
        );
    }
}

fn benches(crit: &mut Criterion) {
    let c = cloud();
    report(&c);

    let mut group = crit.benchmark_group("build_1M");
    group.sample_size(10);
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("disks", |b| b.iter(|| black_box(c.build(Primitive::Disk))));
    group.bench_function("spheres", |b| {
        b.iter(|| black_box(c.build(Primitive::Sphere)))
    });
    group.finish();

    let mut group = crit.benchmark_group("primary_640x360");
    group.sample_size(10);
    group.throughput(Throughput::Elements((W * H) as u64));
    for prim in [Primitive::Disk, Primitive::Sphere] {
        let g = c.build(prim);
        group.bench_function(format!("{prim}_1thread"), |b| {
            b.iter(|| black_box(frame_serial(&g)))
        });
        group.bench_function(format!("{prim}_rayon"), |b| {
            b.iter(|| black_box(frame_parallel(&g)))
        });
    }
    group.finish();
}

criterion_group!(geometry, benches);
criterion_main!(geometry);
