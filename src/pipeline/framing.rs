//! Auto-framing: the sphere a camera frames when the scene names no camera position, and the
//! one camera a whole sequence keeps (so a moving cloud moves in the picture).
//!
//! A sequence is framed once, on its first frame ([`Framing`] of that frame's prepared cloud)
//! or on the union of all its frames ([`Framing::union_all`]), and every frame is rendered from
//! [`sequence_camera`]'s explicit position and look-at. Both depend only on the frames, never
//! on which job of a render farm asks, so sharded jobs agree without talking.

pub use super::config::{DEFAULT_FOV, DEFAULT_FROM, DEFAULT_UP};

use super::config::{CameraConfig, check_focus};
use crate::render::Camera;
use crate::scene::{CameraDesc, SceneDesc};
use crate::{Error, Result};
use glam::Vec3;

/// What auto-framing frames: a box around the films and a sphere about the box's centre that
/// holds every splat whole. Scene units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Framing {
    /// Lower corner of the films' bounding box.
    pub min: Vec3,
    /// Upper corner of the films' bounding box.
    pub max: Vec3,
    /// Centre of the box: the point an auto-framed camera looks at.
    pub centre: Vec3,
    /// Radius of the sphere about `centre` that holds every splat (centre distance + radius).
    pub reach: f32,
}

impl Framing {
    /// The framing of splats at `positions` with `radii` whose geometry's box is
    /// `min`..`max`: centre of that box, reach to the farthest splat rim. Cost: one pass.
    pub fn of_splats(min: Vec3, max: Vec3, positions: &[Vec3], radii: &[f32]) -> Self {
        let centre = 0.5 * (min + max);
        let reach = positions
            .iter()
            .zip(radii)
            .map(|(p, r)| (*p - centre).length() + r)
            .fold(0.0f32, f32::max);
        Framing {
            min,
            max,
            centre,
            reach,
        }
    }

    /// One framing holding all of `framings` (e.g. every frame of a sequence): the union of
    /// their boxes, and a sphere about its centre holding each one's sphere. Independent of
    /// the order of `framings`. `None` if there are none.
    pub fn union_all(framings: &[Framing]) -> Option<Framing> {
        let first = framings.first()?;
        let (min, max) = framings.iter().fold((first.min, first.max), |(lo, hi), f| {
            (lo.min(f.min), hi.max(f.max))
        });
        let centre = 0.5 * (min + max);
        let reach = framings
            .iter()
            .map(|f| (f.centre - centre).length() + f.reach)
            .fold(0.0f32, f32::max);
        Some(Framing {
            min,
            max,
            centre,
            reach,
        })
    }
}

/// The box of a surface drawn through particles at `positions` (an MLS surface) whose
/// geometry's box `min`..`max` holds more than the surface: the centres' box grown by the
/// median of `radii` on every side, within `min`..`max`. An MLS surface's geometry box holds
/// its particles' support spheres, several spacings thick across a flat film, which made
/// [`view_direction`] take a flat film for a thick one and see it 16° above its plane while
/// the same film drawn as disks was seen from 50°; the surface itself lies within a fraction
/// of a spacing of the particles (half a spacing past an open edge). `min`..`max` unchanged
/// when there are no particles. Cost: one pass and a median.
pub fn surface_box(min: Vec3, max: Vec3, positions: &[Vec3], radii: &[f32]) -> (Vec3, Vec3) {
    let (lo, hi) = positions
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let mut sorted = radii.to_vec();
    let mid = sorted.len() / 2;
    let grow = match sorted.is_empty() {
        true => 0.0,
        false => *sorted.select_nth_unstable_by(mid, f32::total_cmp).1,
    };
    let (cut_min, cut_max) = (min.max(lo - grow), max.min(hi + grow));
    if positions.is_empty() || !cut_min.cmple(cut_max).all() {
        return (min, max);
    }
    (cut_min, cut_max)
}

/// The scene's explicit camera, or the auto-framed one for `framing` ([`auto_camera`]) in an
/// image of aspect `aspect`.
///
/// # Errors
/// [`Error::Invalid`] for a bad `[camera]` key, or a position equal to the look-at point.
pub fn camera(desc: &SceneDesc, framing: &Framing, aspect: f32) -> Result<Camera> {
    CameraConfig::resolve(&desc.camera)?.camera(framing, aspect)
}

/// The camera auto-framing picks for `framing` in an image of aspect `aspect` (width / height
/// of the part the scene fills): from `camera.from`, at the distance where the sphere fills
/// the smaller image dimension, looking at its centre, with the scene's lens. Ignores
/// `camera.position` (see [`camera`] for the camera a single render uses).
///
/// # Errors
/// [`Error::Invalid`] for a bad `camera.fov`, `camera.up`, `camera.from`, aperture or focus.
pub fn auto_camera(desc: &SceneDesc, framing: &Framing, aspect: f32) -> Result<Camera> {
    CameraConfig::resolve(&desc.camera)?.auto(framing, aspect)
}

