//! A sequence's camera frame by frame: fixed, a turntable (`orbit`: turned about the up axis
//! around its look-at point) or a path through camera keys (`[[camera.key]]`).
//!
//! Every frame's camera depends only on the sequence's frame list, its start camera (see
//! [`super::sequence`]) and the scene, never on which job of a farm asks, so shards agree.

use super::framing::{DEFAULT_UP, camera_toml};
use crate::scene::{CameraDesc, CameraKey, check_keys};
use crate::{Error, Result};
use glam::{DQuat, DVec3};

/// One frame's camera: position and look-at always set, and the exposure (EV) when a camera
/// path sets one.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameCamera {
    /// The camera (as `[camera]` keys) this frame is rendered from.
    pub camera: CameraDesc,
    /// Exposure of this frame, EV, when camera keys give one (else the scene's).
    pub exposure: Option<f32>,
    /// Degrees this frame is turned by an orbit: the light turns with the camera (0 else).
    pub turn_deg: f32,
}

/// How the camera moves over a sequence.
#[derive(Debug, Clone, PartialEq)]
pub enum CameraMove {
    /// One camera for every frame.
    Fixed,
    /// Turned by `degrees`·i/N about the up axis at frame i of N, around its look-at point.
    Orbit {
        /// Degrees turned over the whole sequence (360: a loop without a repeated frame).
        degrees: f32,
    },
    /// Along a path through keys (in increasing frame order, checked).
    Keys(Vec<CameraKey>),
}

impl CameraMove {
    /// The move `[camera]` asks for: keys, an orbit (0 is none) or fixed.
    ///
    /// # Errors
    /// [`Error::Invalid`] for an orbit that is not finite, an orbit with keys, keys with a
    /// `[camera] position` (both place the camera), an orbit about an explicit position
    /// without `look_at`, or bad keys ([`check_keys`]).
    pub fn of(c: &CameraDesc) -> Result<Self> {
        let orbit = c.orbit.unwrap_or(0.0);
        if !orbit.is_finite() {
            return Err(Error::invalid(format!(
                "camera.orbit must be a finite number of degrees, got {orbit}"
            )));
        }
        if !c.key.is_empty() {
            if orbit != 0.0 {
                return Err(Error::invalid(
                    "camera.orbit and [[camera.key]] both move the camera: choose one",
                ));
            }
            if c.position.is_some() {
                return Err(Error::invalid(
                    "camera.position and [[camera.key]] both place the camera: choose one \
                     (the keys' positions are the path)",
                ));
            }
            check_keys(&c.key).map_err(Error::invalid)?;
            return Ok(CameraMove::Keys(c.key.clone()));
        }
        if orbit == 0.0 {
            return Ok(CameraMove::Fixed);
        }
        if c.position.is_some() && c.look_at.is_none() {
            return Err(Error::invalid(
                "camera.orbit turns the camera around camera.look_at: give it with \
                 camera.position",
            ));
        }
        Ok(CameraMove::Orbit { degrees: orbit })
    }

    /// Whether the start camera must be auto-framed for this move even when the scene would
    /// not need it: keys that leave the look-at point to the framing.
    pub fn needs_framing(&self) -> bool {
        matches!(self, CameraMove::Keys(k) if k.first().is_some_and(|k| k.look_at.is_none()))
    }

    /// Frame `f`'s camera in a sequence of `frames` (in order, contiguous) that starts from
    /// `start` (position and look-at set; for keys, `start` only lends its look-at, up and
    /// lens where the keys give none).
    ///
    /// # Errors
    /// [`Error::Internal`] if an orbit's start camera lacks a position or look-at.
    pub fn at(&self, start: &CameraDesc, frames: &[u64], f: u64) -> Result<FrameCamera> {
        match self {
            CameraMove::Fixed => Ok(FrameCamera {
                camera: start.clone(),
                ..FrameCamera::default()
            }),
            CameraMove::Orbit { degrees } => {
                let (i, n) = (f.saturating_sub(frames[0]), frames.len() as u64);
                let angle = *degrees as f64 * i as f64 / n.max(1) as f64;
                Ok(FrameCamera {
                    camera: orbit(start, angle)?,
                    exposure: None,
                    turn_deg: angle as f32,
                })
            }
            CameraMove::Keys(keys) => Ok(along_keys(keys, f as f64, start)),
        }
    }
}

/// `start` turned by `degrees` about its up axis (default +y) through its look-at point:
/// counter-clockwise seen from the up side (right-handed). The built-in studio turns about +y
/// (see [`crate::render::Environment::turn`]), so with another up the light and the orbit
/// turn about different axes.
///
/// # Errors
/// [`Error::Internal`] without a position or look-at.
pub fn orbit(start: &CameraDesc, degrees: f64) -> Result<CameraDesc> {
    let (Some(p), Some(t)) = (start.position, start.look_at) else {
        return Err(Error::Internal(
            "an orbit's start camera is not placed".into(),
        ));
    };
    let up = DVec3::from(start.up.unwrap_or(DEFAULT_UP).map(f64::from))
        .try_normalize()
        .unwrap_or(DVec3::Y);
    let (p, t) = (v64(p), v64(t));
    let turned = t + DQuat::from_axis_angle(up, degrees.to_radians()) * (p - t);
    Ok(CameraDesc {
        position: Some(turned.as_vec3().to_array()),
        ..start.clone()
    })
}

