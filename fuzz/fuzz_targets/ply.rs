//! The ply reader on arbitrary bytes: an error or a cloud, never a panic; a cloud it returns
//! goes through validation and repair, which must not panic on whatever values it holds.
#![no_main]

use filmsplat::io::{CloudFormat, ReadOptions, read_bytes};
use filmsplat::pointcloud::{repair, validate};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mut cloud) = read_bytes(CloudFormat::Ply, data, Path::new("fuzz.ply"), &ReadOptions::default()).map(|(c, _)| c) {
        let _ = validate(&cloud);
        let _ = repair(&mut cloud);
    }
});
