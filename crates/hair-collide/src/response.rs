//! Collision response and friction (§5.4) as pure functions of one contact.
//!
//! The paper writes the response of a section touching the head as `F_i = 0.5·v_t·N_avg`,
//! `F_{i+1} = 0.5·v_b·N_avg`, with `N_avg` the mean normal of the touched triangles and `v_t`,
//! `v_b` the velocities of the section's top and bottom over the last step. A velocity is a
//! vector and `v·N` is not a force, so here:
//!
//! - the scalar is the node's **approach speed** `max(0, −(v − v_surface)·N_avg)` [m/s]: the
//!   inward normal component of its velocity relative to the moving surface. Only approach is
//!   answered (a node leaving the surface is left alone) and a tangential motion creates no push;
//! - it becomes a force through the node's momentum over the coming step, `m·speed/Δt` [N]: the
//!   force that, held for the step of `Δt` seconds, cancels that approach exactly (an inelastic
//!   contact). The paper's `0.5` splits each section's push between its two nodes; an interior
//!   node touching on both its sections gets the two halves, hence its whole approach cancelled.
//!
//! Friction (§5.4): the node's other forces `F` projected on the tangent plane of `N`, reversed
//! and scaled by the coefficient `μ ∈ [0, 1]` (the solver passes the external forces, gravity,
//! drag and wind; see `other_forces` for why the springs are left out):
//! `F_friction = −μ·(F − (F·N)·N)`. `μ = 1` cancels the tangential pull entirely.

use glam::Vec3;
use hair_core::RigidTransform;

use crate::geometry::Triangle;

/// Unit mean normal `N_avg` of the triangles `ids` of `triangles`; `None` when there are none or
/// their normals cancel (a sliver touched from both sides).
pub fn average_normal(triangles: &[Triangle], ids: &[u32]) -> Option<Vec3> {
    let sum: Vec3 = ids.iter().map(|&t| triangles[t as usize].normal).sum();
    let normal = sum.normalize_or_zero();
    (normal != Vec3::ZERO).then_some(normal)
}

/// Approach speed \[m/s\]: `max(0, −(velocity − surface_velocity)·normal)`, the inward normal
/// component of the velocity relative to the surface (both \[m/s\], `normal` unit, outward).
#[inline]
pub fn approach_speed(velocity: Vec3, surface_velocity: Vec3, normal: Vec3) -> f32 {
    (-(velocity - surface_velocity).dot(normal)).max(0.0)
}

/// The response force \[N\] one touching section puts on one of its two nodes:
/// `0.5 · mass · approach_speed / time_step · normal` (`mass` \[kg\], speed \[m/s\],
/// `time_step` \[s\] > 0).
#[inline]
pub fn response_force(mass: f32, approach_speed: f32, time_step: f32, normal: Vec3) -> Vec3 {
    normal * (0.5 * mass * approach_speed / time_step)
}

/// Friction \[N\]: `−μ·(F − (F·n)·n)` for the node's other forces `other_force` \[N\], unit contact
/// normal `normal` and coefficient `coefficient` (μ, in `[0, 1]`).
#[inline]
pub fn friction_force(other_force: Vec3, normal: Vec3, coefficient: f32) -> Vec3 {
    let tangential = other_force - normal * other_force.dot(normal);
    -tangential * coefficient
}

/// Velocity \[m/s\] of the material point of a rigid body that is at `point` \[m\] under pose
/// `after`, over a motion from pose `before` to `after` lasting `duration` \[s\]:
/// `(point − before(after⁻¹(point))) / duration`. Zero for a non-positive duration.
pub fn rigid_point_velocity(
    before: &RigidTransform,
    after: &RigidTransform,
    point: Vec3,
    duration: f32,
) -> Vec3 {
    if duration <= 0.0 {
        return Vec3::ZERO;
    }
    let earlier = before.transform_point(after.inverse().transform_point(point));
    (point - earlier) / duration
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn response_cancels_the_approach_over_one_step() {
        // Two halves of m·v/Δt make the impulse m·v over Δt: the node's normal velocity → 0.
        let (m, dt, n) = (2e-5, 1.0 / 60.0, Vec3::Y);
        let v = Vec3::new(0.3, -0.5, 0.0);
        let speed = approach_speed(v, Vec3::ZERO, n);
        assert_eq!(speed, 0.5);
        let f = response_force(m, speed, dt, n) * 2.0;
        let after = v + f * (dt / m);
        assert!(after.y.abs() < 1e-6 && (after.x - 0.3).abs() < 1e-7);
        // Leaving the surface: no push.
        assert_eq!(approach_speed(-v, Vec3::ZERO, n), 0.0);
        // Relative to a surface moving in as fast: no approach.
        assert_eq!(approach_speed(v, Vec3::new(0.0, -0.5, 0.0), n), 0.0);
    }

    #[test]
    fn friction_reverses_the_tangential_part() {
        let f = friction_force(Vec3::new(1.0, -2.0, 0.5), Vec3::Y, 0.4);
        assert!((f - Vec3::new(-0.4, 0.0, -0.2)).length() < 1e-7);
    }

    #[test]
    fn rigid_rotation_point_velocity_is_omega_cross_r() {
        let w = 6.0; // rad/s about y
        let dt = 1e-3;
        let before = RigidTransform::IDENTITY;
        let after = RigidTransform::new(Quat::from_rotation_y(w * dt), Vec3::ZERO);
        let p = Vec3::new(0.1, 0.0, 0.0);
        let v = rigid_point_velocity(&before, &after, p, dt);
        // ω × r = (0, 6, 0) × (0.1, 0, 0) = (0, 0, −0.6) m/s, to O(ω·dt) ≈ 0.3 %.
        assert!((v - Vec3::new(0.0, 0.0, -0.6)).length() < 0.6 * 0.01, "{v}");
    }

    #[test]
    fn mean_normal_of_opposite_faces_is_none() {
        let up = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Z * -1.0);
        let down = Triangle::new(Vec3::ZERO, Vec3::Z * -1.0, Vec3::X);
        assert_eq!(average_normal(&[up], &[0]), Some(Vec3::Y));
        assert_eq!(average_normal(&[up, down], &[0, 1]), None);
    }
}
