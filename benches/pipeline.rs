//! Whole-pipeline figures for the README: a bubble of N particles (default 1M) — generate, write
//! and load the PLY, build the tree, primary-ray throughput, and a 1280×720 render at 16 spp —
//! for disks and for spheres. Prints a Markdown table. Each step runs once (these are seconds,
//! not nanoseconds), after a warm-up of the thread pool.
//!
//! `cargo bench --bench pipeline` (env: FILMSPLAT_BENCH_PARTICLES, FILMSPLAT_BENCH_SPP,
//! FILMSPLAT_BENCH_SIZE=WxH).

use filmsplat::geometry::{FilmGeometry, Primitive};
use filmsplat::io::{ReadOptions, read_cloud, write_ply};
use filmsplat::pointcloud::curvature::{curvature_from_table, gradient_from_table};
use filmsplat::pointcloud::knn::KnnTable;
use filmsplat::render::{
    Camera, Environment, FilmShader, RenderSettings, Scene, ShadingMode, Studio, render,
};
use filmsplat::samples::{BubbleParams, bubble};
use filmsplat::spectrum::WavelengthStrategy;
use glam::Vec3;
use std::time::Instant;

mod support;

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() {
    // `cargo bench` passes --bench; ignore arguments.
    let n: usize = env_or("FILMSPLAT_BENCH_PARTICLES", 1_000_000);
    let spp: u32 = env_or("FILMSPLAT_BENCH_SPP", 16);
    let size: String = env_or("FILMSPLAT_BENCH_SIZE", "1280x720".to_string());
    let (w, h) = size
        .split_once('x')
        .map(|(a, b)| (a.parse().unwrap(), b.parse().unwrap()))
        .unwrap();
    println!(
        "bubble, {n} particles, {w}x{h}, {spp} spp, {} threads",
        rayon::current_num_threads()
    );

    let t = Instant::now();
    let cloud = bubble(&BubbleParams {
        particles: n,
        ..BubbleParams::default()
    });
    let generate = t.elapsed().as_secs_f64();
    let path = std::env::temp_dir().join(format!("filmsplat-bench-{n}.ply"));
    write_ply(&path, &cloud).unwrap();
    let bytes = std::fs::metadata(&path).unwrap().len();
    let t = Instant::now();
    let cloud = read_cloud(&path, &ReadOptions::default()).unwrap();
    let load = t.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&path);
    println!(
        "generate {generate:.2} s; PLY {:.1} MB loads in {load:.3} s ({:.0} MB/s)",
        bytes as f64 / 1e6,
        bytes as f64 / 1e6 / load
    );

    println!(
        "\n| primitive | tree build | first-order detail | memory/particle | primary rays | render {w}×{h}, {spp} spp | rays in render |"
    );
    println!("|---|---|---|---|---|---|---|");
    let shader = FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered);
    for prim in [Primitive::Disk, Primitive::Sphere] {
        let radii: Vec<f32> = match prim {
            Primitive::Disk | Primitive::Mls => cloud.radius.clone().unwrap(),
            Primitive::Sphere => cloud
                .radius
                .as_ref()
                .unwrap()
                .iter()
                .map(|r| 0.5 * r)
                .collect(),
        };
        let t = Instant::now();
        let geometry = FilmGeometry::particles(
            prim,
            &cloud.positions,
            cloud.normals.as_ref().unwrap(),
            &radii,
            cloud.thickness_nm.as_ref().unwrap(),
        )
        .unwrap();
        let build = t.elapsed().as_secs_f64();
        // First-order splat detail (disks only): one kNN table, curvature and thickness gradient.
        let mut geometry = geometry;
        let t = Instant::now();
        if let FilmGeometry::Disks(geometry) = &mut geometry {
            let normals = cloud.normals.as_ref().unwrap();
            let table = KnnTable::build(&cloud.positions, 12);
            geometry
                .set_curvature(&curvature_from_table(&cloud.positions, normals, &table))
                .unwrap();
            let grad = gradient_from_table(
                &cloud.positions,
                normals,
                cloud.thickness_nm.as_ref().unwrap(),
                cloud.radius.as_deref().unwrap_or_default(),
                &table,
            );
            geometry.set_thickness_gradient(&grad).unwrap();
        }
        let detail = t.elapsed().as_secs_f64();
        let bytes_per = geometry.memory_bytes() as f64 / n as f64;

        let camera = Camera::frame(
            Vec3::ZERO,
            1.0,
            Vec3::new(0.35, 0.3, 1.0),
            Vec3::Y,
            40.0,
            w as f32 / h as f32,
        );
        // Primary rays: one closest-hit query per pixel centre, all threads.
        let (primary, hits) = support::primary_rays(&camera, w, h, |ray| {
            geometry.intersect(ray, 0.0, f32::INFINITY).is_some()
        });
        let scene = Scene {
            geometry,
            camera,
            environment: Environment::Studio(Studio::default()),
            layer_skip: 0.5 * radii[0],
            epsilon: 1e-5,
            staging: Default::default(),
        };
        let settings = RenderSettings {
            width: w,
            height: h,
            spp,
            ..RenderSettings::default()
        };
        let t = Instant::now();
        let out = render(&scene, &shader, &settings).unwrap();
        let secs = t.elapsed().as_secs_f64();
        println!(
            "| {prim} | {build:.3} s | {} | {bytes_per:.0} B | {primary:.2} M/s ({:.0}% hit) | {secs:.1} s | {:.2} M/s |",
            if prim == Primitive::Disk {
                format!("{detail:.2} s")
            } else {
                "—".to_string()
            },
            100.0 * hits as f64 / (w * h) as f64,
            out.rays as f64 / secs / 1e6
        );
    }
}
