//! Environment lighting: the radiance arriving from infinitely far away in each direction.
//!
//! A film is a perfect specular surface, so everything it shows is the environment (and other
//! films) reflected and transmitted. Radiance is linear sRGB, scaled so 1 is a white surface
//! lit to display white.

use glam::Vec3;

use crate::prefetch::prefetch_read;

pub use super::studio::{SoftBox, Studio};

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

    /// The bilinear footprint of direction `dir`: the texel columns `xa`, `xb`, rows `ya`, `yb`
    /// and the weights `fx`, `fy` of the second column and row (None for an empty map).
    #[inline(always)]
    fn footprint(&self, dir: Vec3) -> Option<([usize; 4], f32, f32)> {
        if self.width == 0 || self.height == 0 {
            return None;
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
        Some(([xa, xb, ya, yb], fx, fy))
    }

    fn radiance(&self, dir: Vec3) -> Vec3 {
        let Some(([xa, xb, ya, yb], fx, fy)) = self.footprint(dir) else {
            return Vec3::ZERO;
        };
        let at = |x: usize, y: usize| self.texels[y * self.width + x];
        let top = at(xa, ya).lerp(at(xb, ya), fx);
        let bottom = at(xa, yb).lerp(at(xb, yb), fx);
        top.lerp(bottom, fy) * self.intensity
    }

    /// Asks the processor to fetch the texels `radiance(dir)` reads into the cache, without
    /// waiting for them (a no-op off x86-64).
    #[inline(always)]
    fn prefetch(&self, dir: Vec3) {
        let Some(([xa, xb, ya, yb], ..)) = self.footprint(dir) else {
            return;
        };
        for (x, y) in [(xa, ya), (xb, ya), (xa, yb), (xb, yb)] {
            prefetch_read(&self.texels[y * self.width + x]);
        }
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

    /// Starts fetching what `radiance(dir)` will read (a map's texels) so that a later call
    /// does not wait on memory; the other kinds read nothing. Changes no result.
    #[inline(always)]
    pub fn prefetch(&self, dir: Vec3) {
        if let Environment::Map(m) = self {
            m.prefetch(dir);
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
