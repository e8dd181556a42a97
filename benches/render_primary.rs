//! Primary-ray throughput of [`DiskGeometry::intersect`] as the renderer uses it: a 1M-disk
//! sphere shell (Fibonacci lattice, radii 0.9–1.5× the spacing) seen by a pinhole camera at
//! 1280×720 that the shell fills completely, traced in 16×16 tiles one ray at a time,
//! single-threaded and with rayon. Also prints build time, bytes per particle and the
//! single-thread throughput per CPU-second (unaffected by other processes on the machine) once.
//! The same frame by rasterising the disks (`DiskGeometry::primary_layers`, its projection and
//! binning included), checked to see the same layers, on one thread and with rayon, and both
//! queries per CPU-second of the process with their ratio.
//!
//! Short runs: `cargo bench --bench render_primary -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use filmsplat::geometry::{DiskGeometry, PinholeGrid, RASTER_TILE, Ray, SurfaceHit};
use glam::Vec3;
use rayon::prelude::*;

mod support;
use support::thread_cpu_ns;

const N: usize = 1_000_000;
const W: usize = 1280;
const H: usize = 720;
const TILE: usize = 16;

/// A 1M-disk Fibonacci sphere shell with radii between 0.9 and 1.5 times the spacing.
fn shell() -> DiskGeometry {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let spacing = (4.0 * std::f32::consts::PI / N as f32).sqrt();
    let pos: Vec<Vec3> = (0..N)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / N as f32;
            let r = (1.0 - z * z).sqrt();
            let a = golden * i as f32;
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
        .collect();
    let radii: Vec<f32> = (0..N as u32)
        .map(|i| {
            let h = i.wrapping_mul(0x9e37_79b9) ^ (i >> 7).wrapping_mul(0x85eb_ca6b);
            (0.9 + 0.6 * (h >> 8) as f32 / (1u32 << 24) as f32) * spacing
        })
        .collect();
    let thk: Vec<f32> = pos.iter().map(|p| 500.0 + 300.0 * p.z).collect();
    DiskGeometry::build(&pos, &pos, &radii, &thk).unwrap()
}

/// Pinhole camera 1.6 units from the centre with a 40° vertical field of view: every pixel
/// sees the shell (the frame corners are at 36.6° off axis, the silhouette at 38.7°).
struct Camera {
    eye: Vec3,
    fwd: Vec3,
    right: Vec3,
    up: Vec3,
    h: f32,
}

impl Camera {
    fn new() -> Camera {
        let eye = Vec3::new(0.3, 0.4, 1.5).normalize() * 1.6;
        let fwd = (-eye).normalize();
        let right = fwd.cross(Vec3::Y).normalize();
        Camera {
            eye,
            fwd,
            right,
            up: right.cross(fwd),
            h: 20f32.to_radians().tan(),
        }
    }

    /// The camera's pixel-centre grid for the rasterised query.
    fn grid(&self) -> PinholeGrid {
        PinholeGrid {
            eye: self.eye,
            forward: self.fwd,
            right: self.right,
            up: self.up,
            half_width: self.h * W as f32 / H as f32,
            half_height: self.h,
            width: W,
            height: H,
        }
    }

    fn ray(&self, x: usize, y: usize) -> Ray {
        let sx = (2.0 * (x as f32 + 0.5) / W as f32 - 1.0) * self.h * W as f32 / H as f32;
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / H as f32) * self.h;
        Ray::new(self.eye, self.fwd + sx * self.right + sy * self.up)
    }
}

/// CPU time of the whole process (all threads), seconds (Linux `/proc/self/stat`, 10 ms
/// ticks); 0 where unavailable.
fn process_cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or(vec![], |(_, rest)| rest.split_whitespace().collect());
    // utime and stime are fields 14 and 15 of the line, 12 and 13 after the name.
    let tick = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (tick(11) + tick(12)) / 100.0
}

type Query = fn(&DiskGeometry, &Ray, f32, f32) -> Option<SurfaceHit>;

/// Traces one 16×16 tile; returns (sum of thicknesses, hits, total coverage).
fn tile(g: &DiskGeometry, cam: &Camera, t: usize) -> (f32, u32, u32) {
    tile_with(g, cam, t, DiskGeometry::intersect)
}

fn tile_with(g: &DiskGeometry, cam: &Camera, t: usize, q: Query) -> (f32, u32, u32) {
    let (tx, ty) = (t % W.div_ceil(TILE), t / W.div_ceil(TILE));
    let mut acc = (0.0, 0, 0);
    for y in ty * TILE..((ty + 1) * TILE).min(H) {
        for x in tx * TILE..((tx + 1) * TILE).min(W) {
            if let Some(h) = q(g, &cam.ray(x, y), 0.0, f32::INFINITY) {
                acc.0 += h.thickness_nm;
                acc.1 += 1;
                acc.2 += h.coverage;
            }
        }
    }
    acc
}