impl CameraConfig {
    /// The explicit camera (position and look-at, default: the framing's centre), or without
    /// a position the auto-framed one ([`CameraConfig::auto`]).
    ///
    /// # Errors
    /// [`Error::Invalid`] if the position is the look-at point or the default focus distance
    /// is not positive.
    pub fn camera(&self, framing: &Framing, aspect: f32) -> Result<Camera> {
        let Some(p) = self.position else {
            return self.auto(framing, aspect);
        };
        let target = self.look_at.unwrap_or(framing.centre);
        if (p - target).length_squared() == 0.0 {
            return Err(Error::invalid(
                "camera.position and camera.look_at are the same point",
            ));
        }
        self.lens(Camera::look_at(p, target, self.up, self.fov_deg), target)
    }

    /// The auto-framed camera for `framing` (see [`auto_camera`]).
    ///
    /// # Errors
    /// As [`CameraConfig::camera`].
    pub fn auto(&self, framing: &Framing, aspect: f32) -> Result<Camera> {
        let from = if self.from_default {
            view_direction(self.from, framing)
        } else {
            self.from
        };
        let cam = Camera::frame(
            framing.centre,
            framing.reach,
            from,
            self.up,
            self.fov_deg,
            aspect,
        );
        self.lens(cam, framing.centre)
    }

    /// Adds the thin lens (`aperture`, `focus_distance`, default: focused on `target`).
    fn lens(&self, cam: Camera, target: Vec3) -> Result<Camera> {
        let focus = match self.focus_distance {
            Some(f) => f,
            None => check_focus((target - cam.position).dot(cam.forward()))?,
        };
        Ok(cam.with_lens(self.aperture, focus))
    }
}

/// A film whose box's thinnest side is at most this fraction of its longest is flat: with no
/// `camera.from` in the scene it is seen from at least [`FLAT_ELEVATION_DEG`] above its plane.
pub const FLAT_RATIO: f32 = 0.1;

/// Least angle, degrees, between the default view of a flat film and the film's plane (the
/// default direction sees a horizontal film 16° above it, where a thin ellipse hides its
/// interference pattern).
pub const FLAT_ELEVATION_DEG: f32 = 50.0;

/// The direction auto-framing looks from when the scene names none: the default `from`, raised
/// to [`FLAT_ELEVATION_DEG`] above the plane of a flat film (the box's thinnest axis; see
/// [`FLAT_RATIO`]) on the side `from` lies on, keeping its azimuth about that axis; `from`
/// itself for a film that is not flat or is already seen steeply enough.
pub fn view_direction(from: Vec3, framing: &Framing) -> Vec3 {
    let ext = framing.max - framing.min;
    let longest = ext.max_element();
    let axis = (0..3)
        .min_by(|a, b| ext[*a].total_cmp(&ext[*b]))
        .unwrap_or(1);
    let Some(d) = from.try_normalize() else {
        return from;
    };
    if !(longest > 0.0 && ext[axis] <= FLAT_RATIO * longest) {
        return from;
    }
    let n = Vec3::AXES[axis];
    let (sin, cos) = FLAT_ELEVATION_DEG.to_radians().sin_cos();
    let along = d.dot(n);
    if along.abs() >= sin {
        return from;
    }
    let side = if along < 0.0 { -1.0 } else { 1.0 };
    let planar = (d - along * n)
        .try_normalize()
        .unwrap_or_else(|| n.any_orthonormal_vector());
    planar * cos + n * (side * sin)
}

/// The explicit camera that reproduces [`auto_camera`] for `framing` exactly: `desc.camera`
/// with `position` and `look_at` set (and `fov`, `up` filled in with their defaults). Given to
/// every frame of a sequence, it renders the same pixels as auto-framing would on a cloud
/// with this framing. `None` if the scene already names a camera position (it wins).
///
/// # Errors
/// As [`auto_camera`].
pub fn sequence_camera(
    desc: &SceneDesc,
    framing: &Framing,
    aspect: f32,
) -> Result<Option<CameraDesc>> {
    if desc.camera.position.is_some() {
        return Ok(None);
    }
    let cam = auto_camera(desc, framing, aspect)?;
    let mut c = desc.camera.clone();
    c.position = Some(cam.position.to_array());
    c.look_at = Some(framing.centre.to_array());
    c.fov = Some(CameraConfig::resolve(&desc.camera)?.fov_deg);
    c.up = Some(c.up.unwrap_or(DEFAULT_UP));
    Ok(Some(c))
}

/// `[camera]` lines of a scene file for `c`'s position, look-at, field of view and up (the
/// keys that are set), with every number written so it reads back to the same `f32`.
pub fn camera_toml(c: &CameraDesc) -> String {
    let v3 = |v: [f32; 3]| format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]));
    let mut s = String::from("[camera]\n");
    if let Some(p) = c.position {
        s += &format!("position = {}\n", v3(p));
    }
    if let Some(t) = c.look_at {
        s += &format!("look_at = {}\n", v3(t));
    }
    if let Some(f) = c.fov {
        s += &format!("fov = {}\n", num(f));
    }
    if let Some(u) = c.up {
        s += &format!("up = {}\n", v3(u));
    }
    s
}

