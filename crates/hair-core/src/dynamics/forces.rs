//! Forces on skeleton nodes (§4.1): angular springs and their damping as the gradient of a bending
//! energy, gravity, air drag with wind, and the collision slot.
//!
//! **Angular springs.** The spring of node `i` (at the bend between segments `i − 1` and `i`) pulls
//! the direction `d_i` of segment `i` towards its rest direction `r_i = F_{i−1}·(sin θ0 cos φ0,
//! sin θ0 sin φ0, cos θ0)` in the frame `F_{i−1}` of the parent segment, parallel-transported along
//! the *current* chain exactly as [`build_chain`](crate::skeleton::build_chain) does at rest. Its
//! energy is `E_i = ½·k_i·α_i²` with `α_i = ∠(d_i, r_i)`: the paper's `F_θ = −k(θ − θ0)`,
//! `F_φ = −k(φ − φ0)` for deviations in θ and, with the weight `sin²θ0` the sphere's metric gives
//! it, in φ, written without φ so that it stays smooth where θ → 0 and φ is undefined.
//!
//! The node forces are `−∂E/∂x` through `d_i` (nodes `i − 1`, `i`) and through the parent frame
//! (nodes `i − 2`, `i − 1`): a change `δd_{i−1}` turns `F_{i−1}` by the smallest rotation
//! `ω = d_{i−1} × δd_{i−1}`, so `δr_i = ω × r_i`. The twist that a change of earlier segments
//! carries into `F_{i−1}` is of second order in the bend angles and is left out. So the spring is a
//! pair of opposite torques `±k·α·(d × r)/|d × r|` on its two segments (angular momentum is kept),
//! and a rest shape is an equilibrium exactly (every `α_i` is 0 there).
//!
//! With the residual `e_i = d_i − r_i`, its Jacobian `J_i` (blocks `Q = (I − d dᵀ)/l_i` for node
//! `i`, `S − Q` for node `i − 1`, `−S` for node `i − 2`, `S = [r]ₓ[d_{i−1}]ₓ / l_{i−1}`) gives the
//! force `−k·(α/sin α)·J_iᵀ e_i` and the Gauss-Newton stiffness `H_i = k·J_iᵀJ_i` the implicit
//! integrator uses; the damping force is `−β·H·v`.

use glam::{Vec3, Vec4};

use crate::frame::Frame;

/// Standard gravity [m/s²], along −Y.
pub const STANDARD_GRAVITY: Vec3 = Vec3::new(0.0, -9.81, 0.0);

/// The frame carried by the smallest rotation from its tangent to `new_tangent` (unit): discrete
/// parallel transport, the same map as [`Frame::transported_to`] written with two reflections
/// (`v ↦ v − ((a+b)·v)/(1+a·b)·(a+b) + 2(a·v)·b`), which is cheaper than a quaternion.
#[inline]
pub fn transport(frame: &Frame, new_tangent: Vec3) -> Frame {
    let a = frame.tangent;
    let b = new_tangent;
    let one_plus_cos = 1.0 + a.dot(b);
    if one_plus_cos < 1e-4 {
        // Nearly reversed: the rotation axis is ill-defined, let the quaternion code choose one.
        return frame.transported_to(b);
    }
    let sum = a + b;
    let normal = frame.normal - sum * (sum.dot(frame.normal) / one_plus_cos)
        + b * (2.0 * a.dot(frame.normal));
    let normal = (normal - b * b.dot(normal)).normalize();
    Frame {
        normal,
        binormal: b.cross(normal),
        tangent: b,
    }
}

/// The direction with local coordinates `local` = (normal, binormal, tangent) in `frame`.
#[inline]
pub fn rest_direction(frame: &Frame, local: Vec3) -> Vec3 {
    frame.normal * local.x + frame.binormal * local.y + frame.tangent * local.z
}

/// Local coordinates (normal, binormal, tangent) of the direction at polar angle θ0 and azimuth φ0
/// [rad]: `(sin θ0 cos φ0, sin θ0 sin φ0, cos θ0)`.
pub fn rest_local_direction(polar: f32, azimuth: f32) -> Vec3 {
    let (sin_polar, cos_polar) = polar.sin_cos();
    let (sin_azimuth, cos_azimuth) = azimuth.sin_cos();
    Vec3::new(sin_polar * cos_azimuth, sin_polar * sin_azimuth, cos_polar)
}

