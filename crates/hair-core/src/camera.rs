//! A look-at perspective camera (right-handed, +Y up, depth 0..1 as in wgpu), shared by level-of-detail
//! selection (screen sizes, frustum, occlusion rays) and the renderer.

use glam::{Mat4, Vec2, Vec3, Vec4, Vec4Swizzles};
use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result};

/// A perspective camera looking from `position` at `target`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
    /// `target` with +Y up; near and far planes scale with the distance.
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

    /// A camera at `position` looking at `target` with +Y up. The far plane scales with the
    /// look distance `d = |target − position|` as [`Camera::orbit`]'s does (`10·d + 1` [m]), so
    /// everything up to ten times beyond the target is drawn; the near plane is `d/1000` [m] (at
    /// least 0.1 mm), closer than an orbit's `d/100` because a keyframed camera often looks far
    /// past things near it (a crowd's front row).
    pub fn looking_at(position: Vec3, target: Vec3, vertical_fov: f32) -> Camera {
        let distance = position.distance(target);
        Camera {
            position,
            target,
            up: Vec3::Y,
            vertical_fov,
            near: (distance * 1e-3).max(1e-4),
            far: distance * 10.0 + 1.0,
        }
    }

    /// Checks that the camera is finite and well formed, naming what is wrong.
    pub fn validate(&self) -> Result<()> {
        let finite = self.position.is_finite()
            && self.target.is_finite()
            && self.up.is_finite()
            && self.vertical_fov.is_finite()
            && self.near.is_finite()
            && self.far.is_finite();
        if !finite {
            return Err(HairError::invalid(
                "camera",
                format!("{self:?}"),
                "finite position, target, up, field of view and clipping distances",
            ));
        }
        let forward = self.target - self.position;
        if forward.length_squared() < 1e-12 {
            return Err(HairError::invalid(
                "camera target",
                self.target,
                "a point away from the camera position",
            ));
        }
        if forward
            .normalize()
            .cross(self.up.normalize_or_zero())
            .length_squared()
            < 1e-10
        {
            return Err(HairError::invalid(
                "camera up vector",
                self.up,
                "non-zero and not parallel to the view direction",
            ));
        }
        if !(self.vertical_fov > 0.0 && self.vertical_fov < std::f32::consts::PI) {
            return Err(HairError::invalid(
                "camera vertical field of view (rad)",
                self.vertical_fov,
                "0 < fov < π",
            ));
        }
        if !(self.near > 0.0 && self.far > self.near) {
            return Err(HairError::invalid(
                "camera clipping distances (m)",
                format!("near {}, far {}", self.near, self.far),
                "0 < near < far",
            ));
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
    /// `d` [m] facing the camera covers `l · focal / d` pixels.
    pub fn focal_length_pixels(&self, height: u32) -> f32 {
        0.5 * height as f32 / (0.5 * self.vertical_fov).tan()
    }

    /// The six planes of the view frustum for an image of aspect `width / height`, each
    /// `(n, d)` packed as a `Vec4` with `n·x + d ≥ 0` inside (n not normalised).
    pub fn frustum_planes(&self, aspect: f32) -> [Vec4; 6] {
        let m = self.view_projection(aspect);
        let (r0, r1, r2, r3) = (m.row(0), m.row(1), m.row(2), m.row(3));
        // Gribb–Hartmann extraction for depth in 0..1: left, right, bottom, top, near, far.
        [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2]
    }

    /// Whether a sphere of `radius` [m] around `centre` [m] touches the view frustum of an image of
    /// aspect `width / height` (conservative: a sphere near a frustum corner may be reported inside).
    pub fn sphere_in_frustum(&self, centre: Vec3, radius: f32, aspect: f32) -> bool {
        self.frustum_planes(aspect).iter().all(|plane| {
            let normal = plane.xyz();
            let length = normal.length();
            length == 0.0 || (normal.dot(centre) + plane.w) / length >= -radius
        })
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
    fn a_length_covers_focal_times_length_over_distance_pixels() {
        let camera = Camera::default();
        let right = camera
            .project_to_pixel(Vec3::new(0.1, 0.0, 0.0), 100, 100)
            .unwrap();
        // Pinhole model: l·f/d pixels for a length l at distance d, facing the camera.
        let expected = 0.1 * camera.focal_length_pixels(100) / 1.0;
        assert!(((right.x - 50.0) - expected).abs() < 1e-3);
    }

    #[test]
    fn frustum_holds_what_projects_into_the_image() {
        let camera = Camera::orbit(Vec3::ZERO, 2.0, 0.4, 0.2, 0.7);
        let aspect = 1.5;
        // Brute force: points inside the frustum are exactly those projecting into the image with
        // depth between near and far.
        let mut random = crate::random::SplitMix64::new(5);
        for _ in 0..2000 {
            let point = Vec3::new(
                random.range(-1.0, 1.0),
                random.range(-1.0, 1.0),
                random.range(-1.0, 1.0),
            ) * 3.0;
            let clip = camera.view_projection(aspect) * point.extend(1.0);
            let inside = clip.w > 0.0
                && clip.x.abs() <= clip.w
                && clip.y.abs() <= clip.w
                && clip.z >= 0.0
                && clip.z <= clip.w;
            let margin = 1e-4;
            if inside == camera.sphere_in_frustum(point, 0.0, aspect) {
                continue;
            }
            // Disagreement only on the boundary, within rounding.
            assert!(
                camera.sphere_in_frustum(point, margin, aspect)
                    && !camera.sphere_in_frustum(point, -margin, aspect),
                "{point}"
            );
        }
        assert!(camera.sphere_in_frustum(Vec3::ZERO, 0.0, aspect));
        assert!(!camera.sphere_in_frustum(camera.position * 3.0, 0.1, aspect));
    }

    #[test]
    fn looking_at_sees_from_near_the_eye_to_far_beyond_the_target() {
        // A crowd shot: the eye 0.5 m above the front row, looking 40 m down the crowd.
        let eye = Vec3::new(0.0, 0.5, 0.9);
        let target = Vec3::new(0.0, -9.1, -39.1);
        let camera = Camera::looking_at(eye, target, 35f32.to_radians());
        camera.validate().unwrap();
        let aspect = 16.0 / 9.0;
        let along = (target - eye).normalize();
        // On the line of sight: in view from 0.1 m (past the near plane d/1000 = 41 mm) to
        // 400 m (within the far plane 10·d + 1 = 412 m), out of view beyond it.
        for distance in [0.1, 1.0, 30.0, 400.0] {
            assert!(
                camera.sphere_in_frustum(eye + along * distance, 0.0, aspect),
                "{distance}"
            );
        }
        assert!(!camera.sphere_in_frustum(eye + along * 420.0, 0.0, aspect));
        assert!(!camera.sphere_in_frustum(eye + along * 0.01, 0.0, aspect));
        // A head 40 m down the crowd, off the line of sight but in the picture.
        assert!(camera.sphere_in_frustum(Vec3::new(5.4, 0.0, -39.0), 0.15, aspect));
    }

    #[test]
    fn bad_cameras_are_rejected() {
        let good = Camera::default();
        assert!(good.validate().is_ok());
        let cases = [
            Camera {
                target: good.position,
                ..good
            },
            Camera {
                up: Vec3::Z,
                ..good
            },
            Camera { near: 0.0, ..good },
            Camera {
                vertical_fov: f32::NAN,
                ..good
            },
            Camera {
                position: Vec3::NAN,
                ..good
            },
        ];
        for camera in cases {
            assert!(camera.validate().is_err(), "{camera:?}");
        }
    }
}
