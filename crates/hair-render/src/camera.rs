//! A look-at perspective camera (right-handed, +Y up, wgpu's 0..1 depth) and an orbit helper.

use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};

use crate::error::{Result, invalid};

/// A perspective camera looking from `position` at `target`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position [m].
    pub position: Vec3,
    /// Point looked at [m].
    pub target: Vec3,
    /// Up direction (need not be unit or orthogonal to the view direction, only not parallel).
    pub up: Vec3,
    /// Vertical field of view [rad], in (0, π).
    pub vertical_fov: f32,
    /// Near clipping distance [m], > 0.
    pub near: f32,
    /// Far clipping distance [m], > near.
    pub far: f32,
}

impl Default for Camera {
    /// 1 m in front of the origin on +Z (the face side), looking at it, 35° vertical field of view.
    fn default() -> Self {
        Camera {
            position: Vec3::new(0.0, 0.0, 1.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            vertical_fov: 35f32.to_radians(),
            near: 0.01,
            far: 100.0,
        }
    }
}

impl Camera {
    /// A camera on a sphere of radius `distance` [m] around `target`, at `azimuth` [rad] about +Y
    /// (0 = on +Z, π/2 = on +X) and `elevation` [rad] above the horizontal plane, looking at
    /// `target` with +Y up.
    pub fn orbit(
        target: Vec3,
        distance: f32,
        azimuth: f32,
        elevation: f32,
        vertical_fov: f32,
    ) -> Camera {
        let direction = Vec3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            elevation.cos() * azimuth.cos(),
        );
        Camera {
            position: target + direction * distance,
            target,
            up: Vec3::Y,
            vertical_fov,
            near: (distance * 0.01).max(1e-4),
            far: distance * 10.0 + 1.0,
        }
    }

    /// This camera turned by `angle` [rad] about the vertical axis through its target.
    pub fn orbited(&self, angle: f32) -> Camera {
        let rotation = glam::Quat::from_axis_angle(Vec3::Y, angle);
        Camera {
            position: self.target + rotation * (self.position - self.target),
            ..*self
        }
    }

    /// Checks that the camera is finite and well formed.
    pub fn validate(&self) -> Result<()> {
        let finite = self.position.is_finite()
            && self.target.is_finite()
            && self.up.is_finite()
            && self.vertical_fov.is_finite()
            && self.near.is_finite()
            && self.far.is_finite();
        if !finite {
            return Err(invalid(format!("camera has non-finite values: {self:?}")));
        }
        let forward = self.target - self.position;
        if forward.length_squared() < 1e-12 {
            return Err(invalid("camera position and target coincide"));
        }
        if forward
            .normalize()
            .cross(self.up.normalize_or_zero())
            .length_squared()
            < 1e-10
        {
            return Err(invalid(
                "camera up vector is zero or parallel to the view direction",
            ));
        }
        if !(self.vertical_fov > 0.0 && self.vertical_fov < std::f32::consts::PI) {
            return Err(invalid(format!(
                "vertical field of view {} rad is not in (0, π)",
                self.vertical_fov
            )));
        }
        if !(self.near > 0.0 && self.far > self.near) {
            return Err(invalid(format!(
                "clipping distances need 0 < near < far (near {}, far {})",
                self.near, self.far
            )));
        }
        Ok(())
    }

    /// The world-to-view matrix.
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.position, self.target, self.up)
    }

    /// The view-to-clip matrix for an image of the given aspect ratio (width / height), depth 0..1.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        glam::camera::rh::proj::directx::perspective(self.vertical_fov, aspect, self.near, self.far)
    }

    /// The world-to-clip matrix for an image of the given aspect ratio (width / height).
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// Where `point` [m] lands in a `width`×`height` image [pixels, origin top left, +y down],
    /// or `None` when it is behind the camera.
    pub fn project_to_pixel(&self, point: Vec3, width: u32, height: u32) -> Option<Vec2> {
        let aspect = width as f32 / height.max(1) as f32;
        let clip = self.view_projection(aspect) * point.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.xy() / clip.w;
        Some(Vec2::new(
            (ndc.x + 1.0) * 0.5 * width as f32,
            (1.0 - ndc.y) * 0.5 * height as f32,
        ))
    }

    /// The focal length in pixels for an image `height` pixels tall: a length `l` [m] at distance
    /// `d` [m] covers about `l · focal / d` pixels.
    pub fn focal_length_pixels(&self, height: u32) -> f32 {
        0.5 * height as f32 / (0.5 * self.vertical_fov).tan()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_projects_to_image_centre() {
        let camera = Camera::orbit(Vec3::new(0.1, 0.2, 0.3), 2.0, 0.7, 0.3, 0.8);
        let pixel = camera.project_to_pixel(camera.target, 200, 100).unwrap();
        assert!((pixel - Vec2::new(100.0, 50.0)).length() < 1e-3, "{pixel}");
        assert!(((camera.position - camera.target).length() - 2.0).abs() < 1e-5);
    }

    #[test]
    fn up_is_up_and_right_is_right() {
        let camera = Camera::default();
        let up = camera
            .project_to_pixel(Vec3::new(0.0, 0.1, 0.0), 100, 100)
            .unwrap();
        let right = camera
            .project_to_pixel(Vec3::new(0.1, 0.0, 0.0), 100, 100)
            .unwrap();
        assert!(up.y < 50.0 && (up.x - 50.0).abs() < 1e-3);
        assert!(right.x > 50.0 && (right.y - 50.0).abs() < 1e-3);
        // A length l at distance d covers l·f/d pixels (pinhole model).
        let expected = 0.1 * camera.focal_length_pixels(100) / 1.0;
        assert!(((right.x - 50.0) - expected).abs() < 1e-3);
    }

    #[test]
    fn orbiting_keeps_the_distance() {
        let camera = Camera::default().orbited(1.0);
        assert!((camera.position.length() - 1.0).abs() < 1e-6);
        assert!((camera.position.x - 1f32.sin()).abs() < 1e-6);
    }

    #[test]
    fn bad_cameras_are_rejected() {
        let good = Camera::default();
        assert!(good.validate().is_ok());
        assert!(
            Camera {
                target: good.position,
                ..good
            }
            .validate()
            .is_err()
        );
        assert!(
            Camera {
                up: Vec3::Z,
                ..good
            }
            .validate()
            .is_err()
        );
        assert!(Camera { near: 0.0, ..good }.validate().is_err());
        assert!(
            Camera {
                vertical_fov: f32::NAN,
                ..good
            }
            .validate()
            .is_err()
        );
        assert!(
            Camera {
                position: Vec3::NAN,
                ..good
            }
            .validate()
            .is_err()
        );
    }
}