const TILES: usize = W.div_ceil(TILE) * H.div_ceil(TILE);

fn frame_serial(g: &DiskGeometry, cam: &Camera) -> (f32, u32, u32) {
    (0..TILES)
        .map(|t| tile(g, cam, t))
        .fold((0.0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2))
}

fn frame_serial_with(g: &DiskGeometry, cam: &Camera, q: Query) -> (f32, u32, u32) {
    (0..TILES)
        .map(|t| tile_with(g, cam, t, q))
        .fold((0.0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2))
}

fn frame_parallel(g: &DiskGeometry, cam: &Camera) -> (f32, u32, u32) {
    (0..TILES)
        .into_par_iter()
        .map(|t| tile(g, cam, t))
        .reduce(|| (0.0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2))
}

fn benches(crit: &mut Criterion) {
    let t = Instant::now();
    let g = shell();
    let build = t.elapsed().as_secs_f64();
    let cam = Camera::new();
    let (_, hits, cov) = frame_parallel(&g, &cam);
    eprintln!(
        "disk shell: build {build:.3} s (incl. input generation), {:.1} bytes/particle, \
         {hits} of {} pixels hit, mean coverage {:.2}",
        g.memory_bytes() as f64 / N as f64,
        W * H,
        cov as f64 / hits.max(1) as f64
    );

    // Throughput per CPU-second of this thread (robust when other processes share the cores).
    for (name, f) in [
        ("intersect", DiskGeometry::intersect as Query),
        ("intersect_single", DiskGeometry::intersect_single),
    ] {
        let c0 = thread_cpu_ns();
        black_box(frame_serial_with(&g, &cam, f));
        if let (Some(c0), Some(c1)) = (c0, thread_cpu_ns()) {
            let rate = (W * H) as f64 / ((c1 - c0) as f64 * 1e-9);
            eprintln!(
                "{name}: {:.2} M rays per CPU-second (1 thread)",
                rate * 1e-6
            );
        }
    }

    // The same frame by rasterising the disks (projection and binning included), tile by
    // tile as a renderer consumes it.
    let raster = |g: &DiskGeometry| {
        let r = g.primary_raster(&cam.grid()).unwrap();
        (0..r.tiles())
            .into_par_iter()
            .map(|t| {
                let mut out = [None; RASTER_TILE * RASTER_TILE];
                r.tile(t, &|x, y| cam.ray(x, y), &mut out);
                out.iter().flatten().fold((0.0, 0u32, 0u32), |a, h| {
                    (a.0 + h.thickness_nm, a.1 + 1, a.2 + h.coverage)
                })
            })
            .reduce(|| (0.0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2))
    };
    let (_, rhits, rcov) = raster(&g);
    assert_eq!(
        (rhits, rcov),
        (hits, cov),
        "the raster sees the same layers"
    );
    // Both on all threads, per CPU-second of the whole process (ten frames each, alternating).
    let (mut cpu_bvh, mut cpu_raster) = (0.0, 0.0);
    for _ in 0..10 {
        let c0 = process_cpu_s();
        black_box(frame_parallel(&g, &cam));
        let c1 = process_cpu_s();
        black_box(raster(&g));
        let c2 = process_cpu_s();
        cpu_bvh += c1 - c0;
        cpu_raster += c2 - c1;
    }
    let rays = 10.0 * (W * H) as f64 * 1e-6;
    eprintln!(
        "rayon, per CPU-second of the process: intersect {:.2} M rays, raster {:.2} M \
         rays, ratio {:.2}",
        rays / cpu_bvh,
        rays / cpu_raster,
        cpu_bvh / cpu_raster
    );

    let mut group = crit.benchmark_group("primary_1280x720");
    group.sample_size(10);
    group.throughput(Throughput::Elements((W * H) as u64));
    group.bench_function("disk_1thread", |b| {
        b.iter(|| black_box(frame_serial(&g, &cam)))
    });
    group.bench_function("disk_rayon", |b| {
        b.iter(|| black_box(frame_parallel(&g, &cam)))
    });
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    group.bench_function("raster_1thread", |b| {
        b.iter(|| one.install(|| black_box(raster(&g))))
    });
    group.bench_function("raster_rayon", |b| b.iter(|| black_box(raster(&g))));
    group.finish();
}

criterion_group!(render_primary, benches);
criterion_main!(render_primary);
