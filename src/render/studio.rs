//! The built-in photo studio: a dark ground where the camera looks, a large diffuse dome
//! everywhere else and two soft boxes (see [`Studio`]).

use glam::{Mat3, Quat, Vec3};

/// A rectangular soft box of the studio: bright inside, falling smoothly to 0 over its rim.
#[derive(Debug, Clone, Copy)]
pub struct SoftBox {
    /// Unit direction toward the box's centre.
    pub dir: Vec3,
    /// Half-width and half-height, as tangents of the half-angles.
    pub half_size: (f32, f32),
    /// Width of the soft rim, in the same tangent units.
    pub softness: f32,
    /// Radiance at the centre (linear RGB).
    pub radiance: Vec3,
}

impl SoftBox {
    /// A soft box toward `dir` (any non-zero length; normalised here) with half-size, rim
    /// width (tangent units) and centre radiance.
    pub fn new(dir: Vec3, half_size: (f32, f32), softness: f32, radiance: Vec3) -> Self {
        SoftBox {
            dir: dir.normalize(),
            half_size,
            softness,
            radiance,
        }
    }

    fn radiance(&self, dir: Vec3) -> Vec3 {
        let c = dir.dot(self.dir);
        if c <= 0.0 {
            return Vec3::ZERO;
        }
        // Box frame: right is horizontal (perpendicular to +y), up completes it.
        let right = self.dir.cross(Vec3::Y).try_normalize().unwrap_or(Vec3::X);
        let up = right.cross(self.dir);
        let (u, v) = (dir.dot(right) / c, dir.dot(up) / c);
        let edge =
            |x: f32, half: f32| smoothstep(half + self.softness, half - self.softness, x.abs());
        self.radiance * edge(u, self.half_size.0) * edge(v, self.half_size.1)
    }
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The built-in photo studio, set up as bubble photographers do: a dark ground behind the
/// subject, exactly where the camera looks (what it sees around and through the film), and a
/// large diffuse source everywhere else (a dome around the subject, over, under, beside and
/// behind the camera) that the film reflects, so its interference colours show over most of
/// its face whatever its shape: a sphere's front reflects every direction, a flat film viewed
/// from above the dome over it, a torn fragment turned every way the dome beside the picture.
/// Two soft boxes add highlights that show the shape.
///
/// The dark ground is the picture's frustum: the directions within the picture's half-angles
/// (`frame`: tangents of the default camera's 40° vertical field at 16:9, or the shot's own,
/// [`Studio::framed`]) of `view` (the default auto-framed camera's viewing direction), widened
/// by [`Studio::GROUND_MARGIN`] and fading into the dome over [`Studio::SOFT_EDGE`]. All of it
/// is set up in the studio's own frame and carried into the scene by `rig`: a photographer's
/// rig that moves with the camera ([`Studio::rigged_to`]), so every camera, however high,
/// sees the film as the default camera does.
#[derive(Debug, Clone)]
pub struct Studio {
    /// Dark ground radiance straight down, at the horizon and straight up.
    pub backdrop: [Vec3; 3],
    /// Diffuse dome radiance straight down, at the horizon and straight up.
    pub dome: [Vec3; 3],
    /// Unit direction the camera looks along: the dark ground is around it.
    pub view: Vec3,
    /// The soft boxes.
    pub boxes: Vec<SoftBox>,
    /// Multiplier on everything.
    pub intensity: f32,
    /// World from studio: the rotation that carries the studio (its `view`, boxes and up,
    /// +y) into the scene. Identity: the default camera's studio.
    pub rig: Quat,
    /// Half-width and half-height of the picture the dark ground fills, as tangents of the
    /// half-angles from `view` (horizontal, vertical).
    pub frame: (f32, f32),
}

impl Default for Studio {
    fn default() -> Self {
        let boxes = vec![
            // Key: bright, upper left behind the camera: a crisp highlight.
            SoftBox::new(
                Vec3::new(-0.55, 0.55, 0.62),
                (0.30, 0.40),
                0.06,
                Vec3::splat(6.0),
            ),
            // Fill: right, lower and warmer.
            SoftBox::new(
                Vec3::new(0.85, 0.05, 0.50),
                (0.22, 0.45),
                0.06,
                Vec3::new(3.2, 3.0, 2.7),
            ),
        ];
        Studio {
            backdrop: [
                Vec3::new(0.004, 0.004, 0.005),
                Vec3::new(0.010, 0.010, 0.013),
                Vec3::new(0.016, 0.017, 0.021),
            ],
            // Bright enough that a film of 4 % reflectance (a thick film, or a thin one off its
            // colour peaks) shows at L* ≈ 30 and more: the dome floor is a white sheet.
            dome: [
                Vec3::new(1.2, 1.2, 1.2),
                Vec3::new(2.0, 2.0, 2.05),
                Vec3::new(3.0, 3.0, 3.1),
            ],
            // The default auto-framed camera looks from +z, a little right and above
            // (`pipeline::config::DEFAULT_FROM`).
            view: -Vec3::new(0.35, 0.3, 1.0).normalize(),
            boxes,
            intensity: 1.0,
            rig: Quat::IDENTITY,
            // The default camera: 40° vertical field, 16:9.
            frame: (
                20f32.to_radians().tan() * 16.0 / 9.0,
                20f32.to_radians().tan(),
            ),
        }
    }
}

impl Studio {
    /// How far the dark ground reaches past the picture's edges, degrees: a lens's rays and a
    /// pixel's footprint at the edge stay on it.
    pub const GROUND_MARGIN: f32 = 0.5;
    /// Width of the soft edge between dark ground and dome, degrees.
    pub const SOFT_EDGE: f32 = 4.0;

