//! Environment lighting: the radiance arriving from infinitely far away in each direction.
//!
//! A film is a perfect specular surface, so everything it shows is the environment (and other
//! films) reflected and transmitted. Radiance is linear sRGB, scaled so 1 is a white surface
//! lit to display white.

use glam::{Mat3, Quat, Vec3};

/// A lat-long (equirectangular) environment map: +y is up, the image's centre column looks
/// toward −z, u grows toward +x (the usual convention of HDR panoramas).
#[derive(Debug, Clone)]
pub struct LatLongMap {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
    /// Rotation about +y, radians.
    rotation: f32,
    /// Radiance multiplier.
    intensity: f32,
}

impl LatLongMap {
    /// A map from `width × height` linear RGB texels (row-major, top row = straight up), rotated
    /// by `rotation_deg` about +y and scaled by `intensity`. Non-finite or negative texels are
    /// replaced by 0 so they can never reach an image.
    pub fn new(
        width: usize,
        height: usize,
        mut texels: Vec<Vec3>,
        rotation_deg: f32,
        intensity: f32,
    ) -> Self {
        for t in &mut texels {
            *t = Vec3::select(t.cmpge(Vec3::ZERO) & t.is_finite_mask(), *t, Vec3::ZERO);
        }
        LatLongMap {
            width,
            height,
            texels,
            rotation: rotation_deg.to_radians(),
            intensity,
        }
    }

    fn radiance(&self, dir: Vec3) -> Vec3 {
        if self.width == 0 || self.height == 0 {
            return Vec3::ZERO;
        }
        let phi = dir.x.atan2(-dir.z) - self.rotation;
        let u = (phi / std::f32::consts::TAU + 0.5).rem_euclid(1.0);
        let v = dir.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
        // Bilinear, wrapping in u and clamping in v.
        let x = u * self.width as f32 - 0.5;
        let y = (v * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let xi = |x: f32| (x as i64).rem_euclid(self.width as i64) as usize;
        let (xa, xb) = (xi(x0), xi(x0 + 1.0));
        let (ya, yb) = (y0 as usize, (y0 as usize + 1).min(self.height - 1));
        let at = |x: usize, y: usize| self.texels[y * self.width + x];
        let top = at(xa, ya).lerp(at(xb, ya), fx);
        let bottom = at(xa, yb).lerp(at(xb, yb), fx);
        top.lerp(bottom, fy) * self.intensity
    }
}

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

/// The built-in photo studio, set up as bubble photographers do: a dark ground behind and
/// below the subject (what the camera sees around and through the film), and a large diffuse
/// source everywhere else (a dome over and behind the camera) that the film reflects, so its
/// interference colours show over most of its face whatever its shape: a sphere's front
/// reflects every direction, a flat film viewed from above the dome over it. Two soft boxes
/// add highlights that show the shape.
///
/// The dark ground faces `view` (the default auto-framed camera's viewing direction):
/// directions within [`Studio::GROUND_CONE`] of it, and, in the azimuths around it, every
/// direction below [`Studio::GROUND_ABOVE_VIEW`] over the view's elevation (the floor and
/// backdrop wall). All of it is set up in the studio's own frame and carried into the scene
/// by `rig`: a photographer's rig that moves with the camera ([`Studio::rigged_to`]), so
/// every camera, however high, sees the film as the default camera does.
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
        }
    }
}

impl Studio {
    /// Half-angle of the cone of dark ground around the view direction, degrees: the middle
    /// of the picture even when the camera looks straight down (the wall below is the rest).
    /// Narrower than the picture's diagonal on purpose: a flat film seen from 16° above (the
    /// default camera's elevation) reflects the direction 32° above the view, which must be
    /// dome.
    pub const GROUND_CONE: f32 = 22.0;
    /// How far the dark ground wall reaches above the view's elevation, degrees (the top of a
    /// 40° picture is 20° above it).
    pub const GROUND_ABOVE_VIEW: f32 = 22.0;
    /// Half-width of the dark wall's azimuths around the view's, degrees (a 16:9 picture of
    /// 40° vertical field spans ±33°).
    pub const GROUND_AZIMUTH: f32 = 50.0;
    /// Width of the soft edge between dark ground and dome, degrees.
    pub const SOFT_EDGE: f32 = 6.0;

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

