//! Motion blur (`--shutter S`): the film particles move along their stored velocity while the
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
use crate::pointcloud::clip::EdgeClip;
use crate::render::{FilmShader, RenderOutput, RenderSettings, View, WorldRef};
use crate::scene::SceneDesc;
use crate::{Error, Result};
use glam::Vec3;

/// Time slices of an open shutter when none are given.
pub const DEFAULT_SLICES: u32 = 8;
/// Most time slices.
pub const MAX_SLICES: u32 = 256;
/// Stored velocity attributes, as the readers name them (each with `_x`, `_y`, `_z`): VTK/VTU
/// and PLY `velocity`, the thin-film SPH snapshots' `v` (v.bin, m/s), MELP's `V`.
pub const VELOCITY_NAMES: [&str; 3] = ["velocity", "v", "V"];

/// `render.shutter`, `render.frame_time` and `render.shutter_slices`, checked: a shutter that
/// is open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShutterConfig {
    /// Fraction of a frame the shutter is open, (0, 1].
    pub open: f32,
    /// Simulation seconds between two frames (> 0).
    pub frame_time_s: f32,
    /// Time slices (1..=[`MAX_SLICES`]; fewer when the samples per pixel are fewer).
    pub slices: u32,
}

impl ShutterConfig {
    /// The shutter of `d`'s `[render]`: `None` when closed (0, the default).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key: a shutter outside [0, 1] or NaN, a frame time not
    /// finite and > 0, slices outside 1..=256, an open shutter without a frame time or with a
    /// scientific `view` (those show the frame's own positions).
    pub fn resolve(d: &SceneDesc, view: &View) -> Result<Option<Self>> {
        let r = &d.render;
        let open = r.shutter.unwrap_or(0.0);
        if !(0.0..=1.0).contains(&open) {
            return Err(Error::invalid(format!(
                "render.shutter (--shutter) must be the fraction of a frame the shutter is open, \
                 0..=1, got {open}"
            )));
        }
        if let Some(t) = r.frame_time.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(Error::invalid(format!(
                "render.frame_time (--frame-time) must be simulation seconds per frame, > 0, got {t}"
            )));
        }
        let slices = r.shutter_slices.unwrap_or(DEFAULT_SLICES);
        if !(1..=MAX_SLICES).contains(&slices) {
            return Err(Error::invalid(format!(
                "render.shutter_slices (--shutter-slices) must be 1..={MAX_SLICES}, got {slices}"
            )));
        }
        if open == 0.0 {
            return Ok(None);
        }
        let Some(frame_time_s) = r.frame_time else {
            return Err(Error::invalid(
                "render.shutter (--shutter) needs the simulation seconds per frame, \
                 render.frame_time (--frame-time SECONDS): the simulators do not store it",
            ));
        };
        if *view != View::Shaded {
            return Err(Error::invalid(format!(
                "render.shutter (--shutter) blurs the shaded view only; the {view} view shows \
                 the frame's own positions (drop --shutter or --view)"
            )));
        }
        Ok(Some(ShutterConfig {
            open,
            frame_time_s,
            slices,
        }))
    }

    /// The slices' time offsets from the frame's time, seconds: the middles of `n` equal parts
    /// of [−S/2, S/2] × the frame time, `n` the slices or `spp` if fewer (each slice needs a
    /// sample), in order.
    pub fn times_s(&self, spp: u32) -> Vec<f32> {
        let n = self.slices.min(spp).max(1);
        let span = self.open * self.frame_time_s;
        (0..n)
            .map(|k| span * ((k as f32 + 0.5) / n as f32 - 0.5))
            .collect()
    }
}

/// The films of one time slice.
#[derive(Debug)]
pub struct MotionSlice {
    /// Offset from the frame's time, simulation seconds.
    pub time_s: f32,
    /// The films moved to that time.
    pub geometry: FilmGeometry,
}

/// Each particle's velocity, scene units per simulation second, from the first of
/// [`VELOCITY_NAMES`] the cloud holds.
///
/// # Errors
/// [`Error::Invalid`] naming `source`: no velocity (with the attributes it has), or a
/// non-finite one (with the particle).
pub fn velocities(cloud: &PointCloud, source: &str) -> Result<Vec<Vec3>> {
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

/// The films at each time of `times_s`: positions moved by velocity × time, everything else
/// as on the unmoved cloud; one geometry each.
pub(super) fn slices(
    film: &FilmConfig,
    cloud: &PointCloud,
    velocities: &[Vec3],
    radii: &[f32],
    clips: &[EdgeClip],
    times_s: &[f32],
) -> Result<Vec<MotionSlice>> {
    times_s
        .iter()
        .map(|&t| {
            let moved = PointCloud {
                positions: (cloud.positions.iter().zip(velocities))
                    .map(|(p, v)| *p + *v * t)
                    .collect(),
                normals: cloud.normals.clone(),
                thickness_nm: cloud.thickness_nm.clone(),
                radius: cloud.radius.clone(),
                extra: Vec::new(),
            };
            Ok(MotionSlice {
                time_s: t,
                geometry: build::film_geometry(film, &moved, radii, None, clips)?,
            })
        })
        .collect()
}

/// Renders `world` once per slice (its films replaced by the slice's), the samples shared out
/// (slice k of K gets spp/K, the first spp mod K one more; a slice left without samples, when
/// the shot asks fewer samples than there are slices, is skipped) with seed mixed from the
/// shot's and k, and averages the buffers weighted by samples.
///
/// # Errors
/// As [`crate::render::render`].
pub(super) fn render(
    slices: &[MotionSlice],
    world: WorldRef,
    shader: &FilmShader,
    settings: &RenderSettings,
) -> Result<RenderOutput> {
    let (k, spp) = (slices.len() as u32, settings.spp);
    let mut sum: Option<RenderOutput> = None;
    for (i, slice) in (0u32..).zip(slices) {
        let spp_i = spp / k + u32::from(i < spp % k);
        if spp_i == 0 {
            continue;
        }
        let s = RenderSettings {
            spp: spp_i,
            seed: crate::mix::mix64(settings.seed ^ crate::mix::mix64(u64::from(i))),
            ..settings.clone()
        };
        let w = spp_i as f32 / spp as f32;
        let out = crate::render::render(
            WorldRef {
                geometry: &slice.geometry,
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
    use super::*;

    #[test]
    fn slices_are_centred_on_the_frame_and_fill_the_open_shutter() {
        let s = ShutterConfig {
            open: 0.5,
            frame_time_s: 0.02,
            slices: 4,
        };
        let t = s.times_s(64);
        // Middles of 4 parts of [-0.005, 0.005] s.
        let want = [-0.00375, -0.00125, 0.00125, 0.00375];
        assert_eq!(t.len(), 4);
        for (a, b) in t.iter().zip(want) {
            assert!((a - b).abs() < 1e-9, "{t:?}");
        }
        // Fewer samples than slices: one slice a sample, still centred.
        let t = s.times_s(2);
        assert!(
            (t[0] + t[1]).abs() < 1e-9 && (t[1] - 0.0025).abs() < 1e-9,
            "{t:?}"
        );
    }
}