/// The camera along `keys` (checked, not empty) at frame `t` (fractional frames allowed):
/// position and look-at on a natural cubic spline through the keys over the frame number
/// (continuous position, velocity and acceleration; two keys give a straight line), fov,
/// aperture, focus distance and exposure eased between neighbouring keys (smoothstep: the
/// value holds still at each key). Before the first key and after the last, the end key
/// holds. What the keys leave out comes from `base`.
pub fn along_keys(keys: &[CameraKey], t: f64, base: &CameraDesc) -> FrameCamera {
    let xs: Vec<f64> = keys.iter().map(|k| k.frame as f64).collect();
    let t = t.clamp(xs[0], xs[xs.len() - 1]);
    let positions: Vec<DVec3> = keys.iter().map(|k| v64(k.position)).collect();
    let position = spline(&xs, &positions, t);
    let look_at = keys[0].look_at.map(|_| {
        let ts: Vec<DVec3> = keys
            .iter()
            .map(|k| v64(k.look_at.unwrap_or_default()))
            .collect();
        spline(&xs, &ts, t).as_vec3().to_array()
    });
    let scalar = |get: fn(&CameraKey) -> Option<f32>| -> Option<f32> {
        get(&keys[0])?;
        Some(eased(
            &xs,
            &keys
                .iter()
                .map(|k| get(k).unwrap_or(0.0))
                .collect::<Vec<_>>(),
            t,
        ))
    };
    let camera = CameraDesc {
        position: Some(position.as_vec3().to_array()),
        look_at: look_at.or(base.look_at),
        fov: scalar(|k| k.fov).or(base.fov),
        aperture: scalar(|k| k.aperture).or(base.aperture),
        focus_distance: scalar(|k| k.focus_distance).or(base.focus_distance),
        orbit: None,
        key: Vec::new(),
        ..base.clone()
    };
    FrameCamera {
        camera,
        exposure: scalar(|k| k.exposure),
        turn_deg: 0.0,
    }
}

/// `[f32; 3]` as a double-precision vector.
fn v64(v: [f32; 3]) -> DVec3 {
    DVec3::from(v.map(f64::from))
}

/// The natural cubic spline through (`xs`, `ys`) (xs strictly increasing) at `t` within
/// `xs[0]..=xs[last]`: second derivatives from the tridiagonal system (Thomas algorithm,
/// O(keys)), zero at both ends.
fn spline(xs: &[f64], ys: &[DVec3], t: f64) -> DVec3 {
    let n = xs.len();
    if n == 1 {
        return ys[0];
    }
    let h: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
    // Second derivatives m[0] = m[n-1] = 0; forward sweep over the interior rows.
    let mut m = vec![DVec3::ZERO; n];
    let (mut c, mut d) = (vec![0.0; n], vec![DVec3::ZERO; n]);
    for i in 1..n - 1 {
        let rhs = 6.0 * ((ys[i + 1] - ys[i]) / h[i] - (ys[i] - ys[i - 1]) / h[i - 1]);
        let diag = 2.0 * (h[i - 1] + h[i]) - h[i - 1] * c[i - 1];
        c[i] = h[i] / diag;
        d[i] = (rhs - h[i - 1] * d[i - 1]) / diag;
    }
    for i in (1..n - 1).rev() {
        m[i] = d[i] - c[i] * m[i + 1];
    }
    let k = xs.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
    let (a, b) = (xs[k + 1] - t, t - xs[k]);
    let hk = h[k];
    m[k] * a.powi(3) / (6.0 * hk)
        + m[k + 1] * b.powi(3) / (6.0 * hk)
        + (ys[k] / hk - m[k] * hk / 6.0) * a
        + (ys[k + 1] / hk - m[k + 1] * hk / 6.0) * b
}

/// `vs` eased between neighbouring keys at `t`: smoothstep 3u² − 2u³ of the span's fraction u.
fn eased(xs: &[f64], vs: &[f32], t: f64) -> f32 {
    let n = xs.len();
    if n == 1 {
        return vs[0];
    }
    let k = xs.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
    let u = ((t - xs[k]) / (xs[k + 1] - xs[k])).clamp(0.0, 1.0);
    let s = u * u * (3.0 - 2.0 * u);
    (vs[k] as f64 + (vs[k + 1] as f64 - vs[k] as f64) * s) as f32
}

/// Scene-file lines that reproduce the path: `[camera]` (the start camera, with `orbit` for a
/// turntable) or the keys as `[[camera.key]]` blocks, every number read back to the same
/// `f32`.
pub fn path_toml(start: &CameraDesc, mv: &CameraMove) -> String {
    match mv {
        CameraMove::Fixed => camera_toml(start),
        CameraMove::Orbit { degrees } => camera_toml(start) + &format!("orbit = {degrees:?}\n"),
        CameraMove::Keys(keys) => {
            let head = CameraDesc {
                up: start.up,
                fov: start.fov,
                ..CameraDesc::default()
            };
            let mut s = if head == CameraDesc::default() {
                String::new()
            } else {
                camera_toml(&head)
            };
            for k in keys {
                s += &key_toml(k);
            }
            s
        }
    }
}

/// One key's `[[camera.key]]` lines.
pub fn key_toml(k: &CameraKey) -> String {
    let v3 = |v: [f32; 3]| format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2]);
    let mut s = format!(
        "[[camera.key]]\nframe = {}\nposition = {}\n",
        k.frame,
        v3(k.position)
    );
    if let Some(t) = k.look_at {
        s += &format!("look_at = {}\n", v3(t));
    }
    let scalars = [
        ("fov", k.fov),
        ("aperture", k.aperture),
        ("focus_distance", k.focus_distance),
        ("exposure", k.exposure),
    ];
    for (name, v) in scalars {
        if let Some(v) = v {
            s += &format!("{name} = {v:?}\n");
        }
    }
    s
}

#[cfg(test)]
#[path = "camera_path_tests.rs"]
mod tests;
