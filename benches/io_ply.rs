//! PLY reading speed: a 1M-particle binary little-endian file (x y z nx ny nz rh, float;
//! 28 MB) read by `read_cloud`, against `std::fs::read` of the same bytes (page cache hot).
//! For reference, 100k particles in ASCII by `read_cloud` and in binary by ply-rs-bw's generic
//! parser (a hash map per element).

use std::hint::black_box;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use filmsplat::io::{ReadOptions, read_cloud};

const HEADER: &str = "property float x\nproperty float y\nproperty float z\n\
    property float nx\nproperty float ny\nproperty float nz\nproperty float rh\nend_header\n";

/// Writes `n` particles on a unit sphere (normal = position, thickness 200..800 nm).
fn write_ply(path: &Path, n: usize, ascii: bool) {
    let format = if ascii {
        "ascii"
    } else {
        "binary_little_endian"
    };
    let mut out = format!("ply\nformat {format} 1.0\nelement vertex {n}\n{HEADER}").into_bytes();
    for i in 0..n {
        let t = i as f32 / n as f32;
        let (phi, z) = (t * 2.4e4, 2.0 * t - 1.0);
        let r = (1.0 - z * z).sqrt();
        let p = [r * phi.cos(), r * phi.sin(), z];
        let rec = [p[0], p[1], p[2], p[0], p[1], p[2], 200.0 + 600.0 * t];
        if ascii {
            let s: Vec<String> = rec.iter().map(|v| v.to_string()).collect();
            writeln!(out, "{}", s.join(" ")).unwrap();
        } else {
            rec.iter().for_each(|v| out.extend(v.to_le_bytes()));
        }
    }
    std::fs::write(path, out).unwrap();
}

fn file(name: &str, n: usize, ascii: bool) -> (PathBuf, u64) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("io_bench");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    write_ply(&p, n, ascii);
    let len = std::fs::metadata(&p).unwrap().len();
    (p, len)
}

fn ply_read(c: &mut Criterion) {
    let opts = ReadOptions::default();
    let (big, big_len) = file("1m_le.ply", 1_000_000, false);
    assert_eq!(read_cloud(&big, &opts).unwrap().len(), 1_000_000);
    let mut g = c.benchmark_group("ply_1M_binary_le_28B_per_particle");
    g.throughput(Throughput::Bytes(big_len)).sample_size(20);
    g.bench_function("std_fs_read", |b| {
        b.iter(|| black_box(std::fs::read(&big).unwrap()))
    });
    g.bench_function("read_cloud", |b| {
        b.iter(|| black_box(read_cloud(&big, &opts).unwrap()))
    });
    g.finish();

    let (small, small_len) = file("100k_le.ply", 100_000, false);
    let (text, text_len) = file("100k_ascii.ply", 100_000, true);
    assert_eq!(read_cloud(&text, &opts).unwrap().len(), 100_000);
    let mut g = c.benchmark_group("ply_100k_reference");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(text_len));
    g.bench_function("read_cloud_ascii", |b| {
        b.iter(|| black_box(read_cloud(&text, &opts).unwrap()))
    });
    g.throughput(Throughput::Bytes(small_len));
    g.bench_function("ply_rs_bw_binary_le", |b| {
        let parser = ply_rs_bw::parser::Parser::<ply_rs_bw::ply::DefaultElement>::new();
        b.iter(|| {
            let mut f = std::fs::File::open(&small).unwrap();
            black_box(parser.read_ply(&mut f).unwrap())
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = ply_read
}
criterion_main!(benches);
