//! Motion blur (`--shutter S`): the film particles, droplets and liquid move along their stored velocity while the
//! shutter is open, a centred shutter of S frames (time offsets t in [−S/2, S/2] × the frame
//! interval). The open shutter is cut into K equal time slices; each slice's films (positions
//! moved by v·t at the slice's middle; normals, radii and thickness as estimated on the unmoved
//! cloud) get their own geometry, rendered with the slice's share of the samples and its own
//! seed, and the pictures are averaged. Deterministic: the same for any thread count or shard.
//!
//! Costs K geometries (memory and build time K times the film's) and K renders of spp/K
//! samples. The simulators do not store the time between frames, so it is a setting
//! (`render.frame_time`, seconds), required with a shutter.

use super::build;
use super::config::FilmConfig;
use crate::geometry::FilmGeometry;
use crate::pointcloud::PointCloud;
use crate::pointcloud::cut::Cut;
use crate::render::{FilmShader, RenderOutput, RenderSettings, Staging, WorldRef};
use crate::{Error, Result};
use glam::Vec3;

/// Stored velocity attributes, as the readers name them (each with `_x`, `_y`, `_z`): VTK/VTU
/// and PLY `velocity`, the thin-film SPH snapshots' `v` (v.bin, m/s), MELP's `V`.
pub const VELOCITY_NAMES: [&str; 3] = ["velocity", "v", "V"];

/// The films of one time slice.
#[derive(Debug)]
pub struct MotionSlice {
    /// Offset from the frame's time, simulation seconds.
    pub time_s: f32,
    /// The films moved to that time.
    pub geometry: FilmGeometry,
    /// The lights, props and liquid of the scene with its droplets moved to that time (`None`
    /// without droplets: the scene's own).
    pub staging: Option<Staging>,
}

/// Each particle's velocity, scene units per simulation second, from the first of
/// [`VELOCITY_NAMES`] the cloud holds.
///
/// # Errors
/// [`Error::Invalid`] naming `source`: no velocity (with the attributes it has), or a
/// non-finite one (with the particle).
pub fn velocities(cloud: &PointCloud, source: &str) -> Result<Vec<Vec3>> {
    if let Some(v) = stored_velocities(cloud, source)? {
        return Ok(v);
    }
    let names: Vec<&str> = cloud.extra.iter().map(|(k, _)| k.as_str()).collect();
    let held = if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    };
    Err(Error::invalid(format!(
        "{source}: --shutter needs each particle's velocity (an attribute velocity, v or V with \
         x, y, z components); its attributes: {held} (a thin-film SPH frame folder's \
         point_velocity is line segments for viewers and is not read: its snapshot/N folders \
         hold v)"
    )))
}

/// The velocities of [`velocities`], `None` when the cloud holds none.
///
/// # Errors
/// [`Error::Invalid`] naming `source` and the particle for a non-finite velocity.
pub(super) fn stored_velocities(cloud: &PointCloud, source: &str) -> Result<Option<Vec<Vec3>>> {
    for name in VELOCITY_NAMES {
        let [Some(x), Some(y), Some(z)] =
            ["x", "y", "z"].map(|a| cloud.extra(&format!("{name}_{a}")))
        else {
            continue;
        };
        let v: Vec<Vec3> = (0..cloud.len())
            .map(|i| Vec3::new(x[i], y[i], z[i]))
            .collect();
        if let Some(i) = v.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(format!(
                "{source}: particle {i} has a non-finite velocity {name} = ({}, {}, {}); \
                 --shutter cannot move it",
                x[i], y[i], z[i]
            )));
        }
        return Ok(Some(v));
    }
    Ok(None)
}

/// `cloud`'s positions, normals, thickness and radii, the positions moved by `v` × `t`.
pub(super) fn moved(cloud: &PointCloud, v: &[Vec3], t: f32) -> PointCloud {
    PointCloud {
        positions: (cloud.positions.iter().zip(v))
            .map(|(p, v)| *p + *v * t)
            .collect(),
        normals: cloud.normals.clone(),
        thickness_nm: cloud.thickness_nm.clone(),
        radius: cloud.radius.clone(),
        extra: Vec::new(),
    }
}

/// The films at each time of `times_s`: positions moved by velocity × time, everything else
/// (radii, the disks' first-order `detail`, normals, thickness, the fit's cuts) as on the unmoved
/// cloud, so each slice costs only its tree's build; one geometry each.
pub(super) fn slices(
    film: &FilmConfig,
    cloud: &PointCloud,
    velocities: &[Vec3],
    (radii, detail): (&[f32], Option<&build::Detail>),
    parts: (&[Cut], &[u32]),
    times_s: &[f32],
) -> Result<Vec<MotionSlice>> {
    times_s
        .iter()
        .map(|&t| {
            let moved = moved(cloud, velocities, t);
            Ok(MotionSlice {
                time_s: t,
                geometry: build::film_geometry(film, &moved, radii, detail, parts)?,
                staging: None,
            })
        })
        .collect()
}

