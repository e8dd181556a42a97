//! Frame folders of the thin-film SPH code (wang-mengdi/sph-thin-film,
//! `sph_bubble/FluidSPHBubbleDriver.cpp`, `Write_Output_Files`): one directory per frame.
//!
//! What the writer puts there, and what filmsplat makes of it (layouts in
//! [`super::sim_arrays`]; all lengths in metres):
//!
//! | file | layout | meaning (writer's attribute) | read as |
//! |---|---|---|---|
//! | `x_bin` | u32 n, n×3 f64 | positions (`X`) | positions |
//! | `norm_bin` | u32 n, n×3 f64 | unit normals (`Normal(i)`, column 2 of the local frame) | normals |
//! | `rh_bin` | u32 n, n f64 | film thickness for rendering, m (`RH`) | thickness |
//! | `h_bin` | u32 n, n f64 | height of the particle's film cylinder, m (`H`) | extra (thickness if no `rh_bin`) |
//! | `kh_bin` | u32 n, n f64 | Laplacian of H (`KH`) | extra |
//! | `sa_bin` | u32 n, n f64 | surface area a particle, m² (`SA`) | extra (the droplets' volume `SA·H`; the splat radius comes from the spacing, since disks of the particles' own area, √(SA/π), do not overlap enough to blend) |
//! | `tracker_points` | i32 4n, 4n f32 | x as float32 for the viewer | skipped (positions if no `x_bin`) |
//! | `tracker_circles`, `point_velocity`, `point_height`, `point_gamma`, `point_force`, `point_sa`, `segment_mesh` | i32 8n, 8n f32 | viewer segments | skipped (`tracker_circles`: normals if no `norm_bin`) |
//! | `tracker_points_3d` | i32 4m, 4m f32 | droplet positions (3D fluid particles) | droplets part |
//! | `rh_bin_3d` | u32 m, m f64 | the film thickness a droplet came from, m | droplet extra `rh` |
//! | `norm_bin_3d` | u32 m, m×3 f64 | unnormalised surface normal of the fluid (`SN`) | droplet extra `sn` |
//! | `last_frame.txt` | text | the run's last frame | skipped |
//!
//! Other `NAME_bin` files become attributes `NAME` (vectors `NAME_x/_y/_z`), mapped by
//! [`FRAME_NORMAL_ALIASES`] (`norm_bin` first), [`FRAME_THICKNESS_ALIASES`] (`rh_bin`, then
//! `h_bin`) and [`crate::io::RADIUS_ALIASES`] unless named explicitly. Thickness is in metres
//! unless [`ReadOptions::thickness_unit_explicit`] says otherwise. All counts must agree. Other
//! files are listed as skipped; subdirectories are ignored.
//!
//! The droplets are read as stored (positions, `rh`, `sn`); the folder stores no droplet
//! mass, so their size comes from the run's film particles (`SA·H`: a film particle turns into
//! a droplet of the same mass), decided by [`crate::pipeline`] with
//! [`crate::pointcloud::droplet_size`].

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::columns::{Aliases, Columns};
use super::sim_arrays::{SCALAR_OR_VECTOR, decode_floats, decode_layout, float_count};
use super::{AttributeRole, CloudPart, PartKind, StoredAttribute};
use super::{FRAME_NORMAL_ALIASES, FRAME_THICKNESS_ALIASES, RADIUS_ALIASES, ReadOptions};
use super::{format_error, read_file};
use crate::error::{Error, Result};
use crate::pointcloud::PointCloud;

/// Name used in error messages.
const FORMAT: &str = "frame folder";

/// The folder's aliases: thickness in metres.
const ALIASES: Aliases = Aliases {
    thickness: FRAME_THICKNESS_ALIASES,
    normal: FRAME_NORMAL_ALIASES,
    radius: RADIUS_ALIASES,
    default_scale_to_nm: 1e9,
};