/// The bend angle `α = ∠(d, r)` [rad] of two unit vectors and the factor `α / sin α` (→ 1 as
/// α → 0) that turns the vector spring `d − r` into the angular spring `k·α`.
#[inline]
pub fn bend_angle_and_factor(direction: Vec3, rest: Vec3) -> (f32, f32) {
    let sin = direction.cross(rest).length();
    let cos = direction.dot(rest);
    let angle = sin.atan2(cos);
    let factor = if sin > 1e-3 {
        angle / sin
    } else {
        // α/sin α = 1 + α²/6 + O(α⁴)
        1.0 + angle * angle * (1.0 / 6.0)
    };
    (angle, factor)
}

/// One bend of a chain, as seen by the spring of node `node`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Joint {
    /// The node at the end of the segment (index within the chain, ≥ 1).
    pub node: usize,
    /// Unit direction `d_i` of segment `node`.
    pub direction: Vec3,
    /// Current length `l_i` of segment `node` [m].
    pub length: f32,
    /// Unit direction and length [m] of the parent segment (`None` for node 1, whose parent frame
    /// is the root frame).
    pub parent: Option<(Vec3, f32)>,
    /// The rest direction `r_i` in the transported parent frame.
    pub rest_direction: Vec3,
}

impl Joint {
    /// `Q·u = (u − d(d·u))/l`: the velocity of the direction `d` for node velocities `u` at its end.
    #[inline]
    pub fn q(&self, u: Vec3) -> Vec3 {
        (u - self.direction * self.direction.dot(u)) / self.length
    }

    /// `S·u = r × (d_{i−1} × u)/l_{i−1}` (zero without parent).
    #[inline]
    pub fn s(&self, u: Vec3) -> Vec3 {
        match self.parent {
            Some((d, l)) => self.rest_direction.cross(d.cross(u)) / l,
            None => Vec3::ZERO,
        }
    }

    /// `Sᵀ·g = d_{i−1} × (r × g)/l_{i−1}`.
    #[inline]
    pub fn s_transpose(&self, g: Vec3) -> Vec3 {
        match self.parent {
            Some((d, l)) => d.cross(self.rest_direction.cross(g)) / l,
            None => Vec3::ZERO,
        }
    }
}

/// Walks a chain from the root, calling `visit` for every joint (nodes `1..n`) with the segment
/// directions, lengths and rest directions in the parent frames transported along the current
/// positions. `rest_local` holds per node the local rest direction ([`rest_local_direction`]).
#[inline]
pub fn walk_joints(
    positions: &[Vec3],
    root_frame: &Frame,
    rest_local: &[Vec3],
    mut visit: impl FnMut(&Joint),
) {
    let mut frame = *root_frame;
    let mut parent: Option<(Vec3, f32)> = None;
    for node in 1..positions.len() {
        let segment = positions[node] - positions[node - 1];
        let length = segment.length();
        let direction = if length > 1e-12 {
            segment / length
        } else {
            frame.tangent
        };
        let rest = rest_direction(&frame, rest_local[node]);
        visit(&Joint {
            node,
            direction,
            length: length.max(1e-12),
            parent,
            rest_direction: rest,
        });
        frame = transport(&frame, direction);
        parent = Some((direction, length.max(1e-12)));
    }
}

