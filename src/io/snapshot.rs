//! Snapshot folders of the thin-film SPH code: `<output>/snapshot/<frame>/`, written every
//! `snapshot_stride` frames by `Points::Save_Snapshot` (src/reservoir/Particles.cpp): one file
//! `NAME.bin` per particle attribute of `SPHBubbleParticles` / `GeometryParticles`, each
//! through `BinaryDataIO::Write_Array` ([`super::sim_arrays`], element layout), and the same
//! for the droplets (3D fluid particles) in `3d/`.
//!
//! | file | per particle | meaning (writer's comment) | read as |
//! |---|---|---|---|
//! | `x.bin` | 3 f64 | position, m | positions |
//! | `e.bin` | 9 f64, 3×3 column-major | local frame; column 2 is the normal | normals (column 2) |
//! | `rh.bin` | f64 | film thickness for rendering, m | thickness |
//! | `h.bin` | f64 | height of the film cylinder, m | extra |
//! | `v.bin`, `f.bin`, `sn.bin` | 3 f64 | velocity m/s, force, surface normal | extras `v_x ..` |
//! | `g.bin` | 4 f64 (2×2) | metric tensor | extras `g_0 .. g_3` |
//! | `dh.bin` | 2 f64 | tangential gradient of H | extras `dh_0 dh_1` |
//! | `b.bin`, `idx.bin`, `phase.bin` | i32 | boundary flag, index, phase | extras |
//! | `m`, `vol`, `sa`, `kh`, `rh_v`, `vrt`, `div`, `p`, `p0`, `p1`, `p2`, `pb`, `gamma`, `conc` | f64 | mass kg, volume m³, area m², Laplacian of H, d(rh)/dt, vorticity, divergence, pressures, surface tension, surfactant concentration | extras |
//!
//! The type of each file is decided by its size per particle (4: i32; 8, 16, 24, 32, 72:
//! 1, 2, 3, 4, 9 f64); every count must equal `x.bin`'s. `e`, `rh`, `h`, `m`, `sa` and `vol`
//! stored as int32 are refused (naming the file), and so are droplet masses (`3d/m.bin`) that
//! are not finite and positive: a droplet's radius is the sphere of its mass over
//! ρ = 1000 kg/m³, decided with [`crate::pointcloud::droplet_size`] by [`crate::pipeline`].

use std::path::Path;

use glam::Vec3;

use super::columns::{Aliases, Columns};
use super::frame_folder::NO_ROLES;
use super::sim_arrays::{SimArray, decode_elements};
use super::{CloudPart, PartKind, RADIUS_ALIASES, ReadOptions, format_error, read_file};
use crate::error::{Error, Result};
use crate::pointcloud::PointCloud;

/// Name used in error messages.
const FORMAT: &str = "snapshot folder";

/// Snapshot aliases: thickness `rh` (then `h`) in metres, normals from the frame `e`.
const ALIASES: Aliases = Aliases {
    thickness: &["rh", "h"],
    normal: &["e_normal"],
    radius: RADIUS_ALIASES,
    default_scale_to_nm: 1e9,
};

/// True if `dir` is a snapshot folder (it holds `x.bin`).
pub(crate) fn is_snapshot_folder(dir: &Path) -> bool {
    dir.join("x.bin").is_file()
}

/// Reads a snapshot folder's film and, if `3d/` holds any, its droplets.
///
/// # Errors
/// [`Error::Io`] if a file cannot be read; [`Error::Format`] naming the file if `x.bin` is
/// missing or not 3 f64 a particle, a file's size fits no layout, or counts disagree.
pub fn read_parts(dir: &Path, opts: &ReadOptions) -> Result<Vec<CloudPart>> {
    opts.check()?;
    let (film, stored) = read_set(dir, opts, &ALIASES)?;
    let mut parts = vec![CloudPart::film(
        format!("{} (film)", dir.display()),
        film,
        stored,
    )];
    let d3 = dir.join("3d");
    if d3.join("x.bin").is_file() {
        let (cloud, stored) = read_set(&d3, &ReadOptions::default(), &NO_ROLES)?;
        if !cloud.is_empty() {
            check_masses(&d3.join("m.bin"), &cloud)?;
            parts.push(CloudPart {
                label: format!("{} (droplets)", d3.join("x.bin").display()),
                kind: PartKind::Droplets,
                cloud,
                stored,
                notes: Vec::new(),
            });
        }
    }
    super::placeholder::drop_placeholder_film(&mut parts);
    Ok(parts)
}

