//! CSV / XYZ text reader: separators, header forms, attribute mapping and malformed files.

mod io_support;

use std::path::Path;

use filmsplat::io::{CloudFormat, ReadOptions, detect_format, read_cloud};
use glam::Vec3;
use io_support::{read, tmp, write};

#[test]
fn separators_and_headers() {
    let d = tmp("csv_ok");
    let files = [
        (
            "a.csv",
            "x,y,z,nx,ny,nz,rh,density\n0,0,0,0,0,1,100,1000\n1,0,0,0,1,0,200,1001\r\n",
        ),
        (
            "b.tsv",
            "x\ty\tz\tnx\tny\tnz\trh\tdensity\n0\t0\t0\t0\t0\t1\t100\t1000\n\n1\t0\t0\t0\t1\t0\t200\t1001",
        ),
        (
            "c.xyz",
            "# x y z nx ny nz rh density\n# comment\n0 0 0  0 0 1 100 1000\n  1 0 0 0 1 0 200 1001\n",
        ),
        (
            "d.txt",
            "\"X\", \"Y\", \"Z\", \"nx\",\"ny\",\"nz\", \"rh\", \"density\"\n0, 0, 0, 0, 0, 1, 1e2, 1000\n1, 0, 0, 0, 1, 0, 2e2, 1001\n",
        ),
    ];
    for (name, text) in files {
        let p = write(&d, name, text.as_bytes());
        assert_eq!(detect_format(&p).unwrap(), CloudFormat::Csv);
        let c = read(&p);
        assert_eq!(c.positions, [Vec3::ZERO, Vec3::X], "{name}");
        assert_eq!(c.normals.as_deref().unwrap(), [Vec3::Z, Vec3::Y], "{name}");
        assert_eq!(c.thickness_nm.as_deref().unwrap(), [100.0, 200.0], "{name}");
        assert_eq!(c.extra("density").unwrap(), [1000.0, 1001.0], "{name}");
        assert_eq!(c.extra.len(), 1, "{name}");
    }
}

#[test]
fn headerless_xyz_and_options() {
    let d = tmp("csv_noheader");
    let c = read(&write(&d, "p.xyz", b"1 2 3 0.5\n4 5 6 0.25\n"));
    assert_eq!(
        c.positions,
        [Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0)]
    );
    assert_eq!(c.extra("c3").unwrap(), [0.5, 0.25]);
    let p = write(&d, "q.csv", b"z,y,x,t_um\n3,2,1,0.5\n");
    let o = ReadOptions {
        thickness_attr: Some("t_um".into()),
        ..ReadOptions::with_thickness_scale(1e3)
    };
    let c = read_cloud(&p, &o).unwrap();
    assert_eq!(
        c.positions,
        [Vec3::new(1.0, 2.0, 3.0)],
        "columns in any order"
    );
    assert_eq!(c.thickness_nm.as_deref().unwrap(), [500.0]);
    let c = read(&write(&d, "r.csv", b"x,y,z\n"));
    assert!(c.is_empty());
}

fn err(p: &Path) -> String {
    let e = read_cloud(p, &ReadOptions::default())
        .expect_err("must fail")
        .to_string();
    let name = p.file_name().unwrap().to_string_lossy();
    assert!(
        e.contains(&*name) && !e.contains('\n') && e.contains("CSV"),
        "{e}"
    );
    e
}

#[test]
fn malformed_files() {
    let d = tmp("csv_bad");
    let cases: &[(&[u8], &str)] = &[
        (b"", "empty file"),
        (b"\n \n", "empty file"),
        (b"a,b,c\n1,2,3\n", "no 'x' column"),
        (b"x,y,z,x\n1,2,3,4\n", "'x' twice"),
        (b"x,y,z,\n1,2,3,4\n", "no name"),
        (b"x,y,z\n1,2,3\n4,5\n", "line 3: expected 3 fields, found 2"),
        (
            b"x,y,z\n1,2,3\n4,5,6,7\n",
            "line 3: expected 3 fields, found 4",
        ),
        (
            b"x y z\n1 2 3\n4 five 6\n",
            "line 3, column 'y': expected a number, found 'five'",
        ),
        (b"x,y,z\n1,,3\n", "column 'y'"),
        (b"1 2\n", "at least 3 columns"),
        (b"x,y,z\n1,2,\xff\n", "line 2: not UTF-8"),
        (b"x,y,z,nx,ny\n1,2,3,4,5\n", "incomplete normal"),
    ];
    for (i, (bytes, want)) in cases.iter().enumerate() {
        let e = err(&write(&d, &format!("bad{i}.csv"), bytes));
        assert!(e.contains(want), "case {i}: {e}");
    }
}

#[test]
fn every_truncation_is_an_error_or_a_prefix() {
    let d = tmp("csv_trunc");
    let full = b"x,y,z,rh\n0.5,1.5,2.5,100\n3.5,4.5,5.5,200\n";
    for len in 0..full.len() {
        match read_cloud(&write(&d, "t.csv", &full[..len]), &ReadOptions::default()) {
            Err(e) => assert!(e.to_string().contains("t.csv"), "{len}: {e}"),
            // A cut inside a number leaves a shorter number: still a valid record.
            Ok(c) => assert!(c.len() <= 2, "{len}"),
        }
    }
}
