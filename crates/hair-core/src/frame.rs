//! Orthonormal frames carried along a hair chain, and the polar/azimuth angles measured in them (§3.2).

use glam::{Mat3, Quat, Vec3};
use serde::{Deserialize, Serialize};

/// A right-handed orthonormal frame attached to a point of a hair.
///
/// `tangent` runs along the hair (root to tip); `normal` and `binormal` span the cross-section, with
/// `normal × binormal = tangent`. At a root, `normal` points away from the scalp and `binormal` runs
/// across the section (see [`Frame::from_tangent_and_normal`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// First cross-section axis (unit).
    pub normal: Vec3,
    /// Second cross-section axis (unit), `tangent × normal`.
    pub binormal: Vec3,
    /// Axis along the hair (unit).
    pub tangent: Vec3,
}

impl Default for Frame {
    /// The identity frame: normal +X, binormal +Y, tangent +Z.
    fn default() -> Self {
        Frame {
            normal: Vec3::X,
            binormal: Vec3::Y,
            tangent: Vec3::Z,
        }
    }
}

impl Frame {
    /// Builds a frame whose tangent is `tangent` and whose normal is the part of `normal_hint` orthogonal
    /// to it. Returns `None` when either vector is zero or non-finite, or when they are parallel.
    pub fn from_tangent_and_normal(tangent: Vec3, normal_hint: Vec3) -> Option<Frame> {
        let tangent = tangent.try_normalize()?;
        let normal = (normal_hint - tangent * normal_hint.dot(tangent)).try_normalize()?;
        Some(Frame {
            normal,
            binormal: tangent.cross(normal),
            tangent,
        })
    }

    /// The unit direction at polar angle `polar` [rad] from the tangent and azimuth `azimuth` [rad]
    /// around it, measured from the normal towards the binormal:
    /// `cos θ · t + sin θ · (cos φ · n + sin φ · b)`.
    pub fn direction(&self, polar: f32, azimuth: f32) -> Vec3 {
        let (sin_polar, cos_polar) = polar.sin_cos();
        let (sin_azimuth, cos_azimuth) = azimuth.sin_cos();
        self.tangent * cos_polar
            + (self.normal * cos_azimuth + self.binormal * sin_azimuth) * sin_polar
    }

    /// The polar and azimuth angles [rad] of a direction in this frame, the inverse of
    /// [`Frame::direction`]. The polar angle is in `0..=π`; the azimuth is in `-π..=π` and is 0 when
    /// the direction is (numerically) along the tangent, where it is undefined.
    pub fn angles_of(&self, direction: Vec3) -> (f32, f32) {
        let along = direction.dot(self.tangent);
        let x = direction.dot(self.normal);
        let y = direction.dot(self.binormal);
        let across = (x * x + y * y).sqrt();
        let polar = across.atan2(along);
        let azimuth = if across <= 1e-7 * direction.length().max(1e-30) {
            0.0
        } else {
            y.atan2(x)
        };
        (polar, azimuth)
    }

    /// The frame rotated by the smallest rotation that takes its tangent to `new_tangent` (unit):
    /// discrete parallel transport, so the frame does not twist about the hair.
    pub fn transported_to(&self, new_tangent: Vec3) -> Frame {
        let normal = arc_rotated(self.tangent, new_tangent, self.normal);
        Frame::orthonormalised(normal, new_tangent)
    }

    /// The frame halfway between this one and its transport to `next_tangent`: the frame at a node
    /// between two segments (its tangent bisects the bend).
    pub fn halfway_to(&self, next_tangent: Vec3) -> Frame {
        // Half the least rotation from a to b is the least rotation from a to their bisector.
        let Some(bisector) = (self.tangent + next_tangent).try_normalize() else {
            let rotation = Quat::from_rotation_arc(self.tangent, next_tangent);
            let half = Quat::IDENTITY.slerp(rotation, 0.5);
            return Frame::orthonormalised(half * self.normal, half * self.tangent);
        };
        let normal = arc_rotated(self.tangent, bisector, self.normal);
        Frame::orthonormalised(normal, bisector)
    }

    /// The frame of `tangent` with `normal` made orthonormal to it, so that errors do not
    /// accumulate along long chains.
    fn orthonormalised(normal: Vec3, tangent: Vec3) -> Frame {
        let tangent = tangent.normalize();
        let normal = (normal - tangent * normal.dot(tangent)).normalize();
        Frame {
            normal,
            binormal: tangent.cross(normal),
            tangent,
        }
    }

    /// The frame rotated by `rotation` (for example a head's rigid rotation).
    pub fn rotate(&self, rotation: Quat) -> Frame {
        Frame {
            normal: rotation * self.normal,
            binormal: rotation * self.binormal,
            tangent: rotation * self.tangent,
        }
    }