    /// The default studio with its dark ground facing `view` (the camera's viewing
    /// direction; the default's if zero or not finite).
    pub fn facing(view: Vec3) -> Self {
        let d = Studio::default();
        match view.try_normalize() {
            Some(v) => Studio { view: v, ..d },
            None => d,
        }
    }

    /// This studio carried along with a camera that looks along `forward` with image up `up`
    /// (unit, perpendicular; [`crate::render::Camera::forward`] and `up`): the rig turns the
    /// default camera's frame (looking along the default `view`, up +y) onto the camera's, so
    /// the dark ground stays behind the subject and the dome around it for a camera at any
    /// elevation, azimuth or roll. A camera within 1e-5 of the default's frame keeps the
    /// identity (its pictures exactly as without a rig).
    pub fn rigged_to(&self, forward: Vec3, up: Vec3) -> Studio {
        let frame = |f: Vec3, u: Vec3| {
            let right = f.cross(u).try_normalize()?;
            Some(Mat3::from_cols(right, right.cross(f), f))
        };
        let rig = match (frame(Studio::default().view, Vec3::Y), frame(forward, up)) {
            (Some(from), Some(to)) => Quat::from_mat3(&(to * from.transpose())).normalize(),
            _ => Quat::IDENTITY,
        };
        let rig = if rig.abs_diff_eq(Quat::IDENTITY, 1e-5) {
            Quat::IDENTITY
        } else {
            rig
        };
        Studio {
            rig,
            ..self.clone()
        }
    }

    /// This studio with its dark ground sized to a picture of vertical half-field
    /// `tan_half_fov` (tangent) and `aspect` (width / height); unchanged for a value that is
    /// not finite and positive.
    pub fn framed(&self, tan_half_fov: f32, aspect: f32) -> Studio {
        let (w, h) = (tan_half_fov * aspect, tan_half_fov);
        let frame = if w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0 {
            (w, h)
        } else {
            self.frame
        };
        Studio {
            frame,
            ..self.clone()
        }
    }

    /// How much of direction `dir` (studio frame) is dark ground, 0 (dome) ..= 1: inside the
    /// picture's frustum around `view` (image up along +y), widened by the margin, with a
    /// soft edge.
    fn ground(&self, dir: Vec3) -> f32 {
        let forward = dir.dot(self.view);
        if forward <= 0.0 {
            return 0.0;
        }
        let right = self.view.cross(Vec3::Y).try_normalize().unwrap_or(Vec3::X);
        let up = right.cross(self.view);
        let edge = |off: f32, half: f32| {
            let deg = (off.abs() / forward).atan().to_degrees();
            let top = half.atan().to_degrees() + Self::GROUND_MARGIN;
            smoothstep(top + Self::SOFT_EDGE, top, deg)
        };
        edge(dir.dot(right), self.frame.0) * edge(dir.dot(up), self.frame.1)
    }