/// The writer's float32 visualisation files: (name, floats per element, what it holds).
const VIEWER_FILES: &[(&str, usize, &str)] = &[
    ("tracker_points", 4, "x as float32 for the viewer"),
    (
        "tracker_circles",
        8,
        "x and normal as float32 for the viewer",
    ),
    ("point_velocity", 8, "viewer segments x to x + v"),
    ("point_height", 8, "viewer segments of H along the normal"),
    ("point_gamma", 8, "viewer segments of KH along the normal"),
    ("point_force", 8, "viewer segments of the force"),
    ("point_sa", 8, "viewer segments of SA"),
    ("segment_mesh", 8, "viewer local frames"),
];

/// True if `dir` is a frame folder: it holds `x_bin` (or, without it, the viewer's
/// `tracker_points`).
pub(crate) fn is_frame_folder(dir: &Path) -> bool {
    dir.join("x_bin").is_file() || dir.join("tracker_points").is_file()
}

/// Reads the frame folder `dir`'s film into a [`PointCloud`] (see the module docs).
///
/// Cost: reads every `*_bin` file once; peak memory is the cloud plus the largest file.
///
/// # Errors
/// [`Error::Io`] if a file cannot be read; [`Error::Format`] naming the file if `dir` is not a
/// directory, `x_bin` is missing or not a vector file, a file's size fits neither layout
/// (truncated files report where the data runs out), counts disagree, or an attribute named
/// in `opts` is missing; [`Error::Invalid`] for a bad option.
pub fn read(dir: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    read_described(dir, opts).map(|(c, _)| c)
}

/// Like [`read`], and also returns what the folder stores ([`StoredAttribute`]s; the
/// viewer files and others it skips are listed with [`AttributeRole::Skipped`]).
pub fn read_described(
    dir: &Path,
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>)> {
    opts.check()?;
    read_checked(dir, opts)
}

/// [`read_described`] with `opts` already checked (by [`crate::io::read_cloud`]).
pub(crate) fn read_checked(
    dir: &Path,
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>)> {
    let meta = std::fs::metadata(dir).map_err(|e| Error::io(dir, e))?;
    if !meta.is_dir() {
        return Err(format_error(dir, FORMAT, "not a directory"));
    }
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    let mut skipped: Vec<StoredAttribute> = Vec::new();
    let mut entries: Vec<(String, PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        if !entry.path().is_file() {
            continue;
        }
        entries.push((
            entry.file_name().to_string_lossy().into_owned(),
            entry.path(),
        ));
    }
    entries.sort();
    for (name, path) in entries {
        match name.strip_suffix("_bin") {
            Some(attr) if !attr.is_empty() && attr != "x" => files.push((attr.to_string(), path)),
            Some(_) => {}
            None if name.ends_with("_3d") => {}
            None => {
                let what = VIEWER_FILES
                    .iter()
                    .find(|(n, ..)| *n == name)
                    .map_or("not a particle array", |(_, _, w)| *w);
                skipped.push(StoredAttribute::new(&name, what, 0, AttributeRole::Skipped));
            }
        }
    }

    let xp = dir.join("x_bin");
    let mut cols = if xp.is_file() {
        positions_from_x_bin(&xp)?
    } else {
        positions_from_viewer(dir)?
    };
    let n = cols.positions.len();
    for (attr, p) in files {
        let (k, v) = parse(&read_file(&p)?).map_err(|m| format_error(&p, FORMAT, m))?;
        if v.len() / k != n {
            return Err(format_error(
                &p,
                FORMAT,
                format!("count {} disagrees with x_bin's {n} particles", v.len() / k),
            ));
        }
        let normal_name = match &opts.normal_attr {
            Some(p) => *p == attr,
            None => FRAME_NORMAL_ALIASES.contains(&attr.as_str()),
        };
        if normal_name && k == 1 && n > 0 {
            return Err(format_error(
                &p,
                FORMAT,
                format!(
                    "holds {n} scalars, but '{attr}' names normals (3 values per particle); \
                     a vector file cut to 4 + 8n bytes looks like this"
                ),
            ));
        }
        cols.push(&attr, k, "float64", v);
    }
    let (cloud, mut stored) = cols
        .into_cloud(opts, &ALIASES)
        .map_err(|m| format_error(dir, FORMAT, m))?;
    stored.extend(skipped);
    Ok((cloud, stored))
}