    /// How much of direction `dir` is dark ground, 0 (dome) ..= 1.
    fn ground(&self, dir: Vec3) -> f32 {
        let deg = |c: f32| c.clamp(-1.0, 1.0).acos().to_degrees();
        let soft = Self::SOFT_EDGE;
        let cone = smoothstep(
            Self::GROUND_CONE + soft,
            Self::GROUND_CONE,
            deg(dir.dot(self.view)),
        );
        let elevation = |d: Vec3| d.y.clamp(-1.0, 1.0).asin().to_degrees();
        let top = elevation(self.view) + Self::GROUND_ABOVE_VIEW;
        let below = smoothstep(top + soft, top, elevation(dir));
        let azimuth = match (
            Vec3::new(dir.x, 0.0, dir.z).try_normalize(),
            Vec3::new(self.view.x, 0.0, self.view.z).try_normalize(),
        ) {
            (Some(a), Some(b)) => smoothstep(
                Self::GROUND_AZIMUTH + soft,
                Self::GROUND_AZIMUTH,
                deg(a.dot(b)),
            ),
            // Straight up or down, or a camera looking straight down: the cone decides.
            _ => 0.0,
        };
        cone.max(below * azimuth)
    }

    fn radiance(&self, dir: Vec3) -> Vec3 {
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

/// Where the light comes from.
#[derive(Debug, Clone)]
pub enum Environment {
    /// The same radiance from every direction (a "white furnace" when it is 1).
    Uniform(Vec3),
    /// `toward` from the hemisphere around `axis` (directions d with d·axis > 0), `away` from the
    /// other half.
    Hemispheres {
        /// Unit axis.
        axis: Vec3,
        /// Radiance of the hemisphere around `axis`.
        toward: Vec3,
        /// Radiance of the opposite hemisphere.
        away: Vec3,
    },
    /// The built-in studio.
    Studio(Studio),
    /// An HDR panorama.
    Map(LatLongMap),
}

impl Environment {
    /// Radiance arriving from direction `dir` (unit; the direction the light travels is `−dir`).
    #[inline]
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        match self {
            Environment::Uniform(c) => *c,
            Environment::Hemispheres { axis, toward, away } => {
                if dir.dot(*axis) > 0.0 {
                    *toward
                } else {
                    *away
                }
            }
            Environment::Studio(s) => s.radiance(dir),
            Environment::Map(m) => m.radiance(dir),
        }
    }
}

impl Environment {
    /// Turns the light `deg` degrees about +y, counter-clockwise seen from above (as a camera
    /// orbit turns its position), so a camera turned with it sees the scene as if the scene
    /// itself had turned the other way in a fixed studio: a turntable. The studio's ground
    /// and soft boxes turn; a map's rotation grows; a uniform light is unchanged.
    pub fn turn(&mut self, deg: f32) {
        let q = glam::Quat::from_rotation_y(deg.to_radians());
        match self {
            Environment::Uniform(_) => {}
            Environment::Hemispheres { axis, .. } => *axis = q * *axis,
            Environment::Studio(s) => s.rig = (q * s.rig).normalize(),
            // radiance(d) looks up phi(d) - rotation; turning by +deg moves phi by -deg.
            Environment::Map(m) => m.rotation -= deg.to_radians(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn latlong_lookup_finds_the_right_texels() {
        // 4×2 map: top row red, bottom row blue; a NaN texel is dropped.
        let mut t = vec![Vec3::X; 4];
        t.extend(vec![Vec3::Z; 4]);
        t[5] = Vec3::NAN;
        let m = Environment::Map(LatLongMap::new(4, 2, t, 0.0, 2.0));
        assert!((m.radiance(Vec3::Y) - 2.0 * Vec3::X).length() < 1e-5);
        assert!(m.radiance(Vec3::NEG_Y).is_finite());
        assert!(m.radiance(Vec3::NEG_Y).z > 0.0);
    }
}