/// Adds the angular spring and spring damping forces [N] of one chain to `forces`: the exact
/// gradient of `E = Σ ½ k_i α_i²`, including the twist that a change of each segment carries into
/// every later transported frame (the holonomy of parallel transport, as in discrete elastic rods:
/// moving segments `j − 1` and `j` twists frame `j` and all frames after it by
/// `δm_j = (κb_j/2)·(δd_{j−1} + δd_j)`, `κb_j = 2 t_{j−1} × d_j / (1 + t_{j−1}·d_j)`).
///
/// `stiffness[i]` is `k_i` [N·m/rad] (0 turns a spring off), `damping` is β [s] (the damping
/// force `−β·k·J_iᵀJ_i·v` leaves the twist terms out: it only has to dissipate),
/// `root_angular_velocity` [rad/s] the root frame's spin (it moves `r_1`). With `skip_root_joint`
/// the root bend has no spring (free roots). `work` is scratch with one entry per node. Returns the
/// bending energy `Σ ½ k α²` [J].
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn add_spring_forces(
    positions: &[Vec3],
    velocities: &[Vec3],
    root_frame: &Frame,
    root_angular_velocity: Vec3,
    rest_local: &[Vec3],
    stiffness: &[f32],
    damping: f32,
    skip_root_joint: bool,
    work: &mut [Vec4],
    forces: &mut [Vec3],
) -> f32 {
    let mut energy = 0.0;
    let root_tangent = root_frame.tangent;
    walk_joints(positions, root_frame, rest_local, |joint| {
        let i = joint.node;
        let k = stiffness[i];
        // Half the curvature binormal of the transport into segment i, for the twist pass.
        let parent_tangent = joint.parent.map_or(root_tangent, |(d, _)| d);
        let half_binormal = parent_tangent.cross(joint.direction)
            / (1.0 + parent_tangent.dot(joint.direction)).max(1e-6);
        if k == 0.0 || (i == 1 && skip_root_joint) {
            work[i] = half_binormal.extend(0.0);
            return;
        }
        let (angle, factor) = bend_angle_and_factor(joint.direction, joint.rest_direction);
        energy += 0.5 * k * angle * angle;
        // Twist torque of this spring on the parent frame: t_{i−1}·(k·(α/sin α)·(d × r)).
        let twist_torque =
            parent_tangent.dot(joint.direction.cross(joint.rest_direction)) * (k * factor);
        work[i] = half_binormal.extend(twist_torque);
        let residual = joint.direction - joint.rest_direction;
        // Rate of the residual: J·v (the root frame's spin turns r_1).
        let mut rate = joint.q(velocities[i] - velocities[i - 1]);
        if i >= 2 {
            rate += joint.s(velocities[i - 1] - velocities[i - 2]);
        } else {
            rate -= root_angular_velocity.cross(joint.rest_direction);
        }
        let g = (residual * factor + rate * damping) * k;
        let qg = joint.q(g);
        forces[i] -= qg;
        if i >= 2 {
            let stg = joint.s_transpose(g);
            forces[i - 1] += qg - stg;
            forces[i - 2] += stg;
        } else {
            forces[i - 1] += qg;
        }
    });
    // Twist pass, tip to root: frame j is twisted by τ_j = −Σ_{m ≤ j} δm_m, which changes E_i
    // (i > j) by τ_{i−1}·W_i; with A_j = Σ_{i > j} W_i, −∂E/∂d_j = A_j·κb_j/2 + A_{j+1}·κb_{j+1}/2.
    let n = positions.len();
    let mut suffix = 0.0f32; // A_{j+1} while at j
    let mut next_half_binormal = Vec3::ZERO;
    for j in (1..n).rev() {
        let a_next = suffix;
        let a_here = suffix + if j + 1 < n { work[j + 1].w } else { 0.0 };
        let half_binormal = work[j].truncate();
        let pull = half_binormal * a_here + next_half_binormal * a_next;
        let segment = positions[j] - positions[j - 1];
        let length = segment.length().max(1e-12);
        let direction = segment / length;
        let force = (pull - direction * direction.dot(pull)) / length;
        forces[j] += force;
        forces[j - 1] -= force;
        suffix = a_here;
        next_half_binormal = half_binormal;
    }
    energy
}

