//! Reading speed of each binary particle format, in particles per second: the same 1M
//! particles (positions, normals, thickness) written here as a frame folder (f64), VTK legacy
//! binary (float), VTU appended raw (float, uncompressed and zlib) and BGEO V5 (plain and
//! gzip), each read by `read_cloud` from the page cache. Binary PLY is in `benches/io_ply.rs`.

use std::hint::black_box;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use filmsplat::io::{ReadOptions, read_cloud};

const N: usize = 1_000_000;

/// Particle i: a point on the unit sphere (normal = position) and thickness 200..800 nm.
fn particle(i: usize) -> ([f32; 3], f32) {
    let t = i as f32 / N as f32;
    let (phi, z) = (t * 2.4e4, 2.0 * t - 1.0);
    let r = (1.0 - z * z).sqrt();
    ([r * phi.cos(), r * phi.sin(), z], 200.0 + 600.0 * t)
}

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("io_formats_bench");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn frame_folder(d: &Path) -> PathBuf {
    let f = d.join("frame");
    std::fs::create_dir_all(&f).unwrap();
    let mut x = (N as u32).to_le_bytes().to_vec();
    let mut rh = x.clone();
    for i in 0..N {
        let (p, t) = particle(i);
        p.iter().for_each(|v| x.extend(f64::from(*v).to_le_bytes()));
        rh.extend((f64::from(t) * 1e-9).to_le_bytes());
    }
    std::fs::write(f.join("x_bin"), &x).unwrap();
    std::fs::write(f.join("norm_bin"), &x).unwrap();
    std::fs::write(f.join("rh_bin"), &rh).unwrap();
    f
}

fn vtk(d: &Path) -> PathBuf {
    let mut b = format!(
        "# vtk DataFile Version 4.1\nbench\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS {N} float\n"
    )
    .into_bytes();
    let cols: Vec<([f32; 3], f32)> = (0..N).map(particle).collect();
    cols.iter()
        .for_each(|(p, _)| p.iter().for_each(|v| b.extend(v.to_be_bytes())));
    b.extend(format!("\nPOINT_DATA {N}\nNORMALS normals float\n").bytes());
    cols.iter()
        .for_each(|(p, _)| p.iter().for_each(|v| b.extend(v.to_be_bytes())));
    b.extend(b"\nSCALARS rh float 1\nLOOKUP_TABLE default\n");
    cols.iter().for_each(|(_, t)| b.extend(t.to_be_bytes()));
    b.push(b'\n');
    let p = d.join("cloud.vtk");
    std::fs::write(&p, b).unwrap();
    p
}

/// Appended raw VTU, UInt64 headers; zlib in 32 KiB blocks if `zlib`.
fn vtu(d: &Path, zlib: bool) -> PathBuf {
    let mut pts = Vec::with_capacity(12 * N);
    let mut rh = Vec::with_capacity(4 * N);
    for i in 0..N {
        let (p, t) = particle(i);
        p.iter().for_each(|v| pts.extend(v.to_le_bytes()));
        rh.extend(t.to_le_bytes());
    }
    let block = |data: &[u8]| -> Vec<u8> {
        if !zlib {
            let mut out = (data.len() as u64).to_le_bytes().to_vec();
            out.extend(data);
            return out;
        }
        let bs = 1 << 15;
        let chunks: Vec<&[u8]> = data.chunks(bs).collect();
        let mut head = vec![chunks.len() as u64, bs as u64, (data.len() % bs) as u64];
        let mut body = Vec::new();
        for c in &chunks {
            let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
            e.write_all(c).unwrap();
            let z = e.finish().unwrap();
            head.push(z.len() as u64);
            body.extend(z);
        }
        let mut out: Vec<u8> = head.iter().flat_map(|w| w.to_le_bytes()).collect();
        out.extend(body);
        out
    };
    let (a, b, c) = (block(&pts), block(&pts), block(&rh));
    let (o1, o2) = (a.len(), a.len() + b.len());
    let comp = if zlib {
        " compressor=\"vtkZLibDataCompressor\""
    } else {
        ""
    };
    let mut out = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\"{comp}>\n<UnstructuredGrid>\n\
         <Piece NumberOfPoints=\"{N}\" NumberOfCells=\"0\">\n<Points>\n\
         <DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\n\
         </Points>\n<PointData>\n\
         <DataArray type=\"Float32\" Name=\"normals\" NumberOfComponents=\"3\" format=\"appended\" offset=\"{o1}\"/>\n\
         <DataArray type=\"Float32\" Name=\"rh\" format=\"appended\" offset=\"{o2}\"/>\n\
         </PointData>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_"
    )
    .into_bytes();
    out.extend(a);
    out.extend(b);
    out.extend(c);
    out.extend(b"\n</AppendedData>\n</VTKFile>\n");
    let p = d.join(if zlib { "zlib.vtu" } else { "raw.vtu" });
    std::fs::write(&p, out).unwrap();
    p
}

fn bgeo(d: &Path, gzip: bool) -> PathBuf {
    let mut b = b"BgeoV".to_vec();
    for v in [5, N as i32, 0, 0, 0, 2, 0, 0, 0] {
        b.extend(v.to_be_bytes());
    }
    for (name, size, ty) in [("N", 3u16, 5i32), ("rh", 1, 0)] {
        b.extend((name.len() as u16).to_be_bytes());
        b.extend(name.bytes());
        b.extend(size.to_be_bytes());
        b.extend(ty.to_be_bytes());
        b.extend(vec![0u8; 4 * size as usize]);
    }
    for i in 0..N {
        let (p, t) = particle(i);
        for v in [p[0], p[1], p[2], 1.0, p[0], p[1], p[2], t] {
            b.extend(v.to_be_bytes());
        }
    }
    if gzip {
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        e.write_all(&b).unwrap();
        b = e.finish().unwrap();
    }
    let p = d.join(if gzip { "cloud.bgeo.gz" } else { "cloud.bgeo" });
    std::fs::write(&p, b).unwrap();
    p
}

fn formats(c: &mut Criterion) {
    let d = dir();
    let opts = ReadOptions::default();
    let files = [
        ("frame_folder_f64", frame_folder(&d)),
        ("vtk_legacy_binary", vtk(&d)),
        ("vtu_appended_raw", vtu(&d, false)),
        ("vtu_appended_zlib", vtu(&d, true)),
        ("bgeo", bgeo(&d, false)),
        ("bgeo_gzip", bgeo(&d, true)),
    ];
    let mut g = c.benchmark_group("read_1M_particles_xyz_normal_thickness");
    g.throughput(Throughput::Elements(N as u64))
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for (name, p) in &files {
        let cloud = read_cloud(p, &opts).unwrap();
        assert_eq!(cloud.len(), N);
        assert!(
            cloud.normals.is_some() && cloud.thickness_nm.is_some(),
            "{name}"
        );
        g.bench_function(*name, |b| {
            b.iter(|| black_box(read_cloud(p, &opts).unwrap()))
        });
    }
    g.finish();
}

criterion_group!(benches, formats);
criterion_main!(benches);
