//! Bulk liquid apart from droplets: the 3D particles of the droplet parts are classified
//! ([`crate::pointcloud::liquid::classify`]); those in liquid bodies become the
//! [`LiquidSurface`], the rest stay droplets. By default (`[input] liquid = "auto"`) the run's
//! frame 0 decides first ([`super::liquid_origin`]): 3D particles shed after it stay droplets.
//! `"surface"` (CLI `--liquid surface`) always classifies; `"droplets"` keeps every 3D particle
//! a droplet, as before.

use std::path::PathBuf;

use super::Note;
pub use super::liquid_mode::LiquidMode;
use super::liquid_origin::{Origin, origin, shed_by_thickness};
use crate::Result;
use crate::geometry::{LiquidField, LiquidSurface};
use crate::pointcloud::PointCloud;
use crate::pointcloud::liquid::classify;

/// The droplet parts split into droplets and bulk liquid.
pub(super) struct Split {
    /// The particles that stay droplets: one cloud per part, attributes kept.
    pub kept: Vec<PointCloud>,
    /// The liquid bodies' surface.
    pub surface: LiquidSurface,
    /// The surface's particles: indices into the droplet parts' particles, taken in order
    /// (part by part), in the order the surface was built from.
    pub liquid: Vec<usize>,
}

impl Split {
    /// Every particle a droplet.
    fn none(drops: &[PointCloud]) -> Self {
        Split {
            kept: drops.to_vec(),
            surface: LiquidSurface::default(),
            liquid: Vec::new(),
        }
    }
}

/// Splits the droplet parts `drops` of the inputs `inputs` (resolved paths; none for a cloud
/// given in memory) into the particles that stay droplets and the liquid bodies' surface;
/// notes which rule decided and how many went where.
///
/// # Errors
/// As [`LiquidSurface::build`].
pub(super) fn split(
    drops: &[PointCloud],
    (mode, field): (LiquidMode, LiquidField),
    inputs: &[PathBuf],
    notes: &mut Vec<Note>,
) -> Result<Split> {
    let total: usize = drops.iter().map(PointCloud::len).sum();
    let why = match mode {
        _ if total == 0 => return Ok(Split::none(drops)),
        LiquidMode::Droplets => return Ok(Split::none(drops)),
        LiquidMode::Surface => "--liquid surface".to_string(),
        LiquidMode::Auto => match origin(inputs) {
            Origin::Shed(first) => {
                notes.push(Note::new(format!(
                    "liquid: 3D particles shed after frame 0 of this run ({} holds none): \
                     drawn as {total} droplets (--liquid surface draws bodies)",
                    first.display()
                )));
                return Ok(Split::none(drops));
            }
            Origin::SetUp(first, n) => format!(
                "{total} 3D particles present since frame 0 ({} holds {n})",
                first.display()
            ),
            Origin::Unknown(why) if shed_by_thickness(drops) => {
                notes.push(Note::new(format!(
                    "liquid: {why}: every 3D particle holds its own thickness rh (no two \
                     alike: each keeps that of the film particle it was shed from), so a \
                     rupture shed them: drawn as {total} droplets (--liquid surface draws bodies)"
                )));
                return Ok(Split::none(drops));
            }
            Origin::Unknown(why) => format!("{why}: positions decide"),
        },
    };
    by_packing(drops, &why, field, notes)
}

/// [`split`] by the particles' packing ([`classify`]); `why` starts the note.
fn by_packing(
    drops: &[PointCloud],
    why: &str,
    field: LiquidField,
    notes: &mut Vec<Note>,
) -> Result<Split> {
    let total: usize = drops.iter().map(PointCloud::len).sum();
    let positions: Vec<_> = drops
        .iter()
        .flat_map(|d| d.positions.iter().copied())
        .collect();
    let split = classify(&positions);
    if split.liquid.is_empty() {
        notes.push(Note::new(format!(
            "liquid: {why}: no 3D particle packed into a body, {total} droplets"
        )));
        return Ok(Split::none(drops));
    }
    let liquid: Vec<_> = split.liquid.iter().map(|&i| positions[i]).collect();
    let surface = LiquidSurface::build_with(&liquid, split.spacing, field)?;
    let mut keep = vec![false; total];
    split.droplets.iter().for_each(|&i| keep[i] = true);
    let mut start = 0;
    let kept = drops
        .iter()
        .map(|d| {
            let range = start..start + d.len();
            start = range.end;
            subset(d, &keep[range])
        })
        .collect();
    // What the particles' stored mass holds, for comparison: their droplet spheres' volume.
    let radii: Vec<f32> = drops
        .iter()
        .flat_map(|d| d.radius.clone().unwrap_or_else(|| vec![0.0; d.len()]))
        .collect();
    let stored: f64 = split
        .liquid
        .iter()
        .map(|&i| 4.0 / 3.0 * std::f64::consts::PI * (radii[i] as f64).powi(3))
        .sum();
    let drawn = split.liquid.len() as f64 * (split.spacing as f64).powi(3);
    notes.push(Note::new(format!(
        "liquid: {why}: {} bodies of water: 3D particles: {} in liquid bodies, drawn as a water surface (spacing {:.3e} m; each \
         particle the volume spacing³ the 3D SPH solver gives it, {drawn:.3e} m³ in all, where \
         their mass as droplets holds {stored:.3e} m³), {} stay droplets (fewer than {} \
         neighbours within {} spacings); --liquid droplets draws them all as droplets",
        split.bodies,
        split.liquid.len(),
        split.spacing,
        split.droplets.len(),
        crate::pointcloud::liquid::CORE_NEIGHBOURS,
        crate::pointcloud::liquid::NEIGHBOUR_SPACINGS,
    )));
    Ok(Split {
        kept,
        surface,
        liquid: split.liquid,
    })
}

/// The particles of `c` where `keep` holds, with every attribute.
fn subset(c: &PointCloud, keep: &[bool]) -> PointCloud {
    fn pick<T: Copy>(v: &[T], keep: &[bool]) -> Vec<T> {
        v.iter()
            .zip(keep)
            .filter(|(_, k)| **k)
            .map(|(x, _)| *x)
            .collect()
    }
    PointCloud {
        positions: pick(&c.positions, keep),
        normals: c.normals.as_deref().map(|v| pick(v, keep)),
        thickness_nm: c.thickness_nm.as_deref().map(|v| pick(v, keep)),
        radius: c.radius.as_deref().map(|v| pick(v, keep)),
        extra: c
            .extra
            .iter()
            .map(|(k, v)| (k.clone(), pick(v, keep)))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_parse() {
        assert_eq!(
            " Surface".parse::<LiquidMode>().unwrap(),
            LiquidMode::Surface
        );
        assert_eq!(
            "droplets".parse::<LiquidMode>().unwrap(),
            LiquidMode::Droplets
        );
        assert_eq!("AUTO".parse::<LiquidMode>().unwrap(), LiquidMode::Auto);
        assert_eq!(LiquidMode::default(), LiquidMode::Auto);
        assert!("mesh".parse::<LiquidMode>().is_err());
    }
}
