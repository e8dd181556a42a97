//! Helpers shared by the whole-render benchmarks.
#![allow(dead_code)]

use std::time::Instant;

use filmsplat::geometry::Ray;
use filmsplat::render::Camera;
use rayon::prelude::*;

/// Casts one ray through every pixel centre of a `w`×`h` image on all threads; `hit` answers
/// whether the ray hits. Returns (million rays per second, pixels hit).
pub fn primary_rays(
    cam: &Camera,
    w: usize,
    h: usize,
    hit: impl Fn(&Ray) -> bool + Sync,
) -> (f64, usize) {
    let aspect = w as f32 / h as f32;
    let t = Instant::now();
    let hits: usize = (0..h)
        .into_par_iter()
        .map(|y| {
            (0..w)
                .filter(|&x| {
                    hit(&cam.ray(
                        (x as f32 + 0.5) / w as f32,
                        (y as f32 + 0.5) / h as f32,
                        aspect,
                    ))
                })
                .count()
        })
        .sum();
    ((w * h) as f64 / t.elapsed().as_secs_f64() / 1e6, hits)
}

/// CPU time of the calling thread in nanoseconds (Linux schedstat), if available.
pub fn thread_cpu_ns() -> Option<u64> {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}
