//! Estimation costs on 1M particles (kNN normals, radii, spacing) and the bubble sample.
//! Run: cargo bench --bench cloud_estimate -- --warm-up-time 1 --measurement-time 3

use criterion::{Criterion, criterion_group, criterion_main};
use filmsplat::pointcloud::PointCloud;
use filmsplat::pointcloud::estimate::{
    EstimateOptions, estimate_normals, estimate_radii, fill_missing, median_spacing,
};
use filmsplat::pointcloud::knn::{KnnTable, PointIndex};
use filmsplat::samples::{BubbleParams, bubble, fibonacci_sphere};
use glam::Vec3;
use std::hint::black_box;

const N: usize = 1_000_000;

fn benches(c: &mut Criterion) {
    let sphere = fibonacci_sphere(N, 1.0);
    // A gently wavy open sheet: exercises the MST orientation path.
    let side = 1000;
    let sheet: Vec<Vec3> = (0..side * side)
        .map(|i| {
            let (x, y) = (
                (i % side) as f32 / side as f32,
                (i / side) as f32 / side as f32,
            );
            Vec3::new(
                x + 0.0003 * (y * 977.0).sin(),
                y,
                0.05 * (6.0 * x).sin() * (4.0 * y).cos(),
            )
        })
        .collect();
    let mut g = c.benchmark_group("cloud_1M");
    g.sample_size(10);
    g.bench_function("kd_tree_build", |b| {
        b.iter(|| PointIndex::build(black_box(&sphere)))
    });
    g.bench_function("knn_table_k12", |b| {
        b.iter(|| KnnTable::build(black_box(&sphere), 12))
    });
    g.bench_function("median_spacing", |b| {
        b.iter(|| median_spacing(black_box(&sphere)))
    });
    g.bench_function("estimate_radii_k8", |b| {
        b.iter(|| estimate_radii(black_box(&sphere), 8, 0.6))
    });
    g.bench_function("estimate_normals_k12_sphere_radial", |b| {
        b.iter(|| estimate_normals(black_box(&sphere), 12))
    });
    g.bench_function("estimate_normals_k12_sheet_mst", |b| {
        b.iter(|| estimate_normals(black_box(&sheet), 12))
    });
    g.bench_function("fill_missing_bare_sphere", |b| {
        b.iter(|| {
            let mut cloud = PointCloud {
                positions: sphere.clone(),
                ..Default::default()
            };
            fill_missing(&mut cloud, &EstimateOptions::default())
        })
    });
    g.finish();
    let mut g = c.benchmark_group("samples");
    g.sample_size(10);
    g.bench_function("bubble_200k", |b| {
        b.iter(|| bubble(&BubbleParams::default()))
    });
    g.finish();
}

criterion_group!(cloud, benches);
criterion_main!(cloud);
