//! The bgeo reader's bounded inflation on arbitrary deflate streams: the input is a raw deflate
//! stream, wrapped here in a gzip header and trailer, so the fuzzer explores what inflates (a
//! header, points, a bomb's padding) rather than gzip framing. Never a panic, and never more
//! inflated than the header's counts need (checked by the reader; a cloud it returns holds at
//! most what the header declares).
#![no_main]

use filmsplat::io::{CloudFormat, ReadOptions, read_bytes};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|deflate: &[u8]| {
    let mut gz = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 0xff];
    gz.extend_from_slice(deflate);
    gz.extend_from_slice(&[0; 8]); // CRC and size: wrong, so only a prefix can ever be read
    if let Ok(cloud) = read_bytes(CloudFormat::Bgeo, &gz, Path::new("fuzz.bgeo.gz"), &ReadOptions::default()).map(|(c, _)| c) {
        // 16 bytes a point at least: the inflated points cannot exceed the deflate ratio.
        assert!(cloud.positions.len() as u64 <= (gz.len() as u64 * 1100 + 1024) / 16);
    }
});