/// The positions of `x_bin` (f64 vectors).
fn positions_from_x_bin(xp: &Path) -> Result<Columns> {
    let (k, x) = parse(&read_file(xp)?).map_err(|m| format_error(xp, FORMAT, m))?;
    if k == 1 && !x.is_empty() {
        return Err(format_error(
            xp,
            FORMAT,
            format!(
                "holds {} scalars; positions need 3 values per particle",
                x.len()
            ),
        ));
    }
    let mut cols = Columns {
        positions: x
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect(),
        ..Columns::default()
    };
    cols.note_positions("x", "float64");
    Ok(cols)
}

/// Without `x_bin`: the positions of the float32 `tracker_points`, and normals from
/// `tracker_circles` (x, 0, normal, 0) when it has as many elements.
fn positions_from_viewer(dir: &Path) -> Result<Columns> {
    let tp = dir.join("tracker_points");
    if !tp.is_file() {
        return Err(format_error(
            &dir.join("x_bin"),
            FORMAT,
            "missing: x_bin holds the positions",
        ));
    }
    let a = decode_floats(&read_file(&tp)?, 4).map_err(|m| format_error(&tp, FORMAT, m))?;
    let mut cols = Columns {
        positions: a.vec3s(0),
        ..Columns::default()
    };
    cols.note_positions("tracker_points", "float32");
    let tc = dir.join("tracker_circles");
    if !dir.join("norm_bin").is_file() && tc.is_file() {
        let c = decode_floats(&read_file(&tc)?, 8).map_err(|m| format_error(&tc, FORMAT, m))?;
        if c.len == a.len {
            let v = c.flat3(4);
            cols.push("norm", 3, "float32", v);
        }
    }
    Ok(cols)
}

/// Reads the frame folder's particle sets: the film, and (once the film has ruptured) the
/// droplets of `tracker_points_3d`. The droplets come as stored, without a radius: their size
/// is decided from the run's stored masses and volumes by [`crate::pipeline`].
///
/// # Errors
/// As [`read`]; for the droplet files, errors naming the file as well.
pub fn read_parts(dir: &Path, opts: &ReadOptions) -> Result<Vec<CloudPart>> {
    let (film, stored) = read_described(dir, opts)?;
    let mut parts = Vec::new();
    let droplets = read_droplets(dir)?;
    parts.push(CloudPart::film(
        format!("{} (film)", dir.display()),
        film,
        stored,
    ));
    parts.extend(droplets);
    super::placeholder::drop_placeholder_film(&mut parts);
    Ok(parts)
}

/// The droplets of `tracker_points_3d`, `rh_bin_3d` and `norm_bin_3d`, if any. Labelled by
/// their positions file, so every message about one droplet names it.
fn read_droplets(dir: &Path) -> Result<Option<CloudPart>> {
    let tp = dir.join("tracker_points_3d");
    if !tp.is_file() {
        return Ok(None);
    }
    let a = decode_floats(&read_file(&tp)?, 4).map_err(|m| format_error(&tp, FORMAT, m))?;
    if a.len == 0 {
        return Ok(None);
    }
    let mut cols = Columns {
        positions: a.vec3s(0),
        ..Columns::default()
    };
    cols.note_positions("tracker_points_3d", "float32");
    for (file, name) in [("rh_bin_3d", "rh"), ("norm_bin_3d", "sn")] {
        let p = dir.join(file);
        if !p.is_file() {
            continue;
        }
        let (k, v) = parse(&read_file(&p)?).map_err(|m| format_error(&p, FORMAT, m))?;
        if v.len() / k != a.len {
            return Err(format_error(
                &p,
                FORMAT,
                format!(
                    "count {} disagrees with tracker_points_3d's {} droplets",
                    v.len() / k,
                    a.len
                ),
            ));
        }
        cols.push(name, k, "float64", v);
    }
    let (cloud, stored) = cols
        .into_cloud(&ReadOptions::default(), &NO_ROLES)
        .map_err(|m| format_error(dir, FORMAT, m))?;
    Ok(Some(CloudPart {
        label: format!("{} (droplets)", tp.display()),
        kind: PartKind::Droplets,
        cloud,
        stored,
        notes: Vec::new(),
    }))
}

