//! Pinhole camera: look-at placement, vertical field of view, and auto-framing of a cloud.

use crate::geometry::Ray;
use glam::Vec3;

/// A pinhole camera. Directions: `forward` looks at the target, `up` is the image's up.
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
        }
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
}
