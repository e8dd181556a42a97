//! The scene-file parser on arbitrary text: an error or a description, never a panic; a parsed
//! description's memory estimate (sample scenes only: no file access) must not panic either.
#![no_main]

use filmsplat::pipeline::memory::estimate_scene;
use filmsplat::scene::SceneDesc;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(desc) = SceneDesc::from_toml(text, "fuzz.toml")
        && desc.input.cloud.is_none()
    {
        let _ = estimate_scene(&desc, Path::new("."), true);
    }
});