    pub(super) fn radiance(&self, dir: Vec3) -> Vec3 {
        // Into the studio's own frame.
        let dir = if self.rig == Quat::IDENTITY {
            dir
        } else {
            self.rig.inverse() * dir
        };
        let y = dir.y.clamp(-1.0, 1.0);
        let gradient = |g: &[Vec3; 3]| {
            if y < 0.0 {
                g[1].lerp(g[0], -y)
            } else {
                g[1].lerp(g[2], y)
            }
        };
        let back = gradient(&self.backdrop).lerp(gradient(&self.dome), 1.0 - self.ground(dir));
        let boxes: Vec3 = self.boxes.iter().map(|b| b.radiance(dir)).sum();
        (back + boxes) * self.intensity
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Environment;

    #[test]
    fn studio_has_bright_boxes_on_a_dark_backdrop() {
        let s = Environment::Studio(Studio::default());
        let key = Vec3::new(-0.55, 0.55, 0.62).normalize();
        assert!(s.radiance(key).min_element() > 4.0);
        assert!(
            s.radiance(Vec3::new(0.0, -0.2, -1.0).normalize())
                .max_element()
                < 0.1
        );
        // The dome: what a horizontal film seen by the default camera reflects (32° above
        // the view), straight up, and behind the camera; the dark ground faces the camera.
        for bright in [
            Vec3::new(-0.35, 0.3, -1.0),
            Vec3::Y,
            Vec3::new(0.0, -0.5, 1.0),
        ] {
            assert!(
                s.radiance(bright.normalize()).min_element() > 1.0,
                "{bright}"
            );
        }
        let turned = Environment::Studio(Studio::facing(Vec3::X));
        assert!(
            turned
                .radiance(Vec3::new(1.0, -0.1, 0.0).normalize())
                .max_element()
                < 0.1
        );
        assert!(
            turned
                .radiance(Vec3::new(-1.0, -0.1, 0.0).normalize())
                .min_element()
                > 1.0
        );
        for i in 0..1000 {
            let d = Vec3::new(
                (i as f32 * 0.37).sin(),
                (i as f32 * 0.11).cos(),
                (i as f32 * 0.73).sin(),
            );
            let r = s.radiance(d.normalize());
            assert!(r.is_finite() && r.min_element() >= 0.0);
        }
    }

    #[test]
    fn a_rigged_studio_shows_every_camera_what_the_default_camera_sees() {
        let s = Studio::default();
        let (f0, up0) = (s.view, Vec3::Y.reject_from(s.view).normalize());
        // The default camera's own frame keeps the identity.
        assert_eq!(s.rigged_to(f0, up0).rig, Quat::IDENTITY);
        // Cameras straight down (up: −z), from below, and from the side rolled 90°.
        for (forward, up) in [
            (Vec3::NEG_Y, Vec3::NEG_Z),
            (Vec3::Y, Vec3::Z),
            (Vec3::X, Vec3::Z),
        ] {
            let r = Environment::Studio(s.rigged_to(forward, up));
            let right = forward.cross(up);
            let right0 = f0.cross(up0);
            // Any direction in the camera's frame gets what the default camera's same
            // direction gets: the dark ground ahead, the dome and boxes where they were.
            for (a, b, c) in [
                (0.0, 0.0, 1.0),
                (0.3, -0.2, 1.0),
                (0.2, 0.9, 0.1),
                (-0.5, 0.5, -0.7),
            ] {
                let d = (right * a + up * b + forward * c).normalize();
                let d0 = (right0 * a + up0 * b + f0 * c).normalize();
                let (x, y) = (r.radiance(d), Environment::Studio(s.clone()).radiance(d0));
                assert!(
                    (x - y).length() < 1e-3 * (1.0 + y.length()),
                    "{forward}: {x} vs {y}"
                );
            }
            assert!(r.radiance(forward).max_element() < 0.1, "{forward}");
        }
    }

    #[test]
    fn the_dark_ground_fills_the_picture_and_no_more() {
        // In the studio's frame: the camera looks along `view`, image up +y. A direction at
        // tangents (x, y) of the picture (x right, y up).
        let s = Studio::default();
        let right = s.view.cross(Vec3::Y).normalize();
        let up = right.cross(s.view);
        let at = |x: f32, y: f32| (s.view + right * x + up * y).normalize();
        let env = |s: &Studio| Environment::Studio(s.clone());
        let (w, h) = s.frame;
        // The picture's corners and edges are dark ground...
        for (x, y) in [(0.0, 0.0), (w, h), (-w, -h), (w, 0.0), (0.0, -h)] {
            assert!(
                env(&s).radiance(at(x, y)).max_element() < 0.05,
                "({x}, {y})"
            );
        }
        // ... and what lies 10° past them is the dome (the old dark wall reached 50° aside
        // and down to the floor: torn fragments turned aside reflected it).
        let past = |t: f32| (t.atan() + 10f32.to_radians()).tan();
        for (x, y) in [(past(w), 0.0), (0.0, -past(h)), (-past(w), -past(h))] {
            assert!(env(&s).radiance(at(x, y)).min_element() > 1.0, "({x}, {y})");
        }
        // A wider picture (3:1 at the same field) widens the ground with it.
        let wide = s.framed(h, 3.0);
        assert!(env(&wide).radiance(at(past(w), 0.0)).max_element() < 0.05);
        assert!(env(&wide).radiance(at(0.0, -past(h))).min_element() > 1.0);
        // Nonsense keeps the frame.
        assert_eq!(s.framed(f32::NAN, 1.0).frame, s.frame);
        assert_eq!(s.framed(0.3, -1.0).frame, s.frame);
    }
}
