//! VTK XML reader: every encoding (ascii, inline base64, appended raw/base64, zlib, UInt32 and
//! UInt64 headers, both byte orders), the real splashsurf files, and malformed files.

mod io_support;

use std::io::Write;
use std::path::Path;

use filmsplat::io::{CloudFormat, ReadOptions, detect_format, read_cloud};
use glam::Vec3;
use io_support::{read, tmp, write};

const P: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.5]];

fn b64(data: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let w = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for i in 0..4 {
            if i <= c.len() {
                s.push(A[(w >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

#[derive(Clone, Copy, Debug)]
struct Mode {
    /// "ascii", "binary" or "appended".
    format: &'static str,
    base64: bool,
    header64: bool,
    zlib: bool,
    big: bool,
}

fn word(x: u64, m: Mode) -> Vec<u8> {
    match (m.header64, m.big) {
        (true, false) => x.to_le_bytes().to_vec(),
        (true, true) => x.to_be_bytes().to_vec(),
        (false, false) => (x as u32).to_le_bytes().to_vec(),
        (false, true) => (x as u32).to_be_bytes().to_vec(),
    }
}

/// Header and body of one binary block (body compressed in 16-byte blocks if zlib).
fn block(data: &[u8], m: Mode) -> (Vec<u8>, Vec<u8>) {
    if !m.zlib {
        return (word(data.len() as u64, m), data.to_vec());
    }
    let bs = 16;
    let chunks: Vec<&[u8]> = data.chunks(bs).collect();
    let mut body = Vec::new();
    let mut sizes = Vec::new();
    for c in &chunks {
        let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(c).unwrap();
        let z = e.finish().unwrap();
        sizes.push(z.len() as u64);
        body.extend(z);
    }
    let last = data.len() % bs;
    let mut h = word(chunks.len() as u64, m);
    h.extend(word(bs as u64, m));
    h.extend(word(last as u64, m));
    sizes.iter().for_each(|&s| h.extend(word(s, m)));
    (h, body)
}

/// Writes a .vtu: points (Float64), then point data rh (Float32), id (Int32), v (Float64 ×3).
fn vtu(m: Mode) -> Vec<u8> {
    let n = P.len();
    let f64s = |v: &[f64]| -> Vec<u8> {
        v.iter()
            .flat_map(|x| {
                if m.big {
                    x.to_be_bytes()
                } else {
                    x.to_le_bytes()
                }
            })
            .collect()
    };
    let pts: Vec<f64> = P.iter().flatten().copied().collect();
    let arrays: Vec<(&str, &str, usize, Vec<u8>, String)> = vec![
        (
            "Points",
            "Float64",
            3,
            f64s(&pts),
            "0 0 0 1 0 0 0 2 0.5".into(),
        ),
        (
            "rh",
            "Float32",
            1,
            [100f32, 200.0, 300.0]
                .iter()
                .flat_map(|x| {
                    if m.big {
                        x.to_be_bytes()
                    } else {
                        x.to_le_bytes()
                    }
                })
                .collect(),
            "100 200 300".into(),
        ),
        (
            "id",
            "Int32",
            1,
            [7i32, 8, 9]
                .iter()
                .flat_map(|x| {
                    if m.big {
                        x.to_be_bytes()
                    } else {
                        x.to_le_bytes()
                    }
                })
                .collect(),
            "7\n8\n9".into(),
        ),
        (
            "v",
            "Float64",
            3,
            f64s(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]),
            "1 2 3 4 5 6 7 8 9".into(),
        ),
    ];
    let mut appended: Vec<u8> = Vec::new();
    let mut tags = Vec::new();
    for (name, ty, k, bytes, text) in &arrays {
        let head = format!("<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{k}\"");
        let tag = match m.format {
            "ascii" => format!("{head} format=\"ascii\">\n {text}\n</DataArray>"),
            "binary" => {
                let (h, body) = block(bytes, m);
                let enc = if m.zlib {
                    b64(&h) + &b64(&body)
                } else {
                    b64(&[h, body].concat())
                };
                format!("{head} format=\"binary\">\n{enc}\n</DataArray>")
            }
            _ => {
                let off = appended.len();
                let (h, body) = block(bytes, m);
                if m.base64 {
                    let enc = if m.zlib {
                        b64(&h) + &b64(&body)
                    } else {
                        b64(&[h, body].concat())
                    };
                    appended.extend(enc.bytes());
                } else {
                    appended.extend(h);
                    appended.extend(body);
                }
                format!("{head} format=\"appended\" offset=\"{off}\"/>")
            }
        };
        tags.push(tag);
    }
    let mut out = format!(
        "<?xml version=\"1.0\"?>\n<!-- test -->\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"{}\" header_type=\"{}\"{}>\n<UnstructuredGrid>\n\
         <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"0\">\n<Points>\n{}\n</Points>\n\
         <Cells><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\"></DataArray></Cells>\n\
         <PointData>\n{}\n{}\n{}\n</PointData>\n</Piece>\n</UnstructuredGrid>\n",
        if m.big { "BigEndian" } else { "LittleEndian" },
        if m.header64 { "UInt64" } else { "UInt32" },
        if m.zlib { " compressor=\"vtkZLibDataCompressor\"" } else { "" },
        tags[0],
        tags[1],
        tags[2],
        tags[3]
    )
    .into_bytes();
    if m.format == "appended" {
        out.extend(
            format!(
                "<AppendedData encoding=\"{}\">\n   _",
                if m.base64 { "base64" } else { "raw" }
            )
            .bytes(),
        );
        out.extend(&appended);
        out.extend(b"\n</AppendedData>\n");
    }
    out.extend(b"</VTKFile>\n");
    out
}

fn modes() -> Vec<Mode> {
    let mut v = vec![Mode {
        format: "ascii",
        base64: false,
        header64: false,
        zlib: false,
        big: false,
    }];
    for format in ["binary", "appended"] {
        for base64 in [false, true] {
            for header64 in [false, true] {
                for zlib in [false, true] {
                    for big in [false, true] {
                        if format == "binary" && !base64 {
                            continue;
                        }
                        v.push(Mode {
                            format,
                            base64,
                            header64,
                            zlib,
                            big,
                        });
                    }
                }
            }
        }
    }
    v
}

#[test]
fn every_encoding_reads_the_same_cloud() {
    let d = tmp("vtu_modes");
    for (i, m) in modes().into_iter().enumerate() {
        let p = write(&d, &format!("m{i}.vtu"), &vtu(m));
        assert_eq!(detect_format(&p).unwrap(), CloudFormat::VtkXml);
        let c = read_cloud(&p, &ReadOptions::default()).unwrap_or_else(|e| panic!("{m:?}: {e}"));
        assert_eq!(
            c.positions,
            [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.5)],
            "{m:?}"
        );
        assert_eq!(c.thickness_nm.as_deref().unwrap(), [100.0, 200.0, 300.0]);
        assert_eq!(c.extra("id").unwrap(), [7.0, 8.0, 9.0], "{m:?}");
        assert_eq!(c.extra("v_y").unwrap(), [2.0, 5.0, 8.0], "{m:?}");
        assert_eq!(c.extra.len(), 4, "{m:?}");
    }
}

#[test]
fn pieces_are_concatenated() {
    let d = tmp("vtu_pieces");
    let one = String::from_utf8(vtu(modes()[0])).unwrap();
    let (a, rest) = one.split_at(one.find("<Piece").unwrap());
    let end = rest.find("</Piece>").unwrap() + "</Piece>".len();
    let piece = &rest[..end];
    let two = format!(
        "{a}{piece}\n{}{}",
        piece.replace("100 200 300", "400 500 600"),
        &rest[end..]
    );
    let c = read(&write(&d, "two.vtu", two.as_bytes()));
    assert_eq!(c.len(), 6);
    assert_eq!(c.positions[3], Vec3::ZERO);
    assert_eq!(
        c.thickness_nm.as_deref().unwrap(),
        [100.0, 200.0, 300.0, 400.0, 500.0, 600.0]
    );
    let bad = format!(
        "{a}{piece}\n{}{}",
        piece.replace("Name=\"id\"", "Name=\"ident\""),
        &rest[end..]
    );
    let e = read_cloud(
        &write(&d, "bad.vtu", bad.as_bytes()),
        &ReadOptions::default(),
    );
    let e = e.unwrap_err().to_string();
    assert!(e.contains("Piece 1") && e.contains("'ident'"), "{e}");
}

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

#[test]
fn real_splashsurf_files() {
    let z = read(&data("fluid_250_particles.vtu")); // appended raw, zlib, UInt64
    let e = read(&data("fluid_encoded_250_particles.vtu")); // appended base64
    for c in [&z, &e] {
        assert_eq!(c.len(), 250);
        let mut names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
        names.sort_unstable();
        assert_eq!(
            names,
            [
                "density",
                "index",
                "pressure",
                "velocity_x",
                "velocity_y",
                "velocity_z"
            ]
        );
        let dens = c.extra("density").unwrap();
        assert!(dens.iter().all(|d| (500.0..1100.0).contains(d)), "{dens:?}");
        let mut idx: Vec<f32> = c.extra("index").unwrap().to_vec();
        idx.sort_by(f32::total_cmp);
        assert_eq!(idx, (1..=250).map(|i| i as f32).collect::<Vec<_>>());
    }
    // Both files hold the same particles.
    assert_eq!(z.positions, e.positions);
    assert_eq!(z.extra("density"), e.extra("density"));
    // The base64 file's recorded ranges hold: density 520.79..1021.46.
    let dens = e.extra("density").unwrap();
    let (lo, hi) = dens
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &d| (a.min(d), b.max(d)));
    assert!(
        (lo - 520.7889).abs() < 1e-2 && (hi - 1021.4626).abs() < 1e-2,
        "{lo} {hi}"
    );
    let pmax = e
        .extra("pressure")
        .unwrap()
        .iter()
        .fold(0f32, |a, &b| a.max(b));
    assert!((pmax - 89839.96).abs() < 0.1, "{pmax}");
}

fn err(p: &Path) -> String {
    let e = read_cloud(p, &ReadOptions::default())
        .expect_err("must fail")
        .to_string();
    let name = p.file_name().unwrap().to_string_lossy();
    assert!(e.contains(&*name) && !e.contains('\n'), "{e}");
    e
}

#[test]
fn malformed_files() {
    let d = tmp("vtu_bad");
    let ok = String::from_utf8(vtu(modes()[0])).unwrap();
    let cases: Vec<(String, &str)> = vec![
        (
            ok.replace("UnstructuredGrid\" version", "ImageData\" version"),
            "not supported",
        ),
        (
            ok.replace("NumberOfPoints=\"3\"", "NumberOfPoints=\"4\""),
            "12 values",
        ),
        (
            ok.replace("NumberOfPoints=\"3\"", "NumberOfPoints=\"99999999999\""),
            "cannot fit",
        ),
        (ok.replace("NumberOfPoints=\"3\"", ""), "NumberOfPoints"),
        (ok.replace("100 200 300", "100 2x0 300"), "'2x0'"),
        (ok.replace("100 200 300", "100 200 300 400"), "more than"),
        (ok.replace("Float32", "Float16"), "unsupported type"),
        (
            ok.replace("\"ascii\">\n 0 0 0", "\"zip\">\n 0 0 0"),
            "unknown format",
        ),
        (
            ok.replace("<Points>", "<Pointz>")
                .replace("</Points>", "</Pointz>"),
            "no Points",
        ),
        (
            ok.replace("NumberOfComponents=\"3\"", "NumberOfComponents=\"0\""),
            "NumberOfComponents",
        ),
        (ok.replace("<VTKFile", "<VTKFyle"), "no <VTKFile>"),
        (ok.replace("Name=\"rh\"", "Name=rh"), "malformed XML"),
        (
            ok.replace(
                "header_type=\"UInt32\"",
                "header_type=\"UInt32\" compressor=\"vtkLZ4DataCompressor\"",
            ),
            "compressor",
        ),
        (ok[..ok.len() / 2].to_string(), "ends inside"),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let p = write(&d, &format!("bad{i}.vtu"), text.as_bytes());
        let e = err(&p);
        assert!(e.contains(want) && e.contains("VTK XML"), "case {i}: {e}");
    }
    let p = write(&d, "empty.vtu", b"");
    assert!(err(&p).contains("empty"));
    // Appended data with a wrong header, a bad offset and corrupt zlib.
    let m = Mode {
        format: "appended",
        base64: false,
        header64: false,
        zlib: true,
        big: false,
    };
    let good = vtu(m);
    let at = good.windows(4).position(|w| w == b"   _").unwrap() + 4;
    let mut bad = good.clone();
    bad[at] = 9; // block count
    assert!(err(&write(&d, "hdr.vtu", &bad)).contains("array 'Points'"));
    let mut bad = good.clone();
    // Points: 72 bytes in 5 blocks of 16 → a header of 3 + 5 u32 words, then zlib streams.
    let body = at + 4 * (3 + 5);
    bad[body + 3] ^= 0xff;
    let e = err(&write(&d, "z.vtu", &bad));
    assert!(e.contains("array 'Points'") && e.contains("corrupt"), "{e}");
    let t = String::from_utf8_lossy(&good).replace("offset=\"0\"", "offset=\"999999\"");
    assert!(err(&write(&d, "off.vtu", t.as_bytes())).contains("beyond"));
}

#[test]
fn every_truncation_and_byte_flip_is_handled() {
    let d = tmp("vtu_trunc");
    for (mi, m) in modes().into_iter().enumerate().step_by(3) {
        let full = vtu(m);
        for len in 0..full.len() {
            let p = write(&d, "t.vtu", &full[..len]);
            if let Err(e) = read_cloud(&p, &ReadOptions::default()) {
                let s = e.to_string();
                assert!(s.contains("t.vtu") && !s.contains('\n'), "{mi} {len}: {s}");
            }
        }
        for i in (0..full.len()).step_by(3) {
            let mut b = full.clone();
            b[i] ^= 0x5a;
            let _ = read_cloud(&write(&d, "f.vtu", &b), &ReadOptions::default());
        }
    }
}

/// Regression (found by the malformed corpus): a file cut before `</VTKFile>` used to read as
/// complete when the arrays were whole, and raw appended data could run into the closing tags.
#[test]
fn every_truncation_is_an_error() {
    for m in modes() {
        let full = vtu(m);
        let close = full
            .windows(b"</VTKFile>".len())
            .rposition(|w| w == b"</VTKFile>")
            .unwrap();
        for cut in (0..close).step_by(5) {
            let r = filmsplat::io::read_bytes(
                CloudFormat::VtkXml,
                &full[..cut],
                Path::new("cut.vtu"),
                &ReadOptions::default(),
            );
            assert!(r.is_err(), "{m:?}: cut at {cut} of {} read", full.len());
        }
    }
}
