//! MLS surface vs disks vs spheres, for the README's "MLS" table:
//! 1. the bubble sample of N particles (default 1M) through the whole pipeline as `render` runs
//!    it (PLY written once, then `pipeline::prepare` per primitive): build time, primary rays
//!    per second (one closest-hit query per pixel centre, all threads), time per frame of a
//!    full render, and CIEDE2000 of each rendered image against the disk render;
//! 2. surface error on an analytic unit sphere of Fibonacci particles (radii 0.92× spacing):
//!    distance of the first hit from the sphere and normal error, over random rays.
//!
//! `cargo bench --bench mls` (env: FILMSPLAT_BENCH_PARTICLES, FILMSPLAT_BENCH_SPP,
//! FILMSPLAT_BENCH_SIZE=WxH, FILMSPLAT_BENCH_SPHERE = particles on the analytic sphere).
//!
//! `FILMSPLAT_BENCH_DUMP=OUT FILMSPLAT_BENCH_INPUT=CLOUD cargo bench --bench mls` instead writes
//! every MLS crossing of a grid of camera rays over CLOUD (continued past each crossing as the
//! integrator does, plus the ray reflected at each crossing) to OUT, one line per crossing
//! (`ray k t nx ny nz`), to compare the surface of two versions of the code.

use filmsplat::geometry::{DiskGeometry, FilmGeometry, MlsSurface, Primitive, Ray, SphereGeometry};
use filmsplat::image::RgbImage;
use filmsplat::image::metrics::delta_e_stats;
use filmsplat::io::write_ply;
use filmsplat::pipeline;
use filmsplat::samples::{BubbleParams, bubble, fibonacci_spacing, fibonacci_sphere};
use filmsplat::scene::SceneDesc;
use std::time::Instant;

mod support;
use support::{primary_rays, thread_cpu_ns};

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Primary rays per second (millions) and the number of pixels hit.
fn primary(p: &pipeline::Prepared, w: usize, h: usize) -> (f64, usize) {
    primary_rays(&p.scene.camera, w, h, |ray| {
        p.scene
            .geometry
            .intersect(ray, 0.0, f32::INFINITY)
            .is_some()
    })
}

/// Primary rays per CPU-second of one thread (millions; robust when other processes share the
/// cores), over every 4th row.
fn primary_cpu(p: &pipeline::Prepared, w: usize, h: usize) -> Option<f64> {
    let aspect = w as f32 / h as f32;
    let cam = &p.scene.camera;
    let c0 = thread_cpu_ns()?;
    let mut hits = 0usize;
    for y in (0..h).step_by(4) {
        for x in 0..w {
            let ray = cam.ray(
                (x as f32 + 0.5) / w as f32,
                (y as f32 + 0.5) / h as f32,
                aspect,
            );
            hits += p
                .scene
                .geometry
                .intersect(&ray, 0.0, f32::INFINITY)
                .is_some() as usize;
        }
    }
    std::hint::black_box(hits);
    let ns = thread_cpu_ns()? - c0;
    Some((w * h.div_ceil(4)) as f64 / (ns as f64 * 1e-9) / 1e6)
}

/// Mean and max distance of first hits from the unit sphere (in spacings) and mean and max
/// normal error (degrees) over `rays` random rays aimed inside the sphere.
fn sphere_error(g: &FilmGeometry, d: f32, rays: usize) -> [f64; 4] {
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    let mut f = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    let mut acc = [0.0f64; 4];
    let (mut n, mut tries) = (0, 0);
    while n < rays && tries < 20 * rays {
        tries += 1;
        let o = glam::Vec3::new(f(), f(), f());
        let target = glam::Vec3::new(f(), f(), f()) * 0.5;
        if o.length() < 0.3 {
            continue;
        }
        let o = 3.0 * o.normalize();
        let Some(h) = g.intersect(&Ray::new(o, target - o), 0.0, f32::INFINITY) else {
            continue;
        };
        n += 1;
        let e = ((h.position.length() - 1.0).abs() / d) as f64;
        let nrm = h.position.normalize();
        let a = (h.normal.dot(nrm).abs().min(1.0).acos().to_degrees()) as f64;
        acc = [acc[0] + e, acc[1].max(e), acc[2] + a, acc[3].max(a)];
    }
    let n = n.max(1) as f64;
    [acc[0] / n, acc[1], acc[2] / n, acc[3]]
}

/// Writes the crossings of camera rays and of the rays reflected at them (see the module docs).
fn dump_hits(input: &str, out: &str, w: usize, h: usize) {
    use std::fmt::Write;
    let toml = format!(
        "[input]\ncloud = {input:?}\n[film]\nprimitive = \"mls\"\n[render]\nwidth = {w}\nheight = {h}\n"
    );
    let desc = SceneDesc::from_toml(&toml, "bench").unwrap();
    let p = pipeline::prepare(&desc, std::path::Path::new("."), false).unwrap();
    let g = &p.scene.geometry;
    let mut text = String::new();
    let chain = |id: usize, ray: &Ray, t0: f32, text: &mut String| {
        let (mut t, mut hits) = (t0, Vec::new());
        while let Some(hit) = g.intersect(ray, t, f32::INFINITY) {
            let n = hit.normal;
            writeln!(
                text,
                "{id} {} {} {} {} {}",
                hits.len(),
                hit.t,
                n.x,
                n.y,
                n.z
            )
            .unwrap();
            t = hit.t_exit + p.scene.epsilon;
            hits.push(hit);
            if hits.len() == 16 {
                break;
            }
        }
        hits
    };
    let aspect = w as f32 / h as f32;
    for y in 0..h {
        for x in 0..w {
            let id = 2 * (y * w + x);
            let (u, v) = ((x as f32 + 0.37) / w as f32, (y as f32 + 0.61) / h as f32);
            let ray = p.scene.camera.ray(u, v, aspect);
            if let Some(hit) = chain(id, &ray, 0.0, &mut text).first() {
                let cos_signed = ray.dir.dot(hit.normal);
                let n = hit.normal * -cos_signed.signum();
                let dir = (ray.dir - 2.0 * ray.dir.dot(n) * n).normalize();
                let skip = (p.scene.layer_skip / cos_signed.abs().max(0.1)).max(p.scene.epsilon);
                chain(id + 1, &Ray::new(hit.position, dir), skip, &mut text);
            }
        }
    }
    std::fs::write(out, text).unwrap();
}

