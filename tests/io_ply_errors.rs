//! PLY reader on malformed input: every case is an `Err` naming the file, the format and the
//! problem (never a panic), including absurd header counts, truncations and corruptions.

mod io_support;

use std::path::Path;

use filmsplat::Error;
use filmsplat::io::{ReadOptions, read_cloud};
use io_support::{FORMATS, V, XYZ, ply, tmp, write, xyz_records};

/// Reads `bytes` as `name` and returns the error message, checking its form.
fn fail(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let p = write(dir, name, bytes);
    let e = read_cloud(&p, &ReadOptions::default()).expect_err(name);
    let m = e.to_string();
    assert!(m.contains(name), "message must name the file: {m}");
    assert!(!m.contains('\n'), "one line: {m}");
    assert!(matches!(e, Error::Format { format: "PLY", .. }), "{m}");
    assert!(m.contains("PLY"), "{m}");
    m
}

#[test]
fn malformed_files_give_clear_errors() {
    let dir = tmp("malformed");
    let le = "binary_little_endian";
    let full = ply(le, XYZ, &xyz_records(5));
    // Truncated in the middle of vertex 3 (each vertex is 12 bytes).
    let m = fail(&dir, "trunc.ply", &full[..full.len() - 12 - 6]);
    assert!(m.contains("vertex 3 of 5"), "{m}");
    let m = fail(&dir, "trunc_ascii.ply", &ply("ascii", XYZ, &xyz_records(4)));
    assert!(
        m.contains("line 13") && m.contains("vertex 4 of 5") && m.contains("ends"),
        "{m}"
    );
    let m = fail(
        &dir,
        "garbage.ply",
        format!(
            "ply\nformat ascii 1.0\n{XYZ}end_header\n\
        1 2 3\n\n4 5 6\n7 zz 9\n"
        )
        .as_bytes(),
    );
    assert!(
        m.contains("line 11") && m.contains("vertex 2 of 5") && m.contains("'zz'"),
        "{m}"
    );
    let one = XYZ.replace("vertex 5", "vertex 1");
    let m = fail(
        &dir,
        "few.ply",
        format!("ply\nformat ascii 1.0\n{one}end_header\n1 2\n").as_bytes(),
    );
    assert!(m.contains("line 8") && m.contains("too few values"), "{m}");
    let m = fail(
        &dir,
        "many.ply",
        format!("ply\nformat ascii 1.0\n{one}end_header\n1 2 3 4\n").as_bytes(),
    );
    assert!(m.contains("line 8") && m.contains("more values"), "{m}");
    let mut b = format!("ply\nformat ascii 1.0\n{one}end_header\n1 ").into_bytes();
    b.extend(b"\xff 3\n");
    let m = fail(&dir, "bin_in_ascii.ply", &b);
    assert!(m.contains("line 8") && m.contains("not text"), "{m}");
    let m = fail(
        &dir,
        "fmt.ply",
        format!("ply\nformat binary_middle_endian 1.0\n{XYZ}end_header\n").as_bytes(),
    );
    assert!(m.contains("line 2") && m.contains("unknown format"), "{m}");
    let m = fail(
        &dir,
        "noend.ply",
        format!("ply\nformat ascii 1.0\n{XYZ}").as_bytes(),
    );
    assert!(m.contains("no end_header"), "{m}");
    let renamed = String::from_utf8_lossy(&full).replace("end_header", "end_headr");
    let m = fail(&dir, "noend_bin.ply", renamed.as_bytes());
    assert!(m.contains("end_header"), "{m}");
    let m = fail(
        &dir,
        "noz.ply",
        &ply(
            le,
            "element vertex 1\nproperty float x\nproperty float y\n\
        property float w\n",
            &[vec![V::F32(0.0); 3]],
        ),
    );
    assert!(
        m.contains("no 'z' property") && m.contains("x, y, w"),
        "{m}"
    );
    let m = fail(
        &dir,
        "listx.ply",
        &ply(
            le,
            "element vertex 1\nproperty list uchar float x\n\
        property float y\nproperty float z\n",
            &[vec![V::U8(0), V::F32(0.0), V::F32(0.0)]],
        ),
    );
    assert!(m.contains("'x'") && m.contains("is a list"), "{m}");
    let m = fail(
        &dir,
        "listrh.ply",
        &ply(le, &format!("{XYZ}property list uchar float rh\n"), &[]),
    );
    assert!(m.contains("'rh'") && m.contains("is a list"), "{m}");
    let m = fail(
        &dir,
        "partial_n.ply",
        &ply(
            le,
            &format!("{XYZ}property float nx\nproperty float ny\n"),
            &[],
        ),
    );
    assert!(m.contains("incomplete normal"), "{m}");
    let m = fail(
        &dir,
        "novertex.ply",
        &ply(
            le,
            "element point 1\nproperty float x\n",
            &[vec![V::F32(0.0)]],
        ),
    );
    assert!(m.contains("no 'vertex' element"), "{m}");
    let m = fail(&dir, "empty.ply", b"");
    assert!(m.contains("empty file"), "{m}");
    let m = fail(&dir, "notply.ply", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR");
    assert!(m.contains("not a PLY file"), "{m}");
    let h = format!("element face 2\nproperty list char int v\n{XYZ}");
    let m = fail(
        &dir,
        "neglist.ply",
        &ply(
            le,
            &h,
            &[&[vec![V::I8(-1)], vec![V::I8(0)]][..], &xyz_records(5)].concat(),
        ),
    );
    assert!(
        m.contains("negative list length") && m.contains("face 0 of 2"),
        "{m}"
    );
    // The list count claims more items than the file holds.
    let mut b = ply(le, &h, &[vec![V::I8(0)], vec![V::I8(100), V::I32(1)]]);
    b.extend([0u8; 60]);
    let m = fail(&dir, "longlist.ply", &b);
    assert!(m.contains("face 1 of 2") && m.contains("truncated"), "{m}");
}

#[test]
fn absurd_counts_fail_before_allocating() {
    let dir = tmp("absurd");
    for f in FORMATS {
        let h =
            "element vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\n";
        let name = format!("absurd_{f}.ply");
        let m = fail(&dir, &name, &ply(f, h, &xyz_records(2)));
        assert!(
            m.contains("too short") && m.contains("1000000000000"),
            "{m}"
        );
        if f != "ascii" {
            assert!(m.contains("in vertex 2 of 1000000000000"), "{m}");
        }
    }
    // 2^64 - 1 vertices of 2^16 list items before them: the products must not overflow.
    let h = "element face 18446744073709551615\nproperty list uint double v\n\
        element vertex 18446744073709551615\nproperty double x\nproperty double y\nproperty double z\n";
    let m = fail(&dir, "overflow.ply", &ply("binary_big_endian", h, &[]));
    assert!(
        m.contains("too short") && m.contains("at or before face 0"),
        "{m}"
    );
}

#[test]
fn missing_files_and_directories() {
    let dir = tmp("paths");
    for (p, want) in [
        (dir.join("missing.ply"), "missing.ply"),
        (dir.clone(), "paths"),
    ] {
        let e = read_cloud(&p, &ReadOptions::default()).unwrap_err();
        // A directory that is no frame folder is a Format error.
        assert!(
            matches!(e, Error::Io { .. } | Error::Format { .. }),
            "{e:?}"
        );
        let m = e.to_string();
        assert!(m.contains(want) && !m.contains('\n'), "{m}");
        let e =
            filmsplat::io::read_as(filmsplat::io::CloudFormat::Ply, &p, &ReadOptions::default())
                .unwrap_err();
        assert!(e.to_string().contains(want), "{e}");
    }
}

/// Every prefix of a valid file is an error (not a panic) unless it holds all vertices; random
/// byte corruptions never panic.
#[test]
fn truncations_and_corruptions_never_panic() {
    let dir = tmp("fuzz");
    for f in FORMATS {
        let h = format!("element face 1\nproperty list uchar int v\n{XYZ}property float rh\n");
        let mut recs = vec![vec![V::U8(2), V::I32(1), V::I32(2)]];
        recs.extend(xyz_records(5).into_iter().map(|mut r| {
            r.push(V::F32(100.0));
            r
        }));
        let full = ply(f, &h, &recs);
        let name = format!("t_{f}.ply");
        let p = dir.join(&name);
        let opts = ReadOptions::default();
        for len in 0..full.len() {
            // ASCII: the last value "100.0\n" may lose up to 5 bytes and still be a number.
            let end_ok = f == "ascii" && len >= full.len() - 5;
            write(&dir, &name, &full[..len]);
            let r = read_cloud(&p, &opts);
            assert_eq!(r.is_ok(), end_ok, "{f} len {len}: {:?}", r.err());
        }
        write(&dir, &name, &full);
        assert_eq!(read_cloud(&p, &opts).unwrap().len(), 5);
        let mut state = 0x2545f4914f6cdd1du64;
        for _ in 0..300 {
            let mut b = full.clone();
            for _ in 0..3 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let i = (state % b.len() as u64) as usize;
                b[i] = (state >> 32) as u8;
            }
            write(&dir, &name, &b);
            if let Err(e) = read_cloud(&p, &opts) {
                assert!(e.to_string().contains("t_"), "{e}");
            }
        }
    }
}
