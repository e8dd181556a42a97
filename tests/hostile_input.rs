//! Hostile input, round two (issue 17), one test per class: allocations sized by a header,
//! decompression and indirection bombs, inputs that are not files, quadratic work on
//! valid-looking data, values never validated, litter. Every hostile file is generated here,
//! small; peak behaviour is asserted through the refusal messages and the work reported, never
//! through timing. Also issue 16's pipes and globs (`-o -`, input `-`, `'frames/*.ply'`).

mod cli_support;
use cli_support::{filmsplat, tmp};

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use filmsplat::io::{ReadOptions, read_cloud};

/// Runs the binary with `env` set and `stdin` fed; returns (code, stdout bytes, stderr).
fn run(args: &[&str], env: &[(&str, &str)], stdin: Option<&[u8]>) -> (i32, Vec<u8>, String) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_filmsplat"));
    c.args(args)
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (k, v) in env {
        c.env(k, v);
    }
    let mut child = c.spawn().unwrap();
    if let Some(b) = stdin {
        let mut w = child.stdin.take().unwrap();
        let b = b.to_vec();
        // The child may refuse before reading everything: a broken pipe is fine.
        std::thread::spawn(move || {
            let _ = w.write_all(&b);
        });
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        out.stdout,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A binary little-endian PLY of positions.
fn ply(points: &[[f32; 3]]) -> Vec<u8> {
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nend_header\n",
        points.len()
    )
    .into_bytes();
    for p in points {
        for v in p {
            b.extend(v.to_le_bytes());
        }
    }
    b
}

