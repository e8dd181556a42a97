//! What `filmsplat info` shows of a file: every attribute with its stored type, components and
//! role, the same for every format (the shared attribute-mapping rules).

use std::fs;
use std::path::{Path, PathBuf};

use filmsplat::io::{AttributeRole, ReadOptions, StoredAttribute, read_cloud_described};

mod cli_support;
use cli_support::{data, filmsplat};

fn tmp(test: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("io_described")
        .join(test);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn described(p: &Path, opts: &ReadOptions) -> Vec<(String, String, usize, AttributeRole)> {
    let (_, stored) = read_cloud_described(p, opts).unwrap_or_else(|e| panic!("{e}"));
    stored
        .into_iter()
        .map(
            |StoredAttribute {
                 name,
                 stored,
                 components,
                 role,
             }| (name, stored, components, role),
        )
        .collect()
}

fn row(
    name: &str,
    ty: &str,
    k: usize,
    role: AttributeRole,
) -> (String, String, usize, AttributeRole) {
    (name.into(), ty.into(), k, role)
}

use AttributeRole::*;

#[test]
fn ply_lists_every_property_with_its_type_and_role() {
    let d = tmp("ply");
    let p = d.join("a.ply");
    fs::write(
        &p,
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n\
         property double z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property uchar rh\nproperty list uchar int idx\nproperty ushort flag\nend_header\n\
         0 0 0 0 0 1 200 2 1 2 7\n1 1 1 0 1 0 100 0 9\n",
    )
    .unwrap();
    assert_eq!(
        described(&p, &ReadOptions::default()),
        [
            row("x", "float64", 1, Position),
            row("y", "float64", 1, Position),
            row("z", "float64", 1, Position),
            row("nx", "float32", 1, Normal),
            row("ny", "float32", 1, Normal),
            row("nz", "float32", 1, Normal),
            row("rh", "uint8", 1, Thickness),
            row("idx", "list uint8 int32", 1, Skipped),
            row("flag", "uint16", 1, Extra),
        ]
    );
    // Naming another attribute moves the role, by the same rules as every other format.
    let opts = ReadOptions {
        thickness_attr: Some("flag".into()),
        ..ReadOptions::default()
    };
    let got = described(&p, &opts);
    assert_eq!(got[6], row("rh", "uint8", 1, Extra));
    assert_eq!(got[8], row("flag", "uint16", 1, Thickness));
}

#[test]
fn columnar_formats_report_stored_types() {
    let vtu = described(
        Path::new(&data("fluid_encoded_250_particles.vtu")),
        &ReadOptions::default(),
    );
    assert_eq!(vtu[0], row("Points", "float64", 3, Position));
    assert!(vtu.contains(&row("index", "int64", 1, Extra)), "{vtu:?}");
    let bgeo = described(
        Path::new(&data("dam_break_frame_9_6859_particles.bgeo")),
        &ReadOptions::default(),
    );
    assert_eq!(bgeo[0], row("P", "float32", 3, Position));
    assert!(bgeo.contains(&row("id", "int32", 1, Extra)), "{bgeo:?}");
    let vtk = described(
        Path::new(&data("double_dam_break_frame_26_4732_particles.vtk")),
        &ReadOptions::default(),
    );
    assert_eq!(vtk[0], row("POINTS", "float32", 3, Position));
    assert!(
        vtk.contains(&row("velocity", "float32", 3, Extra)),
        "{vtk:?}"
    );

    let d = tmp("csv");
    let csv = d.join("a.csv");
    fs::write(
        &csv,
        "x,y,z,nx,ny,nz,thickness,w\n0,0,0,0,0,1,300,1\n1,0,0,0,0,1,310,2\n",
    )
    .unwrap();
    assert_eq!(
        described(&csv, &ReadOptions::default()),
        [
            row("x y z", "text", 3, Position),
            row("nx", "text", 1, Normal),
            row("ny", "text", 1, Normal),
            row("nz", "text", 1, Normal),
            row("thickness", "text", 1, Thickness),
            row("w", "text", 1, Extra),
        ]
    );

    let f = d.join("frame");
    fs::create_dir_all(&f).unwrap();
    let bin = |n: u32, v: &[f64]| {
        let mut b = n.to_le_bytes().to_vec();
        v.iter().for_each(|x| b.extend(x.to_le_bytes()));
        b
    };
    fs::write(f.join("x_bin"), bin(1, &[0.0, 0.0, 0.0])).unwrap();
    fs::write(f.join("norm_bin"), bin(1, &[0.0, 0.0, 1.0])).unwrap();
    fs::write(f.join("rh_bin"), bin(1, &[2e-7])).unwrap();
    fs::write(f.join("kh_bin"), bin(1, &[3.0])).unwrap();
    let mut got = described(&f, &ReadOptions::default());
    got[1..].sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(
        got,
        [
            row("x", "float64", 3, Position),
            row("kh", "float64", 1, Extra),
            row("norm", "float64", 3, Normal),
            row("rh", "float64", 1, Thickness),
        ]
    );
}

#[test]
fn info_prints_types_roles_and_ranges() {
    let (code, out, err) = filmsplat(&["info", &data("fluid_encoded_250_particles.vtu")]);
    assert_eq!(code, 0, "{err}");
    let stored = &out[out.find("stored attributes").expect("section")..];
    let line = stored
        .lines()
        .find(|l| l.trim_start().starts_with("density"))
        .unwrap_or_else(|| panic!("{out}"));
    assert!(line.contains("float64") && line.contains("extra"), "{line}");
    assert!(
        line.contains("520.78") && line.contains("1021.46"),
        "{line}"
    );
    let line = stored
        .lines()
        .find(|l| l.trim_start().starts_with("Points"))
        .unwrap();
    assert!(
        line.contains("float64 x3") && line.contains("position"),
        "{line}"
    );
}
