//! Mesh readers: PLY with faces (ASCII, binary LE/BE) and OBJ, and their one-line errors.

use std::path::{Path, PathBuf};

use filmsplat::io::{ReadOptions, read_cloud, read_mesh};

fn tmp(test: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("io_mesh")
        .join(test);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// A unit square (two vertices carrying thickness and normals) plus a quad face and a triangle,
/// with a `material` element between vertex and face and a scalar before the index list.
fn square_ply(encoding: &str) -> Vec<u8> {
    let header = format!(
        "ply\nformat {encoding} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property double z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float thickness\nelement material 1\nproperty uchar id\n\
         element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n\
         property list uchar float uv\nend_header\n"
    );
    let verts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let mut b = header.into_bytes();
    let be = encoding == "binary_big_endian";
    let f32b =
        |x: f32, b: &mut Vec<u8>| b.extend(if be { x.to_be_bytes() } else { x.to_le_bytes() });
    let i32b =
        |x: i32, b: &mut Vec<u8>| b.extend(if be { x.to_be_bytes() } else { x.to_le_bytes() });
    if encoding == "ascii" {
        for (i, v) in verts.iter().enumerate() {
            b.extend(format!("{} {} 0.5 0 0 1 {}\n", v[0], v[1], 100 * (i + 1)).bytes());
        }
        b.extend(b"7\n3 4 0 1 2 3 2 0.5 0.5\n0 3 1 3 2 0\n");
    } else {
        for (i, v) in verts.iter().enumerate() {
            f32b(v[0], &mut b);
            f32b(v[1], &mut b);
            b.extend(if be {
                0.5f64.to_be_bytes()
            } else {
                0.5f64.to_le_bytes()
            });
            for x in [0.0, 0.0, 1.0, 100.0 * (i + 1) as f32] {
                f32b(x, &mut b);
            }
        }
        b.push(7);
        b.extend([3, 4]);
        for i in [0, 1, 2, 3] {
            i32b(i, &mut b);
        }
        b.push(2);
        f32b(0.5, &mut b);
        f32b(0.5, &mut b);
        b.extend([0, 3]);
        for i in [1, 3, 2] {
            i32b(i, &mut b);
        }
        b.push(0);
    }
    b
}

#[test]
fn ply_meshes_in_every_encoding() {
    let dir = tmp("encodings");
    for enc in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let p = write(&dir, &format!("{enc}.ply"), &square_ply(enc));
        let m = read_mesh(&p, &ReadOptions::default()).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [1, 3, 2]], "{enc}");
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.vertices.positions[2].to_array(), [1.0, 1.0, 0.5]);
        assert_eq!(
            m.vertices.thickness_nm.as_deref(),
            Some(&[100.0, 200.0, 300.0, 400.0][..])
        );
        assert_eq!(m.vertices.normals.as_ref().unwrap()[3].z, 1.0);
        // The same file still reads as a cloud of its vertices.
        assert_eq!(read_cloud(&p, &ReadOptions::default()).unwrap().len(), 4);
    }
}

#[test]
fn obj_meshes() {
    let dir = tmp("obj");
    let p = write(
        &dir,
        "quad.obj",
        b"# a quad\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n",
    );
    let m = read_mesh(&p, &ReadOptions::default()).unwrap();
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert!(m.vertices.thickness_nm.is_none());
    assert_eq!(m.vertices.normals.unwrap()[1].to_array(), [0.0, 0.0, 1.0]);
}

#[test]
fn malformed_meshes_give_one_line_errors() {
    let dir = tmp("errors");
    let good = String::from_utf8(square_ply("ascii")).unwrap();
    let le = square_ply("binary_little_endian");
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "cloud.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n".to_vec(),
            "no 'face' element",
        ),
        (
            "noindices.ply",
            good.replace("vertex_indices", "corners").into_bytes(),
            "no 'vertex_indices' list",
        ),
        (
            "floatindices.ply",
            good.replace("uchar int vertex_indices", "uchar float vertex_indices")
                .into_bytes(),
            "must be a list of integers",
        ),
        (
            "outofrange.ply",
            good.replace("0 3 1 3 2 0", "0 3 1 9 2 0").into_bytes(),
            "vertex index 9 is not one of the 4 vertices",
        ),
        (
            "shortlist.ply",
            good.replace("0 3 1 3 2 0", "0 3 1 3").into_bytes(),
            "too few values",
        ),
        (
            "truncated.ply",
            le[..le.len() - 6].to_vec(),
            "data ends inside face 1 of 2 (file truncated?)",
        ),
        ("bad.obj", b"v 0 0 0\nf 1 2 3\n".to_vec(), "line 2:"),
        ("mesh.stl", b"solid x\n".to_vec(), "unrecognised mesh format"),
    ];
    for (name, bytes, want) in cases {
        let p = write(&dir, name, &bytes);
        let e = read_mesh(&p, &ReadOptions::default())
            .expect_err(name)
            .to_string();
        assert!(e.contains(want), "{name}: got {e:?}, want {want:?}");
        assert!(e.contains(name), "{e}");
        assert!(!e.contains('\n'), "{e}");
    }
    // Every truncation of the binary file fails cleanly or reads fewer faces, never panics.
    for cut in (0..le.len()).step_by(7) {
        let p = write(&dir, "cut.ply", &le[..cut]);
        assert!(read_mesh(&p, &ReadOptions::default()).is_err(), "cut {cut}");
    }
    let missing = read_mesh(&dir.join("none.obj"), &ReadOptions::default()).unwrap_err();
    assert!(missing.to_string().contains("none.obj"));
}