fn main() {
    if let Ok(out) = std::env::var("FILMSPLAT_BENCH_DUMP") {
        let input: String = env_or("FILMSPLAT_BENCH_INPUT", String::new());
        let size: String = env_or("FILMSPLAT_BENCH_SIZE", "320x180".to_string());
        let (w, h) = size.split_once('x').unwrap();
        dump_hits(&input, &out, w.parse().unwrap(), h.parse().unwrap());
        return;
    }
    let n: usize = env_or("FILMSPLAT_BENCH_PARTICLES", 1_000_000);
    let spp: u32 = env_or("FILMSPLAT_BENCH_SPP", 4);
    let size: String = env_or("FILMSPLAT_BENCH_SIZE", "960x540".to_string());
    let m: usize = env_or("FILMSPLAT_BENCH_SPHERE", 100_000);
    let (w, h): (usize, usize) = size
        .split_once('x')
        .map(|(a, b)| (a.parse().unwrap(), b.parse().unwrap()))
        .unwrap();
    println!(
        "bubble, {n} particles, {w}x{h}, {spp} spp, {} threads",
        rayon::current_num_threads()
    );
    let path = std::env::temp_dir().join(format!("filmsplat-bench-mls-{n}.ply"));
    write_ply(
        &path,
        &bubble(&BubbleParams {
            particles: n,
            ..BubbleParams::default()
        }),
    )
    .unwrap();

    println!(
        "\n| primitive | build | memory/particle | primary rays (all threads; 1 thread per CPU-second) | render {w}×{h}, {spp} spp | ΔE2000 vs disks (mean / p95 / max) |"
    );
    println!("|---|---|---|---|---|---|");
    let mut reference: Option<RgbImage> = None;
    let only: String = env_or("FILMSPLAT_BENCH_ONLY", String::new());
    for prim in ["disk", "sphere", "mls"] {
        if !only.is_empty() && only != prim {
            continue;
        }
        let toml = format!(
            "[input]\ncloud = {:?}\n[film]\nprimitive = \"{prim}\"\n[render]\nwidth = {w}\nheight = {h}\nspp = {spp}\n",
            path.to_str().unwrap()
        );
        let desc = SceneDesc::from_toml(&toml, "bench").unwrap();
        let p = pipeline::prepare(&desc, std::path::Path::new("."), false).unwrap();
        let bytes = p.scene.geometry.memory_bytes() as f64 / n as f64;
        let (rate, hits) = primary(&p, w, h);
        let cpu = primary_cpu(&p, w, h).map_or("?".to_string(), |r| format!("{r:.2}"));
        let t = Instant::now();
        let out = pipeline::render(&p, &p.shot).unwrap();
        let frame = t.elapsed().as_secs_f64();
        let img =
            RgbImage::from_data(w, h, out.rgb.iter().map(|c| c.to_array()).collect()).unwrap();
        let de = match &reference {
            None => "—".to_string(),
            Some(r) => {
                let s = delta_e_stats(r, &img).unwrap();
                format!("{:.2} / {:.2} / {:.1}", s.mean, s.p95, s.max)
            }
        };
        if prim == "disk" {
            reference = Some(img);
        }
        println!(
            "| {prim} | {:.2} s | {bytes:.0} B | {rate:.2} M/s, {cpu} M/CPU-s ({hits} px hit) | {frame:.1} s | {de} |",
            p.build_time.as_secs_f64()
        );
    }
    let _ = std::fs::remove_file(&path);

    // Surface error on the analytic sphere.
    let pos = fibonacci_sphere(m, 1.0);
    let d = fibonacci_spacing(m, 1.0);
    let r = vec![0.92 * d; m];
    let thk = vec![500.0; m];
    println!("\nunit sphere, {m} Fibonacci particles, spacing d = {d:.5}, 20000 rays");
    println!(
        "| primitive | build | distance from the sphere, mean / max (d) | normal error mean / max |"
    );
    println!("|---|---|---|---|");
    for prim in [Primitive::Disk, Primitive::Sphere, Primitive::Mls] {
        let t = Instant::now();
        let g: FilmGeometry = match prim {
            Primitive::Mls => MlsSurface::build(&pos, &pos, &r, &thk).unwrap().into(),
            Primitive::Disk => {
                let mut g = DiskGeometry::build(&pos, &pos, &r, &thk).unwrap();
                g.set_curvature(&vec![1.0; m]).unwrap(); // exact curvature of the unit sphere
                g.into()
            }
            Primitive::Sphere => {
                let half: Vec<f32> = r.iter().map(|r| 0.5 * r).collect();
                SphereGeometry::build(&pos, &pos, &half, &thk)
                    .unwrap()
                    .into()
            }
        };
        let build = t.elapsed().as_secs_f64();
        let e = sphere_error(&g, d, 20_000);
        println!(
            "| {prim} | {build:.3} s | {:.4} / {:.4} | {:.3}° / {:.3}° |",
            e[0], e[1], e[2], e[3]
        );
    }
}