/// `n` points on a unit sphere (Fibonacci).
fn sphere(n: usize) -> Vec<[f32; 3]> {
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).sqrt();
            let t = i as f32 * 2.399_963;
            [r * t.cos(), r * t.sin(), z]
        })
        .collect()
}

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let p = tmp(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn gz(b: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(b).unwrap();
    e.finish().unwrap()
}

// ---- 1. Allocations sized by a header -------------------------------------------------------

/// A real 8x8 EXR render with its data and display windows patched to 100000x100000.
fn huge_exr(name: &str) -> PathBuf {
    let small = tmp(&format!("{name}.small.exr"));
    let cloud = write(&format!("{name}.ply"), &ply(&sphere(500)));
    let (code, _, err) = filmsplat(&["render", s(&cloud), "-o", s(&small), "--size", "8x8", "-q"]);
    assert_eq!(code, 0, "{err}");
    let mut b = std::fs::read(&small).unwrap();
    for attr in [&b"dataWindow\0box2i\0"[..], b"displayWindow\0box2i\0"] {
        let at = b.windows(attr.len()).position(|w| w == attr).unwrap() + attr.len() + 4;
        for (k, v) in [0i32, 0, 99_999, 99_999].iter().enumerate() {
            b[at + 4 * k..at + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
        }
    }
    write(&format!("{name}.exr"), &b)
}

#[test]
fn exr_headers_claiming_huge_images_are_refused_before_decoding() {
    let map = huge_exr("huge_env");
    let cloud = write("huge_env_cloud.ply", &ply(&sphere(500)));
    let out = tmp("huge_env.png");
    let (code, _, err) = filmsplat(&[
        "render",
        s(&cloud),
        "--env",
        s(&map),
        "-o",
        s(&out),
        "--size",
        "64x48",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("huge_env.exr") && err.contains("100000x100000") && !err.contains("panick"),
        "{err}"
    );
    assert!(!out.exists());
    // A stability frame: the same check, the same message.
    let dir = tmp("huge_frames");
    std::fs::create_dir_all(&dir).unwrap();
    for f in 0..2 {
        std::fs::copy(&map, dir.join(format!("{f}.exr"))).unwrap();
    }
    let pattern = format!("{}/{{}}.exr", dir.display());
    let (code, _, err) = filmsplat(&["stability", &pattern, "--frames", "0..2"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("0.exr") && err.contains("100000x100000"),
        "{err}"
    );
}

#[test]
fn render_sizes_beyond_the_memory_allowance_are_refused_before_loading() {
    let cloud = write("allowance.ply", &ply(&sphere(500)));
    let out = tmp("allowance.png");
    let limit = [("FILMSPLAT_MEMORY_LIMIT", "64M")];
    // 4096x4096 needs ~1.2 GiB of image buffers; 64x48 a few hundred KiB.
    let args = |size| ["render", s(&cloud), "-o", s(&out), "--size", size, "-q"].map(String::from);
    let a = args("4096x4096");
    let (code, _, err) = run(
        &a.iter().map(String::as_str).collect::<Vec<_>>(),
        &limit,
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("4096x4096 render needs") && err.contains("available"),
        "{err}"
    );
    assert!(!out.exists());
    let a = args("64x48");
    let (code, _, err) = run(
        &a.iter().map(String::as_str).collect::<Vec<_>>(),
        &limit,
        None,
    );
    assert_eq!(code, 0, "{err}");
    // A generated sample's particle count, the same way.
    let sample = tmp("allowance_sample.ply");
    let (code, _, err) = run(
        &[
            "sample",
            "bubble",
            "--particles",
            "10000000",
            "-o",
            s(&sample),
        ],
        &limit,
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--particles = 10000000 needs"), "{err}");
    assert!(!sample.exists());
    // The CLI's own bound on sizes, at the flag.
    let a = args("40000x10");
    let (code, _, err) = run(&a.iter().map(String::as_str).collect::<Vec<_>>(), &[], None);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--size"), "{err}");
}

// ---- 2. Decompression and indirection bombs -------------------------------------------------

/// A classic BGEO V5 with P only: `declared` points in the header, `points` written, then
/// `padding` zero bytes (what a bomb inflates to).
fn bgeo(declared: i32, points: &[[f32; 3]], padding: usize) -> Vec<u8> {
    let mut b = b"BgeoV".to_vec();
    for v in [5, declared, 0, 0, 0, 0, 0, 0, 0] {
        b.extend(v.to_be_bytes());
    }
    for p in points {
        for x in [p[0], p[1], p[2], 1.0] {
            b.extend(x.to_be_bytes());
        }
    }
    b.resize(b.len() + padding, 0);
    b
}

#[test]
fn gzip_bgeo_is_inflated_only_as_far_as_its_header_needs() {
    let pts = sphere(10);
    // 10 points, then 256 MiB of zeros: ~250 KB compressed. Reading it must not inflate the
    // padding (the reader's own unit test checks the inflated length); the points come out.
    let bomb = write("bomb.bgeo.gz", &gz(&bgeo(10, &pts, 256 << 20)));
    assert!(std::fs::metadata(&bomb).unwrap().len() < 2 << 20);
    let cloud = read_cloud(&bomb, &ReadOptions::default()).unwrap();
    assert_eq!(cloud.positions.len(), 10);
    assert!((cloud.positions[3].x - pts[3][0]).abs() < 1e-6);
    // Under a 64 MiB allowance the whole padding could not even be held: still fine.
    let out = tmp("bomb.png");
    let (code, _, err) = run(
        &["render", s(&bomb), "-o", s(&out), "--size", "64x48", "-q"],
        &[("FILMSPLAT_MEMORY_LIMIT", "64M")],
        None,
    );
    assert_eq!(code, 0, "{err}");
    // A header declaring more points than the compressed bytes could hold is refused at once.
    let liar = write("liar.bgeo.gz", &gz(&bgeo(i32::MAX, &pts, 1 << 20)));
    let e = read_cloud(&liar, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("liar.bgeo.gz") && e.contains("compressed bytes can inflate to"),
        "{e}"
    );
}

/// A VTU with `pieces` Pieces of 3 points each whose Points all point at appended offset 0.
fn vtu_pieces(pieces: usize) -> Vec<u8> {
    let mut x = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt32\">\n<UnstructuredGrid>\n",
    );
    for _ in 0..pieces {
        x.push_str(
            "<Piece NumberOfPoints=\"3\" NumberOfCells=\"0\"><Points><DataArray \
             type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\
             </Points></Piece>\n",
        );
    }
    x.push_str("</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_");
    let mut b = x.into_bytes();
    b.extend(36u32.to_le_bytes());
    for v in 0..9 {
        b.extend((v as f32).to_le_bytes());
    }
    b.extend(b"\n</AppendedData>\n</VTKFile>\n");
    b
}

#[test]
fn vtu_pieces_sharing_one_appended_block_are_refused_before_decoding() {
    let one = write("one_piece.vtu", &vtu_pieces(1));
    assert_eq!(
        read_cloud(&one, &ReadOptions::default())
            .unwrap()
            .positions
            .len(),
        3
    );
    let many = write("many_pieces.vtu", &vtu_pieces(1000));
    let e = read_cloud(&many, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("many_pieces.vtu") && e.contains("both point at appended offset 0"),
        "{e}"
    );
}

#[test]
fn vtu_zlib_blocks_inflate_only_to_their_declared_size() {
    // One block declared as 36 bytes (3 points), holding 16 MiB of zeros compressed.
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
    z.write_all(&vec![0u8; 16 << 20]).unwrap();
    let block = z.finish().unwrap();
    let mut b = b"<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
        byte_order=\"LittleEndian\" header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\">\n\
        <UnstructuredGrid><Piece NumberOfPoints=\"3\" NumberOfCells=\"0\"><Points><DataArray \
        type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/></Points>\
        </Piece></UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_"
        .to_vec();
    for v in [1u32, 36, 36, block.len() as u32] {
        b.extend(v.to_le_bytes());
    }
    b.extend(&block);
    b.extend(b"\n</AppendedData>\n</VTKFile>\n");
    let p = write("zlib_bomb.vtu", &b);
    let e = read_cloud(&p, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("zlib_bomb.vtu") && e.contains("36 of 36 bytes"),
        "{e}"
    );
}

// ---- 3. Files that are not files ------------------------------------------------------------

#[test]
fn devices_are_refused_and_pipes_are_read_once_with_a_bound() {
    let ply_bytes = ply(&sphere(800));
    let out = tmp("pipe.png");
    // A symlink to /dev/zero.
    let link = tmp("zero.ply");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let (code, _, err) = filmsplat(&["render", s(&link), "-o", s(&out), "--size", "64x48"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("zero.ply") && err.contains("character device"),
        "{err}"
    );
    // A scene file that is /dev/zero.
    let scene = tmp("zero.toml");
    let _ = std::fs::remove_file(&scene);
    std::os::unix::fs::symlink("/dev/zero", &scene).unwrap();
    let (code, _, err) = filmsplat(&["render", s(&scene), "-o", s(&out)]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("zero.toml") && err.contains("character device"),
        "{err}"
    );
    // A named pipe without a writer: refused after the (shortened) wait, not a hang.
    let fifo = tmp("lonely.fifo");
    let _ = std::fs::remove_file(&fifo);
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let (code, _, err) = run(
        &["render", s(&fifo), "-o", s(&out), "--size", "64x48"],
        &[("FILMSPLAT_PIPE_WAIT", "0.2")],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("lonely.fifo") && err.contains("no writer"),
        "{err}"
    );
    // A named pipe with a writer (what `<(cat f.ply)` is): the format is told from the bytes
    // read, once.
    let fed = tmp("fed.fifo");
    let _ = std::fs::remove_file(&fed);
    assert!(Command::new("mkfifo").arg(&fed).status().unwrap().success());
    let (f2, b2) = (fed.clone(), ply_bytes.clone());
    let writer = std::thread::spawn(move || {
        let mut w = std::fs::OpenOptions::new().write(true).open(&f2).unwrap();
        w.write_all(&b2).unwrap();
    });
    let (code, _, err) = filmsplat(&["render", s(&fed), "-o", s(&out), "--size", "64x48", "-q"]);
    writer.join().unwrap();
    assert_eq!(code, 0, "{err}");
    assert!(out.exists());
    // Standard input of the wrong content is refused from its first bytes, not read to the end.
    let zeros = vec![0u8; 8 << 20];
    let (code, _, err) = run(&["render", "-", "-o", s(&out)], &[], Some(&zeros));
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("first bytes"), "{err}");
    // A stream larger than the bound is refused (the bound is half the allowance: 512 KiB).
    let big = ply(&sphere(60_000));
    let (code, _, err) = run(
        &["render", "-", "-o", s(&out), "--size", "8x8"],
        &[("FILMSPLAT_MEMORY_LIMIT", "1M")],
        Some(&big),
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("more than 512.0 KiB"), "{err}");
}

// ---- 4. Quadratic work on valid-looking data ------------------------------------------------

#[test]
fn knn_with_many_coincident_points_matches_brute_force() {
    use filmsplat::pointcloud::knn::KnnTable;
    use glam::Vec3;
    let mut p: Vec<Vec3> = sphere(700).into_iter().map(Vec3::from).collect();
    p.extend(std::iter::repeat_n(Vec3::new(0.1, 0.2, 0.3), 900));
    p.extend(std::iter::repeat_n(Vec3::new(-0.0, 1.0, 0.0), 40));
    p.push(Vec3::new(0.0, 1.0, 0.0));
    p.extend(sphere(300).into_iter().map(|q| Vec3::from(q) * 0.5));
    let k = 8;
    let t = KnnTable::build(&p, k);
    for i in (0..p.len()).step_by(7) {
        let mut d: Vec<f32> = (0..p.len())
            .filter(|&j| j != i)
            .map(|j| p[i].distance(p[j]))
            .collect();
        d.sort_by(f32::total_cmp);
        let row: Vec<(u32, f32)> = t.row(i).collect();
        assert_eq!(row.len(), k, "row {i}");
        for (m, (j, dist)) in row.iter().enumerate() {
            assert_ne!(*j as usize, i);
            assert!((dist - p[i].distance(p[*j as usize])).abs() < 1e-6);
            assert!(
                (dist - d[m]).abs() < 1e-5,
                "row {i} slot {m}: {dist} vs {}",
                d[m]
            );
        }
        let mut ids: Vec<u32> = row.iter().map(|r| r.0).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), k, "row {i} repeats a neighbour");
    }
}

#[test]
fn sixty_thousand_particles_at_one_position_are_drawn_once() {
    let mut pts = vec![[0.5f32, 0.5, 0.5]; 60_000];
    pts.extend(sphere(1000));
    let p = write("coincident.ply", &ply(&pts));
    let out = tmp("coincident.png");
    let (code, data, stdout) = filmsplat(&["render", s(&p), "-o", s(&out), "--size", "64x48"]);
    assert_eq!(code, 0, "{stdout}");
    assert!(data.is_empty(), "messages go to stderr: {data}");
    assert!(
        stdout.contains("59999 particles at the same position as an earlier one"),
        "{stdout}"
    );
    assert!(stdout.contains("1001 particles"), "{stdout}");
}

#[test]
fn legacy_vtk_line_numbers_stay_right_over_many_keyword_lines() {
    // 40 000 one-value arrays (80 000 keyword lines), then a bad keyword on the last line: its
    // number must be right (counted once, in order; counting from the start for every line was
    // quadratic).
    let mut t = String::from(
        "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float\n0 0 0\n\
         POINT_DATA 1\n",
    );
    let arrays = 40_000;
    for i in 0..arrays {
        t.push_str(&format!("SCALARS a{i} float 1\nLOOKUP_TABLE default\n1\n"));
    }
    t.push_str("BOGUS 1\n");
    let lines = 7 + 3 * arrays + 1;
    let p = write("many_keywords.vtk", t.as_bytes());
    let e = read_cloud(&p, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("line {lines}:")) && e.contains("BOGUS"),
        "{e}"
    );
}

// ---- 5. Values never validated --------------------------------------------------------------

#[test]
fn every_numeric_flag_refuses_non_finite_and_out_of_range_values() {
    use clap::CommandFactory;
    use std::ffi::OsStr;
    let root = filmsplat::cli::Cli::command();
    // Integer flags that take any value of their type (frame numbers are names, not counts;
    // a frame list is bounded in length by its own parser; a memory limit may be any size).
    let any_value = ["seed", "frames", "frame", "max_memory"];
    let (mut floats, mut ints) = (0, 0);
    for sub in root.get_subcommands() {
        for arg in sub.get_arguments() {
            if !arg.get_action().takes_values() {
                continue;
            }
            let Some(long) = arg.get_long() else {
                continue; // positionals are paths and names
            };
            // The flag alone in a command of its own: its value parser decides.
            let alone = clap::Command::new("t").arg(arg.clone().required(false));
            let ok = |v: &str| {
                alone
                    .clone()
                    .try_get_matches_from([
                        OsStr::new("t"),
                        OsStr::new(&format!("--{long}")),
                        OsStr::new(v),
                    ])
                    .is_ok()
            };
            let name = format!("{} --{}", sub.get_name(), arg.get_id());
            if ok("abc") || !ok("1") {
                continue; // not a plain number
            }
            if ok("0.5") {
                floats += 1;
                for bad in ["nan", "inf", "-inf", "NaN", "1e309", "-1e309"] {
                    assert!(!ok(bad), "{name} accepts {bad}");
                }
                // Every float flag is f32 but these (f64 all the way down).
                let f64_flags = [
                    "film --thickness",
                    "film --angle",
                    "film --ior",
                    "film --wavelengths",
                    "sample --sparse",
                ];
                if !f64_flags.contains(&name.as_str()) {
                    assert!(
                        !ok("1e39") && !ok("-1e39"),
                        "{name} accepts 1e39 (infinite as f32)"
                    );
                }
            } else {
                ints += 1;
                if !any_value.contains(&arg.get_id().as_str()) {
                    assert!(!ok("9000000000000000000"), "{name} accepts 9e18");
                }
            }
        }
    }
    assert!(
        floats >= 25 && ints >= 8,
        "{floats} float and {ints} integer flags"
    );
    // End to end: the flag is named, nothing is written.
    let out = tmp("nan_exposure.png");
    let cloud = write("nan_exposure.ply", &ply(&sphere(300)));
    let (code, _, err) = filmsplat(&["render", s(&cloud), "-o", s(&out), "--exposure", "nan"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--exposure"), "{err}");
    assert!(!out.exists());
}

/// A scene setting every float key the scene format has (one value per line).
const FULL_SCENE: &str = "[input]
sample = \"bubble\"
particles = 300
time = 0.5
sparse = 0.9
[film]
ior = 1.33
thickness_scale = 1.0
default_thickness_nm = 500.0
radius_scale = 1.0
[camera]
position = [0.0, 0.5, 4.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
aperture = 0.0
focus_distance = 4.0
[environment]
rotation = 10.0
intensity = 1.0
[render]
min_weight = 0.001
roulette = 0.0
[output]
exposure = 0.0
white_balance = 6504.0
gains = [1.0, 1.0, 1.0]
contrast = 1.0
saturation = 1.0
[[light]]
shape = \"sphere\"
position = [0.0, 3.0, 0.0]
radius = 0.5
luminance = 100.0
temperature = 5000.0
[[prop]]
shape = \"sphere\"
position = [0.0, -2.0, 0.0]
radius = 0.5
roughness = 0.3
colour = [0.5, 0.5, 0.5]
";

#[test]
fn every_scene_float_refuses_non_finite_values_naming_file_line_and_key() {
    let out = tmp("scene_sweep.png");
    let ok = write("scene_ok.toml", FULL_SCENE.as_bytes());
    let (code, _, err) = filmsplat(&["render", s(&ok), "-o", s(&out), "--size", "32x24", "-q"]);
    assert_eq!(code, 0, "{err}");
    let mut swept = 0;
    for (i, line) in FULL_SCENE.lines().enumerate() {
        let Some((key, value)) = line.split_once(" = ") else {
            continue;
        };
        if !value.contains('.') {
            continue; // not a float
        }
        for bad in ["nan", "inf", "-inf", "1e39"] {
            let v = if let Some(rest) = value.strip_prefix('[') {
                // The first element of the array.
                format!("[{bad},{}", rest.split_once(',').unwrap().1)
            } else {
                bad.to_string()
            };
            let mut text: Vec<String> = FULL_SCENE.lines().map(String::from).collect();
            text[i] = format!("{key} = {v}");
            let p = write("scene_bad.toml", text.join("\n").as_bytes());
            let (code, _, err) = filmsplat(&["render", s(&p), "-o", s(&out), "-q"]);
            assert_eq!(code, 2, "{key} = {v}: {err}");
            assert!(
                err.contains("scene_bad.toml")
                    && err.contains(&format!("line {}:", i + 1))
                    && err.contains(key),
                "{key} = {v}: {err}"
            );
        }
        swept += 1;
    }
    assert!(swept >= 25, "{swept}");
}

#[test]
fn bad_scene_values_found_later_still_name_the_file_and_line() {
    let out = tmp("scene_late.png");
    // (replace, by, key named, the line named starts with).
    for (from, to, key, at) in [
        (
            "particles = 300",
            "particles = 9000000000000000000",
            "input.particles",
            "particles",
        ),
        ("fov = 40.0", "fov = 400.0", "camera.fov", "fov"),
        (
            "min_weight = 0.001",
            "min_weight = -1.0",
            "render.min_weight",
            "min_weight",
        ),
        // A light's errors name its block by the line of its `shape`.
        (
            "radius = 0.5\nluminance",
            "radius = 0.0\nluminance",
            "radius",
            "shape = \"sphere\"\nposition = [0.0, 3.0",
        ),
    ] {
        let text = FULL_SCENE.replacen(from, to, 1);
        let line = text[..text.find(at).unwrap()].matches('\n').count() + 1;
        let p = write("scene_late.toml", text.as_bytes());
        let (code, _, err) = filmsplat(&["render", s(&p), "-o", s(&out), "-q"]);
        assert_eq!(code, 2, "{to}: {err}");
        assert!(
            err.contains("scene_late.toml")
                && err.contains(&format!("line {line}"))
                && err.contains(key),
            "{to}: {err}"
        );
    }
}

#[test]
fn far_coordinates_are_refused_naming_the_file_and_the_coordinates() {
    let mut pts = sphere(200);
    pts[7] = [1e30, 0.0, 0.0];
    let p = write("far.ply", &ply(&pts));
    let out = tmp("far.png");
    let (code, _, err) = filmsplat(&["render", s(&p), "-o", s(&out), "--size", "64x48"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("far.ply") && err.contains("1e30") && err.contains("index 7"),
        "{err}"
    );
    assert!(!err.contains("focus_distance"), "{err}");
    // --repair drops it and renders the rest.
    let (code, data, err) = filmsplat(&[
        "render",
        s(&p),
        "-o",
        s(&out),
        "--size",
        "64x48",
        "--repair",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(data.is_empty() && err.contains("dropped 1"), "{err}");
}

// ---- 6. Litter ------------------------------------------------------------------------------

#[test]
fn a_plain_render_removes_temporaries_of_dead_processes() {
    let dir = tmp("litter");
    std::fs::create_dir_all(&dir).unwrap();
    let target = dir.join("frame.png");
    // PID 4194304 exceeds Linux's pid_max: that process is not running.
    let stale = dir.join(".frame.png.tmp-4194304-0");
    std::fs::write(&stale, b"half a png").unwrap();
    let cloud = write("litter.ply", &ply(&sphere(300)));
    let (code, _, err) = filmsplat(&[
        "render",
        s(&cloud),
        "-o",
        s(&target),
        "--size",
        "32x24",
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(target.exists() && !stale.exists());
}

// ---- Issue 16 item 5: pipes and globs -------------------------------------------------------

#[test]
fn stdin_in_and_png_on_stdout() {
    let bytes = ply(&sphere(800));
    let (code, png, err) = run(
        &["render", "-", "-o", "-", "--size", "64x48"],
        &[],
        Some(&bytes),
    );
    assert_eq!(code, 0, "{err}");
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "stdout is not a PNG");
    let p = write("stdout.png", &png);
    let img = filmsplat::image::read_png(&p).unwrap();
    assert_eq!((img.width, img.height), (64, 48));
    assert!(
        err.contains("800 particles") && err.contains("wrote standard output"),
        "{err}"
    );
    // Failing renders write nothing to stdout.
    let (code, png, _) = run(
        &["render", "-", "-o", "-", "--size", "64x48"],
        &[],
        Some(b"ply\nbad"),
    );
    assert_eq!(code, 2);
    assert!(png.is_empty());
}

#[test]
fn a_quoted_glob_renders_every_match_in_order_with_stem_outputs() {
    let dir = tmp("glob_frames");
    let outdir = tmp("glob_out");
    let _ = std::fs::remove_dir_all(&outdir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::create_dir_all(&outdir).unwrap();
    for (name, n) in [("b_02.ply", 300), ("b_01.ply", 400), ("b_10.ply", 500)] {
        std::fs::write(dir.join(name), ply(&sphere(n))).unwrap();
    }
    std::fs::write(dir.join("notes.txt"), "not a frame").unwrap();
    let pattern = format!("{}/b_*.ply", dir.display());
    let out = format!("{}/{{stem}}.png", outdir.display());
    let (code, data, stdout) = filmsplat(&["render", &pattern, "-o", &out, "--size", "32x24"]);
    assert_eq!(code, 0, "{stdout}");
    assert!(data.is_empty(), "messages go to stderr: {data}");
    let order: Vec<usize> = ["b_01.ply (1/3)", "b_02.ply (2/3)", "b_10.ply (3/3)"]
        .iter()
        .map(|m| stdout.find(m).unwrap_or_else(|| panic!("{m}: {stdout}")))
        .collect();
    assert!(order.windows(2).all(|w| w[0] < w[1]), "{stdout}");
    for stem in ["b_01", "b_02", "b_10"] {
        assert!(outdir.join(format!("{stem}.png")).exists(), "{stem}");
    }
    assert!(stdout.contains("400 particles") && stdout.contains("500 particles"));
    // Several matches into one output name, and no match at all, are refused.
    let (code, _, err) = filmsplat(&[
        "render",
        &pattern,
        "-o",
        &format!("{}/one.png", outdir.display()),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("{stem}"), "{err}");
    let none = format!("{}/zz_*.ply", dir.display());
    let (code, _, err) = filmsplat(&["render", &none, "-o", &out]);
    assert_eq!(code, 2);
    assert!(err.contains("no file matches"), "{err}");
}