/// Refuses droplet masses (`m.bin`, kg) that are not finite and positive: a droplet's size is
/// the sphere of its mass over water's density.
fn check_masses(path: &Path, cloud: &PointCloud) -> Result<()> {
    let Some(m) = cloud.extra("m") else {
        return Ok(());
    };
    let bad = m.iter().filter(|m| !(m.is_finite() && **m > 0.0)).count();
    match m.iter().position(|m| !(m.is_finite() && *m > 0.0)) {
        None => Ok(()),
        Some(i) => Err(format_error(
            path,
            FORMAT,
            format!(
                "{bad} of {} droplet masses are not finite and positive (first: droplet {i}, \
                 {:e} kg); a droplet is a sphere of its mass over 1000 kg/m³",
                m.len(),
                m[i]
            ),
        )),
    }
}

/// Attributes the writer stores as float64 (`Write_Array` of `real`): read as int32 (4 bytes
/// a particle) they would be counts, not lengths or masses.
const FLOAT64_ONLY: &[&str] = &["e", "rh", "h", "m", "sa", "vol"];

/// Reads one folder of `NAME.bin` attributes.
fn read_set(
    dir: &Path,
    opts: &ReadOptions,
    aliases: &Aliases,
) -> Result<(PointCloud, Vec<super::StoredAttribute>)> {
    let xp = dir.join("x.bin");
    let x = decode_elements(&read_file(&xp)?, None).map_err(|m| format_error(&xp, FORMAT, m))?;
    if x.len > 0 && x.components != 3 {
        return Err(format_error(
            &xp,
            FORMAT,
            format!(
                "{} values a particle; positions need 3 float64",
                x.components
            ),
        ));
    }
    let n = x.len;
    let mut cols = Columns {
        positions: (0..n).map(|i| vec3(&x, i, 0)).collect(),
        ..Columns::default()
    };
    cols.note_positions("x", "float64");
    let mut names: Vec<(String, std::path::PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if let Some(attr) = name.strip_suffix(".bin")
            && attr != "x"
            && !attr.is_empty()
            && entry.path().is_file()
        {
            names.push((attr.to_string(), entry.path()));
        }
    }
    names.sort();
    for (attr, p) in names {
        let a =
            decode_elements(&read_file(&p)?, Some(n)).map_err(|m| format_error(&p, FORMAT, m))?;
        if attr == "e" && a.components == 9 {
            // Eigen stores the 3×3 frame column-major: the normal (column 2) is values 6..9.
            let v = (0..n)
                .flat_map(|i| {
                    let c = vec3(&a, i, 6);
                    [c.x, c.y, c.z]
                })
                .collect();
            cols.push("e_normal", 3, "float64 3x3 (column 2)", v);
            continue;
        }
        if a.stored == "int32" && FLOAT64_ONLY.contains(&attr.as_str()) {
            return Err(format_error(
                &p,
                FORMAT,
                format!(
                    "stores 4 bytes a particle (int32), but the simulator writes '{attr}' as \
                     float64 (8 bytes a particle)"
                ),
            ));
        }
        let stored = if a.stored == "int32" {
            "int32"
        } else {
            "float64"
        };
        cols.push(
            &attr,
            a.components,
            stored,
            a.values.iter().map(|v| *v as f32).collect(),
        );
    }
    cols.into_cloud(opts, aliases)
        .map_err(|m| format_error(dir, FORMAT, m))
}

/// Components `c..c + 3` of element `i` as a vector.
fn vec3(a: &SimArray, i: usize, c: usize) -> Vec3 {
    Vec3::new(
        a.get(i, c) as f32,
        a.get(i, c + 1) as f32,
        a.get(i, c + 2) as f32,
    )
}