    /// Maps local coordinates `(along normal, along binormal, along tangent)` to a world vector.
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        self.normal * local.x + self.binormal * local.y + self.tangent * local.z
    }

    /// The frame as a rotation matrix with columns normal, binormal, tangent.
    pub fn to_mat3(&self) -> Mat3 {
        Mat3::from_cols(self.normal, self.binormal, self.tangent)
    }
}

/// `v` turned by the least rotation that takes the unit vector `a` to the unit vector `b`:
/// `R v = v + k × v + k × (k × v) / (1 + a·b)` with `k = a × b` (Rodrigues' formula with
/// `sin θ · axis = k` and `1 − cos θ = |k|² / (1 + cos θ)`). Where `a` and `b` are nearly opposite
/// (within about 8°) the rotation's axis is ill-conditioned and glam's `from_rotation_arc` picks it.
fn arc_rotated(a: Vec3, b: Vec3, v: Vec3) -> Vec3 {
    let c = a.dot(b);
    if c < -0.99 {
        return Quat::from_rotation_arc(a, b) * v;
    }
    let k = a.cross(b);
    let kv = k.cross(v);
    v + kv + k.cross(kv) / (1.0 + c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tilted_frame() -> Frame {
        Frame::from_tangent_and_normal(Vec3::new(0.2, -1.0, 0.3), Vec3::new(0.0, 0.0, 1.0)).unwrap()
    }

    #[test]
    fn frame_is_right_handed_and_orthonormal() {
        let frame = tilted_frame();
        assert!((frame.normal.cross(frame.binormal) - frame.tangent).length() < 1e-6);
        assert!((frame.to_mat3().determinant() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn angles_round_trip_through_direction() {
        let frame = tilted_frame();
        for &(polar, azimuth) in &[(0.3f32, 1.0f32), (1.2, -2.5), (0.01, 3.0), (1.5, -1.5)] {
            let direction = frame.direction(polar, azimuth);
            assert!((direction.length() - 1.0).abs() < 1e-6);
            let (p, a) = frame.angles_of(direction);
            assert!((p - polar).abs() < 1e-5, "{p} vs {polar}");
            assert!((a - azimuth).abs() < 1e-4, "{a} vs {azimuth}");
        }
        // Along the tangent the azimuth is undefined and reported as 0.
        let (polar, azimuth) = frame.angles_of(frame.tangent);
        assert!(polar.abs() < 1e-6);
        assert_eq!(azimuth, 0.0);
    }

    /// The transport and the halfway frame are the rotations about `a × b` by the bend angle
    /// `atan2(|a × b|, a · b)` and by half of it (a reference built independently of the
    /// formula, from an axis and an angle), within f32 rounding of a few operations, for bends
    /// from 0.006° to 179°. (glam's `from_rotation_arc` returns the identity below about 7e-4 rad,
    /// so it is no reference for the small bends.)
    #[test]
    fn transport_matches_the_rotation_about_the_bend_axis() {
        let frame = tilted_frame();
        let mut random = crate::random::SplitMix64::new(7);
        for case in 0..2000 {
            let polar = match case % 4 {
                0 => 1.0e-4,
                1 => 3.12,
                _ => random.next_f32() * 3.12,
            };
            let azimuth = random.next_f32() * std::f32::consts::TAU;
            let next = frame.direction(polar, azimuth);
            let k = frame.tangent.cross(next);
            let angle = k.length().atan2(frame.tangent.dot(next));
            let axis = k.normalize();
            let rotation = Quat::from_axis_angle(axis, angle);
            let moved = frame.transported_to(next);
            assert!(
                (moved.normal - rotation * frame.normal).length() < 1e-5,
                "{case}"
            );
            assert!((moved.tangent - next).length() < 1e-6, "{case}");
            let half = Quat::from_axis_angle(axis, 0.5 * angle);
            let middle = frame.halfway_to(next);
            assert!(
                (middle.normal - half * frame.normal).length() < 1e-5,
                "{case}"
            );
            assert!(
                (middle.tangent - half * frame.tangent).length() < 1e-5,
                "{case}"
            );
            assert!((middle.normal.cross(middle.binormal) - middle.tangent).length() < 1e-6);
        }
    }

    #[test]
    fn transport_keeps_the_bend_axis_fixed() {
        // Bending towards the normal rotates about the binormal, which must stay where it was.
        let frame = tilted_frame();
        let next = frame.direction(0.4, 0.0);
        let moved = frame.transported_to(next);
        assert!((moved.binormal - frame.binormal).length() < 1e-6);
        assert!((moved.tangent - next).length() < 1e-6);
        let half = frame.halfway_to(next);
        assert!((half.tangent - frame.direction(0.2, 0.0)).length() < 1e-5);
    }
}
