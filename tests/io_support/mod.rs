//! Shared helpers for the PLY reader tests: temp files and a tiny PLY writer.
#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};

use filmsplat::io::{ReadOptions, read_cloud};
use filmsplat::pointcloud::PointCloud;

/// A fresh directory for one test.
pub fn tmp(test: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("io_ply")
        .join(test);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

pub fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    // Unlink first: truncating an existing file makes ext4 flush it to disk (auto_da_alloc).
    let _ = fs::remove_file(&p);
    fs::write(&p, bytes).unwrap();
    p
}

/// One typed value, written in any encoding.
#[derive(Clone, Copy, Debug)]
pub enum V {
    I8(i8),
    U8(u8),
    I16(i16),
    U16(u16),
    I32(i32),
    U32(u32),
    F32(f32),
    F64(f64),
}

impl V {
    pub fn bytes(self, be: bool, out: &mut Vec<u8>) {
        macro_rules! b {
            ($x:expr) => {
                out.extend(if be {
                    $x.to_be_bytes()
                } else {
                    $x.to_le_bytes()
                })
            };
        }
        match self {
            V::I8(x) => b!(x),
            V::U8(x) => b!(x),
            V::I16(x) => b!(x),
            V::U16(x) => b!(x),
            V::I32(x) => b!(x),
            V::U32(x) => b!(x),
            V::F32(x) => b!(x),
            V::F64(x) => b!(x),
        }
    }

    pub fn text(self) -> String {
        match self {
            V::I8(x) => x.to_string(),
            V::U8(x) => x.to_string(),
            V::I16(x) => x.to_string(),
            V::U16(x) => x.to_string(),
            V::I32(x) => x.to_string(),
            V::U32(x) => x.to_string(),
            V::F32(x) => format!("{x:?}"),
            V::F64(x) => format!("{x:?}"),
        }
    }

    pub fn f32(self) -> f32 {
        match self {
            V::I8(x) => x as f32,
            V::U8(x) => x as f32,
            V::I16(x) => x as f32,
            V::U16(x) => x as f32,
            V::I32(x) => x as f32,
            V::U32(x) => x as f32,
            V::F32(x) => x,
            V::F64(x) => x as f32,
        }
    }
}

/// `records` in the given encoding after `header` (property lines etc., no format/end_header).
/// Each record is a list of values; in ASCII one line per record.
pub fn ply(format: &str, header: &str, records: &[Vec<V>]) -> Vec<u8> {
    let mut out =
        format!("ply\nformat {format} 1.0\ncomment test\n{header}end_header\n").into_bytes();
    for r in records {
        match format {
            "ascii" => {
                let line: Vec<String> = r.iter().map(|v| v.text()).collect();
                out.extend(line.join(" ").bytes());
                out.push(b'\n');
            }
            _ => r
                .iter()
                .for_each(|v| v.bytes(format == "binary_big_endian", &mut out)),
        }
    }
    out
}

pub const FORMATS: [&str; 3] = ["ascii", "binary_little_endian", "binary_big_endian"];

pub fn read(p: &Path) -> PointCloud {
    read_cloud(p, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

pub fn extra<'a>(c: &'a PointCloud, name: &str) -> &'a [f32] {
    &c.extra
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no {name}"))
        .1
}
pub const XYZ: &str = "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n";

pub fn xyz_records(n: usize) -> Vec<Vec<V>> {
    (0..n)
        .map(|i| vec![V::F32(i as f32), V::F32(0.5), V::F32(-1.0)])
        .collect()
}
