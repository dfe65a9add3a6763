//! The viewer's camera: the scene's camera path until the user moves it, then an orbit camera
//! (target, distance, azimuth, elevation) that mouse drags turn and pan and the wheel zooms.

use glam::Vec3;
use hairlod::core::Camera;

/// Radians of turn per pixel of drag.
const ORBIT_RADIANS_PER_PIXEL: f32 = 0.008;
/// The factor one wheel notch multiplies the distance by (zooming in).
const ZOOM_PER_NOTCH: f32 = 0.9;
/// Elevation limit [rad]: just short of straight above or below, where the up vector fails.
const MAX_ELEVATION: f32 = 1.5;

/// A camera on a sphere around a target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The point looked at [m].
    pub target: Vec3,
    /// Distance from the target [m], > 0.
    pub distance: f32,
    /// Angle about +Y [rad] (0: on +Z, in front of the face).
    pub azimuth: f32,
    /// Angle above the horizontal [rad].
    pub elevation: f32,
    /// Vertical field of view [rad].
    pub fov: f32,
}

impl Orbit {
    /// The orbit that puts a camera where `camera` is, looking at its target.
    pub fn from_camera(camera: &Camera) -> Orbit {
        let offset = camera.position - camera.target;
        let distance = offset.length().max(1e-3);
        let direction = offset / distance;
        Orbit {
            target: camera.target,
            distance,
            azimuth: direction.x.atan2(direction.z),
            elevation: direction.y.clamp(-1.0, 1.0).asin(),
            fov: camera.vertical_fov,
        }
    }

    /// The camera (near and far planes from the distance, +Y up).
    pub fn camera(&self) -> Camera {
        Camera::orbit(
            self.target,
            self.distance,
            self.azimuth,
            self.elevation,
            self.fov,
        )
    }

    /// Turns around the target by a drag of (`dx`, `dy`) pixels: right drags turn the scene
    /// right (the camera left), down drags look from higher up.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.azimuth -= dx * ORBIT_RADIANS_PER_PIXEL;
        self.elevation =
            (self.elevation + dy * ORBIT_RADIANS_PER_PIXEL).clamp(-MAX_ELEVATION, MAX_ELEVATION);
    }

    /// Moves the camera and the target in the image plane so that a point at the target's depth
    /// follows a drag of (`dx`, `dy`) pixels in an image `height` pixels high.
    pub fn pan(&mut self, dx: f32, dy: f32, height: u32) {
        let camera = self.camera();
        let forward = (camera.target - camera.position).normalize();
        let right = forward.cross(Vec3::Y).normalize();
        let up = right.cross(forward);
        let metres_per_pixel = 2.0 * self.distance * (0.5 * self.fov).tan() / height.max(1) as f32;
        self.target += (-dx * right + dy * up) * metres_per_pixel;
    }

    /// Moves towards the target by `notches` wheel notches (negative: away).
    pub fn zoom(&mut self, notches: f32) {
        self.distance = (self.distance * ZOOM_PER_NOTCH.powf(notches)).clamp(0.05, 500.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_orbit_camera_round_trips_through_its_camera() {
        let orbit = Orbit {
            target: Vec3::new(0.1, 0.2, -0.3),
            distance: 1.7,
            azimuth: 0.5,
            elevation: 0.15,
            fov: 0.6,
        };
        let back = Orbit::from_camera(&orbit.camera());
        assert!((back.target - orbit.target).length() < 1e-6);
        assert!((back.distance - orbit.distance).abs() < 1e-5);
        assert!((back.azimuth - orbit.azimuth).abs() < 1e-5);
        assert!((back.elevation - orbit.elevation).abs() < 1e-5);
    }

    #[test]
    fn orbiting_keeps_the_distance_and_panning_keeps_the_view_direction() {
        let mut orbit = Orbit::from_camera(&Camera::default());
        let before = orbit.camera();
        orbit.orbit(100.0, 40.0);
        let turned = orbit.camera();
        assert!(((turned.position - turned.target).length() - 1.0).abs() < 1e-5);
        assert!((turned.position - before.position).length() > 0.5);
        let direction = (turned.target - turned.position).normalize();
        orbit.pan(30.0, -20.0, 360);
        let panned = orbit.camera();
        assert!(((panned.target - panned.position).normalize() - direction).length() < 1e-5);
        assert!((panned.target - turned.target).length() > 1e-3);
    }

    #[test]
    fn the_wheel_zooms_geometrically_and_elevation_stays_below_the_pole() {
        let mut orbit = Orbit::from_camera(&Camera::default());
        orbit.zoom(2.0);
        assert!((orbit.distance - 0.81).abs() < 1e-5);
        orbit.zoom(-2.0);
        assert!((orbit.distance - 1.0).abs() < 1e-5);
        orbit.orbit(0.0, 1e6);
        assert!(orbit.elevation <= MAX_ELEVATION);
        orbit.camera().validate().unwrap();
    }
}
