//! Data flows one way: each stage imports only the stages below it (see the table in
//! src/lib.rs). This test reads the sources and fails on an import that breaks the order.

use std::collections::BTreeSet;
use std::path::Path;

mod source_support;
use source_support::rust_files;

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
            for (i, line) in text.lines().enumerate() {
                if line.trim_start().starts_with("//") {
                    continue; // doc links may name any module
                }
                let mut rest = line;
                while let Some(pos) = rest.find("crate::") {
                    rest = &rest[pos + 7..];
                    let used: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    if all.contains(used.as_str()) && used != *module {
                        assert!(
                            allowed.contains(&used.as_str()),
                            "{}:{}: `{module}` imports `{used}`, which is not below it",
                            f.display(),
                            i + 1
                        );
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(
        checked > 10,
        "the scan found too few imports to be meaningful ({checked})"
    );
}
