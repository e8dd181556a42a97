//! MELP's foam frame folders (wang-mengdi/melp-thin-film, `melp/ParticleALEFoamDriver.cpp`,
//! `Write_Output_Files` and `Write_Output_Files_Region`): one folder per frame, one set of
//! files per bubble (region) R = 0, 1, 2, ... Layouts in [`super::sim_arrays`]; lengths in
//! metres.
//!
//! | file | layout | meaning | read as |
//! |---|---|---|---|
//! | `l_tracker_points_R` | i32 4n, f32 x y z 0 | Lagrangian particles (they carry the film) | positions of film part R |
//! | `l_tracker_circles_R` | i32 8n, f32 x y z 0 nx ny nz 0 | position and unit normal | normals |
//! | `l_h_bin_R` | u32 n, n f64 | film thickness, m (`H`) | thickness |
//! | `l_origin_bin_R` | u32 n, n f64 | the particle's index `I` as a float | extra `origin` |
//! | `e_tracker_points_R`, `e_tracker_circles_R`, `e_h_bin_R`, `e_point_force_R` | as above | Eulerian particles: the same film resampled, and their forces | skipped (the Lagrangian set is the film) |
//! | `v_tracker_points` | i32 4m, f32 | 3D fluid particles (droplets) | droplets part |
//! | `boundary_points` | i32 4m, f32 | boundary particles | skipped |
//!
//! A frozen region writes empty files; it gives an empty part.

use std::path::Path;

use glam::Vec3;

use super::columns::{Aliases, Columns};
use super::sim_arrays::{decode_elements, decode_floats};
use super::{AttributeRole, CloudPart, PartKind, RADIUS_ALIASES, ReadOptions, StoredAttribute};
use super::{format_error, read_file};
use crate::error::{Error, Result};

/// Name used in error messages.
const FORMAT: &str = "MELP frame folder";

/// Thickness `h` in metres, normals `n`.
const ALIASES: Aliases = Aliases {
    thickness: &["h"],
    normal: &["n"],
    radius: RADIUS_ALIASES,
    default_scale_to_nm: 1e9,
};

/// True if `dir` holds MELP's per-region foam files.
pub fn is_melp_folder(dir: &Path) -> bool {
    dir.join("l_tracker_points_0").is_file() || dir.join("e_tracker_points_0").is_file()
}

/// Reads every region's Lagrangian film (one part each) and the droplets, if any.
///
/// # Errors
/// [`Error::Io`] if a file cannot be read; [`Error::Format`] naming the file if a layout or
/// count does not fit.
pub fn read_parts(dir: &Path, opts: &ReadOptions) -> Result<Vec<CloudPart>> {
    opts.check()?;
    let mut regions: Vec<usize> = Vec::new();
    let mut skipped: Vec<StoredAttribute> = Vec::new();
    let mut eulerian = 0usize;
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if let Some(r) = name
            .strip_prefix("l_tracker_points_")
            .and_then(|r| r.parse().ok())
        {
            regions.push(r);
        } else if name.starts_with("e_") {
            eulerian += 1;
        } else if name == "boundary_points" {
            skipped.push(StoredAttribute::new(
                &name,
                "boundary particles",
                0,
                AttributeRole::Skipped,
            ));
        }
    }
    if eulerian > 0 {
        // One row for all of them: they are one thing (the film resampled), not attributes.
        skipped.push(StoredAttribute::new(
            &format!("e_*_R ({eulerian} files)"),
            "Eulerian particles (the film resampled)",
            0,
            AttributeRole::Skipped,
        ));
    }
    regions.sort_unstable();
    skipped.sort_by(|a, b| a.name.cmp(&b.name));
    if regions.is_empty() {
        return Err(format_error(
            dir,
            FORMAT,
            "no l_tracker_points_R (only the Eulerian e_ files; the film is the Lagrangian set)",
        ));
    }
    let mut parts = Vec::new();
    for r in regions {
        let mut part = read_region(dir, r, opts)?;
        if parts.is_empty() {
            part.stored.extend(skipped.iter().cloned());
        }
        parts.push(part);
    }
    let vp = dir.join("v_tracker_points");
    if vp.is_file() {
        let v = decode_floats(&read_file(&vp)?, 4).map_err(|m| format_error(&vp, FORMAT, m))?;
        if v.len > 0 {
            let positions: Vec<Vec3> = v.vec3s(0);
            let cloud = crate::pointcloud::PointCloud {
                positions,
                ..Default::default()
            };
            parts.push(CloudPart {
                label: format!("{} (droplets)", vp.display()),
                kind: PartKind::Droplets,
                cloud,
                stored: vec![StoredAttribute::new(
                    "v_tracker_points",
                    "float32",
                    3,
                    AttributeRole::Position,
                )],
                notes: Vec::new(),
            });
        }
    }
    Ok(parts)
}

/// One region's Lagrangian particles.
fn read_region(dir: &Path, r: usize, opts: &ReadOptions) -> Result<CloudPart> {
    let tp = dir.join(format!("l_tracker_points_{r}"));
    let a = decode_floats(&read_file(&tp)?, 4).map_err(|m| format_error(&tp, FORMAT, m))?;
    let n = a.len;
    let mut cols = Columns {
        positions: a.vec3s(0),
        ..Columns::default()
    };
    cols.note_positions(&format!("l_tracker_points_{r}"), "float32");
    let tc = dir.join(format!("l_tracker_circles_{r}"));
    if tc.is_file() {
        let c = decode_floats(&read_file(&tc)?, 8).map_err(|m| format_error(&tc, FORMAT, m))?;
        if c.len != n {
            return Err(format_error(
                &tc,
                FORMAT,
                format!("{} circles for {n} particles", c.len),
            ));
        }
        cols.push("n", 3, "float32", c.flat3(4));
    }
    for (file, name) in [("l_h_bin", "h"), ("l_origin_bin", "origin")] {
        let p = dir.join(format!("{file}_{r}"));
        if !p.is_file() {
            continue;
        }
        let h =
            decode_elements(&read_file(&p)?, Some(n)).map_err(|m| format_error(&p, FORMAT, m))?;
        cols.push(
            name,
            h.components,
            h.stored,
            h.values.iter().map(|v| *v as f32).collect(),
        );
    }
    let (cloud, stored) = cols
        .into_cloud(opts, &ALIASES)
        .map_err(|m| format_error(dir, FORMAT, m))?;
    Ok(CloudPart::film(
        format!("{} (region {r})", dir.display()),
        cloud,
        stored,
    ))
}
