//! One `*_bin` file of a thin-film SPH frame folder on arbitrary bytes: an error or
//! (components, values) consistent with the size, never a panic.
#![no_main]

use filmsplat::io::frame_folder::read_bin_bytes;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok((k, values)) = read_bin_bytes(data, Path::new("fuzz_bin")) {
        assert!(k == 1 || k == 3);
        assert_eq!(values.len() % k, 0);
        assert_eq!(4 + 8 * values.len(), data.len());
    }
});
