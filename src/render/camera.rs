//! Camera: look-at placement, vertical field of view, auto-framing of a cloud, and an optional
//! thin lens for depth of field.

use crate::geometry::Ray;
use glam::Vec3;

/// A pinhole camera, or a thin lens when given an aperture. Directions: `forward` looks at the target, `up` is the image's up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position, scene units.
    pub position: Vec3,
    /// Unit view direction.
    forward: Vec3,
    /// Unit right vector of the image plane.
    right: Vec3,
    /// Unit up vector of the image plane.
    up: Vec3,
    /// tan(fov_y / 2).
    tan_half_fov: f32,
    /// Radius of the lens aperture, scene units (0: pinhole).
    lens_radius: f32,
    /// Distance of the plane in focus along the view direction, scene units.
    focus_distance: f32,
}

impl Camera {
    /// A camera at `position` looking at `target`, with `up` hinting the image's up direction and
    /// a vertical field of view of `fov_y_deg` degrees (1–170). If `up` is parallel to the view
    /// direction another up is chosen.
    pub fn look_at(position: Vec3, target: Vec3, up: Vec3, fov_y_deg: f32) -> Self {
        let forward = (target - position).try_normalize().unwrap_or(Vec3::NEG_Z);
        let mut right = forward.cross(up);
        if right.length_squared() < 1e-12 {
            right = forward.cross(if forward.x.abs() < 0.9 {
                Vec3::X
            } else {
                Vec3::Z
            });
        }
        let right = right.normalize();
        let up = right.cross(forward);
        let fov = fov_y_deg.clamp(1.0, 170.0).to_radians();
        Camera {
            position,
            forward,
            right,
            up,
            tan_half_fov: (0.5 * fov).tan(),
            lens_radius: 0.0,
            focus_distance: 1.0,
        }
    }

    /// This camera as a thin lens of aperture radius `aperture` (scene units, 0 = pinhole)
    /// focused at `focus_distance` (scene units, measured along the view direction). Points on
    /// that plane stay sharp; others blur into discs of diameter
    /// `2·aperture·|d − focus|/d` (in the plane of focus) at distance `d`.
    pub fn with_lens(mut self, aperture: f32, focus_distance: f32) -> Self {
        self.lens_radius = aperture.max(0.0);
        self.focus_distance = focus_distance.max(1e-6);
        self
    }

    /// True if the camera has a finite aperture.
    #[inline]
    pub fn has_lens(&self) -> bool {
        self.lens_radius > 0.0
    }

