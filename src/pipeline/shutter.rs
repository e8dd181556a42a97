//! The shutter of motion blur (`render.shutter`, `render.frame_time`,
//! `render.shutter_slices`), checked, and the times of its slices (see [`super::motion`]).

use crate::render::View;
use crate::scene::SceneDesc;
use crate::{Error, Result};

/// Time slices of an open shutter when none are given.
pub const DEFAULT_SLICES: u32 = 8;
/// Most time slices.
pub const MAX_SLICES: u32 = 256;
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
