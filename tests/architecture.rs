//! Data flows one way: each stage imports only the stages below it (see the table in
//! src/lib.rs). This test reads the sources and fails on an import that breaks the order.

use std::collections::BTreeSet;
use std::path::Path;

mod source_support;
use source_support::rust_files;

mod import_scan;
use import_scan::crate_modules_used;

/// Module → the crate modules it may use (besides `error`).
const ALLOWED: &[(&str, &[&str])] = &[
    ("optics", &[]),
    ("image", &[]),
    ("scene", &[]),
    ("spectrum", &["optics"]),
    ("pointcloud", &[]),
    ("io", &["pointcloud"]),
    ("geometry", &[]),
    ("samples", &["pointcloud"]),
    ("figure", &["spectrum", "optics", "image"]),
    ("render", &["geometry", "spectrum", "optics", "image"]),
    (
        "pipeline",
        &[
            "scene",
            "io",
            "pointcloud",
            "samples",
            "geometry",
            "render",
            "figure",
            "spectrum",
            "optics",
            "image",
        ],
    ),
    (
        "view",
        &[
            "pipeline",
            "figure",
            "scene",
            "io",
            "pointcloud",
            "samples",
            "geometry",
            "render",
            "spectrum",
            "optics",
            "image",
        ],
    ),
    (
        "cli",
        &[
            "view",
            "pipeline",
            "figure",
            "scene",
            "io",
            "pointcloud",
            "samples",
            "geometry",
            "render",
            "spectrum",
            "optics",
            "image",
        ],
    ),
];

/// The module path below `src/` of a source file: `src/render/camera.rs` → `[render,
/// camera]`, `src/render/mod.rs` → `[render]`.
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

#[test]
fn stages_import_only_stages_below_them() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let all: BTreeSet<&str> = ALLOWED.iter().map(|(m, _)| *m).collect();
    let mut checked = 0;
    for (module, allowed) in ALLOWED {
        let dir = src.join(module);
        assert!(dir.is_dir(), "src/{module}/ should be a module folder");
        let mut files = Vec::new();
        rust_files(&dir, &mut files);
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            let path = module_path(&src, &f);
            let path: Vec<&str> = path.iter().map(String::as_str).collect();
            for (line, used) in crate_modules_used(&text, &path) {
                if all.contains(used.as_str()) && used != *module {
                    assert!(
                        allowed.contains(&used.as_str()),
                        "{}:{line}: `{module}` imports `{used}`, which is not below it",
                        f.display(),
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(
        checked > 10,
        "the scan found too few imports to be meaningful ({checked})"
    );
}

/// The names the scan finds in `src`, as a file `src/render/camera.rs` would hold it.
fn found(src: &str) -> Vec<String> {
    crate_modules_used(src, &["render", "camera"])
        .into_iter()
        .map(|(_, m)| m)
        .collect()
}

#[test]
fn scan_finds_grouped_nested_multiline_and_inline_paths() {
    assert_eq!(found("use crate::geometry::Ray;"), ["geometry"]);
    assert_eq!(
        found("use crate::{geometry::Ray, pipeline::{load, build}, Error};"),
        ["geometry", "pipeline", "Error"]
    );
    assert_eq!(
        found("pub use crate::{\n    image::Rgb,\n    view::{\n        a,\n        b,\n    },\n};"),
        ["image", "view"]
    );
    assert_eq!(found("let x = crate::cli::run(a);"), ["cli"]);
    assert_eq!(
        found("fn f() -> crate :: view :: App { todo!() }"),
        ["view"]
    );
    assert_eq!(
        found("macro_rules! m { () => { $crate::view::x() } }"),
        ["view"]
    );
    // super chains that climb to the crate root, also from inline modules
    assert_eq!(found("use super::super::view::App;"), ["view"]);
    assert_eq!(found("use super::super::{view, io::x};"), ["view", "io"]);
    assert_eq!(
        found("mod tests {\n use super::super::super::pipeline::X;\n use super::super::Y; }"),
        ["pipeline"]
    );
    assert_eq!(found("mod a { }\nuse super::super::view;"), ["view"]);
}

#[test]
fn scan_ignores_comments_strings_and_local_paths() {
    assert!(found("// use crate::view::App;").is_empty());
    assert!(found("/// see [`crate::view::App`]").is_empty());
    assert!(found("/* use crate::view::App; /* nested */ crate::cli */").is_empty());
    assert!(found("let s = \"crate::view::App\";").is_empty());
    assert!(found("let s = r#\"crate::view \" crate::cli\"#;").is_empty());
    assert!(found("let c = '\"'; let s = \"x\";").is_empty());
    assert!(found("pub(crate) fn f<'a>(x: &'a str) {}").is_empty());
    assert!(found("use super::lights::Light; use super::super::render::X;").len() == 1);
    // the line of each name is reported
    let lines: Vec<usize> = crate_modules_used("\n\nuse crate::{\n a,\n b };", &["x"])
        .into_iter()
        .map(|(l, _)| l)
        .collect();
    assert_eq!(lines, [4, 5]);
}
