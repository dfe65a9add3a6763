//! "Frame all" for characters read from files: a scene that names a groom file but no camera
//! target or distance is looked at as a DCC viewer's "frame all" would, its body's and groom's
//! bounds filling the picture ([`Shot::frame_scene`]), instead of the procedural head's centre
//! from 0.8 m (which shows a centimetre-scale bust's shoulders, or fills the frame with a small
//! head).

use glam::Vec3;
use hair_core::{RigidTransform, Scene};
use serde::Serialize;

use crate::loaded::LoadedScene;
use crate::pipeline::Result;
use crate::scene_file::{MAX_CAMERA_DISTANCE, MIN_CAMERA_DISTANCE};
use crate::shot::{CameraPath, Shot};

/// Where a framed camera looks from: the bounds' centre and the distance that fits them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Framing {
    /// The bounds' lower corner [m].
    pub min: Vec3,
    /// The bounds' upper corner [m].
    pub max: Vec3,
    /// The point looked at, the bounds' centre [m].
    pub target: Vec3,
    /// The distance from it [m].
    pub distance: f32,
}

/// The scene's bounds `(min, max)` [m]: the body's mesh and the groom's skeletons at rest,
/// unposed. `None` for a scene with neither.
pub fn scene_bounds(scene: &Scene) -> Option<(Vec3, Vec3)> {
    let mut bounds = scene.head.mesh.bounds();
    let skeletons = &scene.groom.skeletons;
    let mut positions = Vec::new();
    for chain in 0..skeletons.chain_count() {
        positions.resize(skeletons.chain_node_count(chain), Vec3::ZERO);
        skeletons.rest_positions_of(chain, &RigidTransform::IDENTITY, &mut positions);
        for &p in &positions {
            bounds = Some(match bounds {
                None => (p, p),
                Some((lo, hi)) => (lo.min(p), hi.max(p)),
            });
        }
    }
    bounds.filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
}

/// The distance [m] from which a ball of `radius` [m] fits a camera of vertical field of view
/// `fov` [rad] and aspect `aspect` (width / height): `radius / sin(a)`, `a` the smaller of the
/// vertical and horizontal half-angles (`tan(a_h) = aspect·tan(fov/2)`), within the scene
/// file's camera distances.
pub fn fitting_distance(radius: f32, fov: f32, aspect: f32) -> f32 {
    let vertical = 0.5 * fov;
    let horizontal = (aspect * vertical.tan()).atan();
    let half_angle = vertical.min(horizontal);
    (radius / half_angle.sin()).clamp(MIN_CAMERA_DISTANCE, MAX_CAMERA_DISTANCE)
}

impl CameraPath {
    /// Looks at the centre of `(min, max)` from the distance that fits its bounding ball
    /// ([`fitting_distance`]) at `aspect`; the zoom-out ends at `end_distance` or 4 × that.
    pub fn frame_bounds(
        &mut self,
        (min, max): (Vec3, Vec3),
        aspect: f32,
        end_distance: Option<f32>,
    ) -> Framing {
        let target = 0.5 * (min + max);
        let distance = fitting_distance(0.5 * min.distance(max), self.fov, aspect);
        self.target = target;
        self.distance = distance;
        self.end_distance = end_distance.unwrap_or((4.0 * distance).min(MAX_CAMERA_DISTANCE));
        Framing {
            min,
            max,
            target,
            distance,
        }
    }
}

impl Shot {
    /// Frames the camera on `scene` where the scene file asked for it
    /// ([`CameraPath::frame_all`]): returns what it chose, `None` when the camera was left as
    /// given.
    pub fn frame_scene(&mut self, scene: &Scene) -> Option<Framing> {
        let frame_all = self.camera.frame_all?;
        let bounds = scene_bounds(scene)?;
        let aspect = self.width as f32 / self.height as f32;
        Some(
            self.camera
                .frame_bounds(bounds, aspect, frame_all.end_distance),
        )
    }

    /// [`Shot::build_loaded_scene`], then [`Shot::frame_scene`] on what was built.
    pub fn build_framed_scene(&mut self) -> Result<(Scene, Option<LoadedScene>, Option<Framing>)> {
        let (scene, loaded) = self.build_loaded_scene()?;
        let framing = self.frame_scene(&scene);
        Ok((scene, loaded, framing))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hair_core::Camera;

    #[test]
    fn the_fitting_distance_puts_the_ball_tangent_to_the_narrower_side_of_the_frustum() {
        // Landscape 16:9 at 35°: the vertical half-angle binds, d = r / sin(17.5°).
        let fov = 35f32.to_radians();
        let d = fitting_distance(0.3, fov, 16.0 / 9.0);
        assert!((d - 0.3 / 17.5f32.to_radians().sin()).abs() < 1e-5);
        // Portrait 1:2: the horizontal one, tan(a) = 0.5·tan(17.5°).
        let a = (0.5 * 17.5f32.to_radians().tan()).atan();
        let portrait = fitting_distance(0.3, fov, 0.5);
        assert!((portrait - 0.3 / a.sin()).abs() < 1e-5);
        // From that distance the ball is inside the frustum and touches it: a ball 1 % larger
        // is not (Camera::sphere_in_frustum tests the six planes).
        let camera = Camera::orbit(Vec3::ZERO, d, 0.7, 0.2, fov);
        assert!(camera.sphere_in_frustum(Vec3::ZERO, 0.3 * 0.999, 16.0 / 9.0));
        let inside = |r: f32, p: Vec3| camera.sphere_in_frustum(p, r, 16.0 / 9.0);
        // A point 1.01·r off the axis upwards (in the camera's up direction) is outside.
        let forward = (camera.target - camera.position).normalize();
        let up = forward.cross(Vec3::Y).cross(forward).normalize();
        let edge = up * (0.3 * 1.01 / 17.5f32.to_radians().cos());
        assert!(!inside(0.0, edge), "{edge}");
        assert!(inside(0.0, up * 0.29));
        assert_eq!(fitting_distance(1e9, fov, 1.0), MAX_CAMERA_DISTANCE);
    }
}
