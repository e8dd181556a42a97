//! The fixed costs of a frame, stage by stage, on a particle file: the colour table, the
//! radius fit's neighbour search and fans, the first-order detail (12-neighbour search,
//! curvature, thickness gradient) and the disks' BVH build. Plain wall-clock timing (median of
//! `FILMSPLAT_BENCH_RUNS` runs, default 3) so it can also run under
//! `valgrind --tool=callgrind` for instruction counts (set `FILMSPLAT_BENCH_RUNS=1`).
//!
//! `cargo bench --bench fixed_costs -- FILE.ply [STAGE ...]`, stages: `lut`, `lut_cached`,
//! `index`, `fit`, `detail`, `bvh` (default: all). Without a file it uses a 1M-particle
//! bubble sample (generating it takes ~3 s).

use filmsplat::geometry::DiskGeometry;
use filmsplat::io::{ReadOptions, read_cloud};
use filmsplat::pointcloud::PointCloud;
use filmsplat::pointcloud::curvature::first_order_detail;
use filmsplat::pointcloud::estimate::{EstimateOptions, fill_missing};
use filmsplat::pointcloud::gaps::fit_radii;
use filmsplat::pointcloud::knn::PointIndex;
use filmsplat::samples::{BubbleParams, bubble};
use filmsplat::spectrum::FilmLut;
use std::hint::black_box;
use std::time::Instant;

fn median_secs(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// The file's cloud (or the 1M bubble), with what it lacks (normals, radii, thickness)
/// estimated as `render` would, so every stage has its inputs.
fn load(args: &[String]) -> PointCloud {
    let mut cloud = match args.iter().find(|a| !a.starts_with('-') && a.contains('.')) {
        Some(path) => read_cloud(path.as_ref(), &ReadOptions::default()).expect("readable cloud"),
        None => bubble(&BubbleParams {
            particles: 1_000_000,
            ..Default::default()
        }),
    };
    fill_missing(&mut cloud, &EstimateOptions::default());
    cloud
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let known = ["lut", "lut_cached", "index", "fit", "detail", "bvh"];
    let mut stages: Vec<&str> = known
        .iter()
        .copied()
        .filter(|s| args.iter().any(|a| a == s))
        .collect();
    if stages.is_empty() {
        stages = known.to_vec();
    }
    let runs = std::env::var("FILMSPLAT_BENCH_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3);
    let cloud = load(&args);
    let n = cloud.len();
    let normals = cloud.normals.clone().unwrap_or_default();
    let thickness = cloud.thickness_nm.clone().unwrap_or_default();
    let radii = cloud.radius.clone().unwrap_or_default();
    println!(
        "{n} particles, median of {runs} runs, {} threads",
        rayon::current_num_threads()
    );
    for stage in stages {
        let secs = match stage {
            "lut" => median_secs(runs, || FilmLut::build_uncached(1.33).prebuild()),
            "lut_cached" => median_secs(runs, || {
                let lut = FilmLut::new(1.33);
                lut.prebuild();
                black_box(lut.reflectance_rgb(0.5, 300.0));
            }),
            "index" => median_secs(runs, || {
                black_box(PointIndex::build(&cloud.positions).len());
            }),
            "fit" => median_secs(runs, || {
                let mut r = radii.clone();
                black_box(fit_radii(&cloud.positions, &normals, &mut r, None));
            }),
            "detail" => median_secs(runs, || {
                black_box(first_order_detail(
                    &cloud.positions,
                    &normals,
                    &thickness,
                    &radii,
                    12,
                ));
            }),
            "bvh" => median_secs(runs, || {
                let g = DiskGeometry::build(&cloud.positions, &normals, &radii, &thickness);
                black_box(g.map(|g| g.memory_bytes()).unwrap_or(0));
            }),
            _ => continue,
        };
        println!("{stage:<11} {secs:8.3} s");
    }
}