/// Aliases that map nothing: every attribute of a droplet set is an extra (its radius is
/// derived, not read).
pub(crate) const NO_ROLES: Aliases = Aliases {
    thickness: &[],
    normal: &[],
    radius: &[],
    default_scale_to_nm: 1e9,
};

/// How many 3D particles (droplets) the frame folder `dir`'s `tracker_points_3d` holds (0
/// without the file), from its 4-byte header and its size alone, with the checks of the full
/// read.
///
/// # Errors
/// [`Error::Io`] if the file cannot be opened or read; [`Error::Format`] naming it if the
/// header and size disagree (as the full read).
pub fn droplet_count(dir: &Path) -> Result<usize> {
    use std::io::Read;
    let tp = dir.join("tracker_points_3d");
    if !tp.is_file() {
        return Ok(0);
    }
    let mut f = std::fs::File::open(&tp).map_err(|e| Error::io(&tp, e))?;
    let size = f.metadata().map_err(|e| Error::io(&tp, e))?.len();
    let mut head = [0u8; 4];
    if size < 4 {
        let m = format!("{size} bytes: shorter than its 4-byte count");
        return Err(format_error(&tp, FORMAT, m));
    }
    f.read_exact(&mut head).map_err(|e| Error::io(&tp, e))?;
    float_count(head, size - 4, 4).map_err(|m| format_error(&tp, FORMAT, m))
}

/// Decodes one `*_bin` file's content already in memory: returns (components per particle,
/// 1 or 3; the values as f32). `path` only names the file in errors. Never panics.
///
/// # Errors
/// [`Error::Format`] naming `path` if the size fits neither layout.
pub fn read_bin_bytes(bytes: &[u8], path: &Path) -> Result<(usize, Vec<f32>)> {
    parse(bytes).map_err(|m| format_error(path, FORMAT, m))
}

/// Decodes one `*_bin` file ([`decode_layout`] of f64 scalars or 3-vectors): returns
/// (components, values as f32). An empty file body (count 0) reads as scalar.
fn parse(bytes: &[u8]) -> std::result::Result<(usize, Vec<f32>), String> {
    let e = decode_layout(bytes, None, SCALAR_OR_VECTOR)?;
    Ok((e.kind.components, e.values_f32()))
}

#[cfg(test)]
mod tests {
    use super::parse;

    fn file(n: u32, vals: &[f64]) -> Vec<u8> {
        let mut b = n.to_le_bytes().to_vec();
        vals.iter().for_each(|v| b.extend(v.to_le_bytes()));
        b
    }

    #[test]
    fn layouts() {
        assert_eq!(parse(&file(2, &[1.0, 2.0])).unwrap(), (1, vec![1.0, 2.0]));
        let (k, v) = parse(&file(1, &[1.0, 2.0, 3.0])).unwrap();
        assert_eq!((k, v.len()), (3, 3));
        assert_eq!(parse(&file(0, &[])).unwrap(), (1, vec![]));
        let e = parse(&file(3, &[1.0, 2.0])).unwrap_err();
        assert!(e.contains("truncated") && e.contains("particle 2"), "{e}");
        let e = parse(&file(1, &[1.0, 2.0])).unwrap_err();
        assert!(e.contains("runs out at particle 0"), "{e}");
        let e = parse(&file(1, &[1.0, 2.0, 3.0, 4.0])).unwrap_err();
        assert!(e.contains("neither"), "{e}");
        assert!(parse(&[1, 0]).unwrap_err().contains("4-byte count"));
        let e = parse(&file(u32::MAX, &[1.0])).unwrap_err();
        assert!(e.contains("truncated"), "{e}");
    }
}