/// Renders `world` once per slice (its films replaced by the slice's), the samples shared out
/// (slice k of K gets spp/K, the first spp mod K one more) with seed mixed from the shot's and
/// k, and averages the buffers weighted by samples. A shot of fewer samples than slices (the
/// viewer's one-sample passes) renders spp slices spread evenly over the shutter, one sample
/// each (one sample: the middle slice, so the picture stays centred on the frame).
///
/// # Errors
/// As [`crate::render::render`].
pub(super) fn render(
    slices: &[MotionSlice],
    world: WorldRef,
    shader: &FilmShader,
    settings: &RenderSettings,
) -> Result<RenderOutput> {
    let mut sum: Option<RenderOutput> = None;
    for (i, spp_i) in shares(slices.len() as u32, settings.spp) {
        let slice = &slices[i as usize];
        let spp = settings.spp;
        let s = RenderSettings {
            spp: spp_i,
            seed: crate::mix::mix64(settings.seed ^ crate::mix::mix64(u64::from(i))),
            ..settings.clone()
        };
        let w = spp_i as f32 / spp as f32;
        // Moved droplets, grown to this camera's pixel footprints as `super::render` grows the
        // scene's.
        let grown = match &slice.staging {
            Some(st) => (st.droplets).footprints(|c| world.camera.pixel_footprint(c, s.height))?,
            None => None,
        };
        let (staging, footprints) = match &slice.staging {
            Some(st) => (st, grown.as_ref()),
            None => (world.staging, world.footprints),
        };
        let out = crate::render::render(
            WorldRef {
                geometry: &slice.geometry,
                staging,
                footprints,
                ..world
            },
            shader,
            &s,
        )?;
        sum = Some(match sum {
            None => scaled(out, w),
            Some(acc) => added(acc, &out, w),
        });
    }
    let mut out = sum.ok_or_else(|| Error::invalid("no samples to render"))?;
    // The first-hit buffers were summed weighted by coverage: back to means over what was met.
    for i in 0..out.alpha.len() {
        let a = out.alpha[i];
        let inv = if a > 0.0 { 1.0 / a } else { 0.0 };
        out.depth[i] *= inv;
        out.normal[i] *= inv;
        out.thickness[i] *= inv;
        out.hits[i] *= inv;
    }
    Ok(out)
}

/// The slices rendered and their samples: (slice, samples) for `k` slices and `spp` samples
/// (see [`render`]).
fn shares(k: u32, spp: u32) -> Vec<(u32, u32)> {
    if spp >= k {
        return (0..k)
            .map(|i| (i, spp / k + u32::from(i < spp % k)))
            .collect();
    }
    (0..spp).map(|j| ((2 * j + 1) * k / (2 * spp), 1)).collect()
}

/// `out` with every mean buffer times `w` (first-hit buffers times `w` × coverage).
fn scaled(mut out: RenderOutput, w: f32) -> RenderOutput {
    for i in 0..out.alpha.len() {
        let wa = w * out.alpha[i];
        out.rgb[i] *= w;
        out.depth[i] *= wa;
        out.normal[i] *= wa;
        out.thickness[i] *= wa;
        out.hits[i] *= wa;
        out.alpha[i] *= w;
        out.droplets[i] *= w;
    }
    out
}

/// `acc` plus `out` scaled as [`scaled`].
fn added(mut acc: RenderOutput, out: &RenderOutput, w: f32) -> RenderOutput {
    for i in 0..acc.alpha.len() {
        let wa = w * out.alpha[i];
        acc.rgb[i] += out.rgb[i] * w;
        acc.depth[i] += out.depth[i] * wa;
        acc.normal[i] += out.normal[i] * wa;
        acc.thickness[i] += out.thickness[i] * wa;
        acc.hits[i] += out.hits[i] * wa;
        acc.alpha[i] += out.alpha[i] * w;
        acc.droplets[i] += out.droplets[i] * w;
    }
    acc.rays += out.rays;
    acc
}

#[cfg(test)]
mod tests {
    #[test]
    fn samples_are_shared_out_and_few_samples_spread_over_the_shutter() {
        assert_eq!(super::shares(3, 7), [(0, 3), (1, 2), (2, 2)]);
        // One sample: the middle slice; two: the middles of each half.
        assert_eq!(super::shares(8, 1), [(4, 1)]);
        assert_eq!(super::shares(8, 2), [(2, 1), (6, 1)]);
    }
}