    /// Frames a bounding sphere (`centre`, `radius`, scene units) from direction `from` (pointing
    /// from the centre toward the camera), so the sphere fills the smaller image dimension with
    /// a small margin. Use the cloud's real bounding sphere, not its box's, or a round cloud
    /// ends up small in the frame.
    pub fn frame(
        centre: Vec3,
        radius: f32,
        from: Vec3,
        up: Vec3,
        fov_y_deg: f32,
        aspect: f32,
    ) -> Self {
        let radius = radius.max(1e-6);
        let half = 0.5 * fov_y_deg.clamp(1.0, 170.0).to_radians();
        // The narrower of the two half-angles decides.
        let half_min = if aspect < 1.0 {
            (half.tan() * aspect).atan()
        } else {
            half
        };
        let distance = 1.05 * radius / half_min.sin();
        let dir = from.try_normalize().unwrap_or(Vec3::Z);
        Camera::look_at(centre + dir * distance, centre, up, fov_y_deg)
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// Unit up vector of the image plane (perpendicular to [`Camera::forward`]).
    pub fn up(&self) -> Vec3 {
        self.up
    }

    /// Unit right vector of the image plane (perpendicular to both).
    pub fn right(&self) -> Vec3 {
        self.right
    }

    /// tan(fov_y / 2): the picture's half-height at unit distance along the view.
    pub fn tan_half_fov(&self) -> f32 {
        self.tan_half_fov
    }

    /// Radius (scene units) of a disk that covers one pixel of an image `height_px` pixels
    /// high at point `p`'s distance along the view direction: 0.75 pixel widths (a pixel's
    /// half-diagonal is 0.71). 0 for a point behind the camera.
    pub fn pixel_footprint(&self, p: Vec3, height_px: usize) -> f32 {
        let depth = (p - self.position).dot(self.forward);
        if depth <= 0.0 || height_px == 0 {
            return 0.0;
        }
        0.75 * 2.0 * self.tan_half_fov * depth / height_px as f32
    }

    /// The ray through film position (`sx`, `sy`) in [0, 1]² (x right, y down), for an image of
    /// aspect ratio `aspect` = width / height.
    #[inline]
    pub fn ray(&self, sx: f32, sy: f32, aspect: f32) -> Ray {
        let px = (2.0 * sx - 1.0) * self.tan_half_fov * aspect;
        let py = (1.0 - 2.0 * sy) * self.tan_half_fov;
        let dir = (self.forward + px * self.right + py * self.up).normalize();
        Ray {
            origin: self.position,
            dir,
        }
    }
}

impl Camera {
    /// Like [`ray`](Self::ray), through the lens point chosen by `lens` ∈ [0, 1)² (uniform over
    /// the aperture disk, concentric mapping); a pinhole ignores `lens`.
    #[inline]
    pub fn ray_lens(&self, sx: f32, sy: f32, aspect: f32, lens: (f32, f32)) -> Ray {
        let pin = self.ray(sx, sy, aspect);
        if self.lens_radius <= 0.0 {
            return pin;
        }
        // Where the pinhole ray meets the plane of focus.
        let focus = pin.origin + pin.dir * (self.focus_distance / pin.dir.dot(self.forward));
        let (a, b) = (2.0 * lens.0 - 1.0, 2.0 * lens.1 - 1.0);
        let (r, phi) = if a == 0.0 && b == 0.0 {
            (0.0, 0.0)
        } else if a.abs() > b.abs() {
            (a, std::f32::consts::FRAC_PI_4 * (b / a))
        } else {
            (
                b,
                std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (a / b),
            )
        };
        let origin =
            self.position + self.lens_radius * r * (phi.cos() * self.right + phi.sin() * self.up);
        Ray {
            origin,
            dir: (focus - origin).normalize(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_at_target_and_corners_span_the_fov() {
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 60.0);
        let r = cam.ray(0.5, 0.5, 1.0);
        assert!((r.dir - Vec3::NEG_Z).length() < 1e-6);
        let top = cam.ray(0.5, 0.0, 1.0);
        assert!((top.dir.angle_between(r.dir).to_degrees() - 30.0).abs() < 1e-3);
        assert!(top.dir.y > 0.0, "image y runs down, so sy = 0 is the top");
        let right = cam.ray(1.0, 0.5, 2.0);
        assert!(right.dir.x > 0.0);
    }

    #[test]
    fn framing_keeps_the_bounds_in_view() {
        let cam = Camera::frame(
            Vec3::ZERO,
            1.0,
            Vec3::new(1.0, 0.5, 2.0),
            Vec3::Y,
            40.0,
            16.0 / 9.0,
        );
        let to_centre = -cam.position;
        let half = 20f32.to_radians();
        let sphere_half_angle = (1.0 / to_centre.length()).asin();
        assert!(sphere_half_angle < half && sphere_half_angle > 0.8 * half);
    }

    /// A point on the plane of focus is reached from every lens point (stays sharp); a point
    /// off it spreads over a disc of the predicted size.
    #[test]
    fn thin_lens_focuses_the_focal_plane_and_blurs_the_rest() {
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0)
            .with_lens(0.2, 5.0);
        let pin = cam.ray(0.3, 0.6, 1.5);
        let target = pin.at(5.0 / pin.dir.dot(cam.forward()));
        let mut spread = 0.0f32;
        for i in 0..64 {
            let lens = ((i % 8) as f32 / 8.0 + 0.06, (i / 8) as f32 / 8.0 + 0.06);
            let r = cam.ray_lens(0.3, 0.6, 1.5, lens);
            // In focus: every lens ray passes through the same point.
            let t = (target - r.origin).dot(r.dir);
            assert!((r.at(t) - target).length() < 1e-4);
            // At distance 10 (twice the focus) the rays spread over ~2·0.2·(10−5)/5 = 0.4.
            let p = r.at(10.0 / r.dir.dot(cam.forward()) * 1.0);
            let q = pin.at(10.0 / pin.dir.dot(cam.forward()));
            spread = spread.max((p - q).length());
        }
        assert!(spread > 0.1 && spread < 0.25, "{spread}");
    }
}