/// A TOML float that parses back to exactly `v` (Rust's shortest round-trip form, with a
/// decimal point).
fn num(v: f32) -> String {
    format!("{v:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(min: [f32; 3], max: [f32; 3], reach: f32) -> Framing {
        let (min, max) = (Vec3::from(min), Vec3::from(max));
        Framing {
            min,
            max,
            centre: 0.5 * (min + max),
            reach,
        }
    }

    #[test]
    fn a_flat_film_is_seen_from_above_its_plane_and_others_as_asked() {
        let from = Vec3::from(DEFAULT_FROM);
        let elevation = |d: Vec3, n: Vec3| d.normalize().dot(n).asin().to_degrees();
        // A horizontal film (thin in y): raised from 16° to 50°, same azimuth.
        let flat = f([-1.0, -0.01, -1.0], [1.0, 0.01, 1.0], 1.5);
        let d = view_direction(from, &flat);
        assert!((elevation(from, Vec3::Y) - 15.8).abs() < 0.1);
        assert!(
            (elevation(d, Vec3::Y) - FLAT_ELEVATION_DEG).abs() < 1e-3,
            "{d}"
        );
        assert!((d.x / d.z - from.x / from.z).abs() < 1e-5);
        // Thin in x: raised toward +x, the side `from` is on; below, toward -x.
        let side = f([-0.01, -1.0, -1.0], [0.01, 1.0, 1.0], 1.5);
        assert!((elevation(view_direction(from, &side), Vec3::X) - 50.0).abs() < 1e-3);
        let back = Vec3::new(-0.35, 0.3, 1.0);
        assert!((elevation(view_direction(back, &side), Vec3::X) + 50.0).abs() < 1e-3);
        // Thin in z: the default already sees it face on; a bubble is not flat.
        let facing = f([-1.0, -1.0, -0.01], [1.0, 1.0, 0.01], 1.5);
        assert_eq!(view_direction(from, &facing), from);
        let round = f([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0], 1.8);
        assert_eq!(view_direction(from, &round), from);
        // A named direction is kept, a flat film or not.
        let mut desc = SceneDesc::default();
        desc.camera.from = Some([0.35, 0.3, 1.0]);
        let named = auto_camera(&desc, &flat, 1.0).unwrap();
        let auto = auto_camera(&SceneDesc::default(), &flat, 1.0).unwrap();
        assert!((elevation(-named.forward(), Vec3::Y) - 15.8).abs() < 0.1);
        assert!((elevation(-auto.forward(), Vec3::Y) - 50.0).abs() < 1e-3);
    }

    #[test]
    fn the_union_holds_every_sphere_in_any_order() {
        let a = f([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0], 1.8);
        let b = f([3.0, -1.0, -1.0], [5.0, 1.0, 1.0], 1.8);
        let c = f([0.0, 2.0, 0.0], [0.5, 2.5, 0.5], 0.4);
        let u = Framing::union_all(&[a, b, c]).unwrap();
        assert_eq!(u.min, Vec3::new(-1.0, -1.0, -1.0));
        assert_eq!(u.max, Vec3::new(5.0, 2.5, 1.0));
        for g in [a, b, c] {
            assert!((g.centre - u.centre).length() + g.reach <= u.reach + 1e-6);
        }
        // Tight: the farthest sphere touches the union's.
        let tight = [a, b, c]
            .iter()
            .map(|g| (g.centre - u.centre).length() + g.reach)
            .fold(0.0f32, f32::max);
        assert_eq!(u.reach, tight);
        assert_eq!(Framing::union_all(&[c, b, a]), Some(u));
        assert_eq!(Framing::union_all(&[a]), Some(a));
        assert_eq!(Framing::union_all(&[]), None);
    }

    #[test]
    fn the_sequence_camera_reproduces_auto_framing_and_reads_back() {
        let desc = SceneDesc::default();
        let fr = Framing::of_splats(
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.5, 0.2),
            &[Vec3::new(-0.9, 0.1, 0.1), Vec3::new(0.9, 0.4, 0.1)],
            &[0.1, 0.1],
        );
        let auto = auto_camera(&desc, &fr, 16.0 / 9.0).unwrap();
        let fixed = sequence_camera(&desc, &fr, 16.0 / 9.0).unwrap().unwrap();
        let toml = camera_toml(&fixed);
        let back = SceneDesc::from_toml(&toml, "pasted").unwrap();
        assert_eq!(back.camera.position, fixed.position, "{toml}");
        assert_eq!(back.camera.look_at, fixed.look_at);
        assert_eq!(back.camera.fov, Some(40.0));
        assert_eq!(back.camera.up, Some([0.0, 1.0, 0.0]));
        // The pasted camera is the auto-framed one, bit for bit.
        let c = &back.camera;
        let explicit = CameraConfig::resolve(c)
            .unwrap()
            .camera(&Framing::of_splats(Vec3::ZERO, Vec3::ZERO, &[], &[]), 1.0)
            .unwrap();
        assert_eq!(explicit, auto);
        // A scene camera wins.
        let mut named = SceneDesc::default();
        named.camera.position = Some([0.0, 0.0, 5.0]);
        assert!(sequence_camera(&named, &fr, 1.0).unwrap().is_none());
    }
}