/// Adds gravity, air drag towards the wind and the collision forces [N]:
/// `F_i += m_i·g + m_i·γ·(w_i − v_i) + F_col,i`, where `wind_velocities` holds `w_i` [m/s].
#[inline]
pub fn add_external_forces(
    masses: &[f32],
    velocities: &[Vec3],
    wind_velocities: impl Fn(usize) -> Vec3,
    collision_forces: &[Vec3],
    gravity: Vec3,
    air_drag_rate: f32,
    forces: &mut [Vec3],
) {
    for i in 0..forces.len() {
        let m = masses[i];
        forces[i] += gravity * m
            + (wind_velocities(i) - velocities[i]) * (m * air_drag_rate)
            + collision_forces[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::tests::coiled_positions;

    fn chain(polar: f32) -> (Frame, Vec<Vec3>, Vec<Vec3>) {
        let frame = Frame::from_tangent_and_normal(Vec3::new(0.3, -1.0, 0.1), Vec3::Z).unwrap();
        let lengths = [0.0, 0.01, 0.012, 0.009, 0.01, 0.011, 0.01];
        let positions = coiled_positions(&frame, &lengths, polar);
        // The rest shape is the coiled shape itself (the directions `build_chain` was given).
        let local = (0..lengths.len())
            .map(|i| {
                let polar = if i == 0 { 0.0 } else { polar };
                rest_local_direction(polar, 0.9 * i as f32)
            })
            .collect();
        (frame, positions, local)
    }

    #[test]
    fn fast_transport_matches_the_quaternion_transport() {
        let frame = Frame::from_tangent_and_normal(Vec3::new(0.2, 1.0, -0.4), Vec3::X).unwrap();
        for target in [
            Vec3::new(1.0, 0.2, 0.3),
            Vec3::new(-0.3, 0.9, -0.5),
            Vec3::new(0.1, -0.2, 1.0),
        ] {
            let target = target.normalize();
            let fast = transport(&frame, target);
            let slow = frame.transported_to(target);
            assert!((fast.normal - slow.normal).length() < 1e-5);
            assert!((fast.binormal - slow.binormal).length() < 1e-5);
        }
    }

    fn springs(
        positions: &[Vec3],
        frame: &Frame,
        local: &[Vec3],
        stiffness: &[f32],
        forces: &mut [Vec3],
    ) -> f32 {
        let n = positions.len();
        let zero = vec![Vec3::ZERO; n];
        let mut work = vec![Vec4::ZERO; n];
        add_spring_forces(
            positions,
            &zero,
            frame,
            Vec3::ZERO,
            local,
            stiffness,
            0.0,
            false,
            &mut work,
            forces,
        )
    }

    #[test]
    fn rest_shape_is_an_equilibrium() {
        for polar in [0.0, 0.4, 1.2] {
            let (frame, positions, local) = chain(polar);
            let n = positions.len();
            let stiffness = vec![2e-5; n];
            let mut forces = vec![Vec3::ZERO; n];
            let energy = springs(&positions, &frame, &local, &stiffness, &mut forces);
            // At rest: α_i = 0 ⇒ E = 0 and F = −∇E = 0 (to rounding: k·1e-6 / l).
            assert!(energy < 1e-14, "{energy}");
            assert!(
                forces.iter().all(|f| f.length() < 2e-5 * 1e-4 / 0.01),
                "{forces:?}"
            );
        }
    }

    #[test]
    fn spring_forces_are_the_energy_gradient() {
        // F = −∂E/∂x at every node, twist terms included, against central differences
        // (h = 1e-4 m: truncation O(h²) and f32 rounding O(ε·E/h) both below 1% of the largest |F|).
        for polar in [0.0, 0.5, 0.9] {
            let (frame, mut positions, local) = chain(polar);
            let n = positions.len();
            for (i, p) in positions.iter_mut().enumerate().skip(1) {
                *p += Vec3::new(0.002, -0.001 * i as f32, 0.0015 * (i % 3) as f32);
            }
            let stiffness = vec![2e-5; n];
            let mut forces = vec![Vec3::ZERO; n];
            springs(&positions, &frame, &local, &stiffness, &mut forces);
            let scale = forces.iter().map(|f| f.length()).fold(0.0f32, f32::max);
            let h = 1e-4;
            for node in 0..n {
                for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
                    let mut plus = positions.clone();
                    let mut minus = positions.clone();
                    plus[node] += axis * h;
                    minus[node] -= axis * h;
                    let mut scratch = vec![Vec3::ZERO; n];
                    let gradient = (springs(&plus, &frame, &local, &stiffness, &mut scratch)
                        - springs(&minus, &frame, &local, &stiffness, &mut scratch))
                        / (2.0 * h);
                    let force = forces[node].dot(axis);
                    assert!(
                        (force + gradient).abs() < 1e-2 * scale,
                        "θ0 {polar} node {node}: force {force} vs −∂E/∂x {}",
                        -gradient
                    );
                }
            }
            // Internal forces sum to zero (the root bend's reaction on the head acts at the root).
            let total: Vec3 = forces.iter().sum();
            assert!(total.length() < 1e-4 * scale, "{total}");
        }
    }
}
