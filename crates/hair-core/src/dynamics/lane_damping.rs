//! The spring damping of the XPBD step ([`xpbd`](crate::dynamics::xpbd)) for
//! [`LANES`](crate::dynamics::lanes::LANES) chains at once: `−β·k·Jᵀ·J·v` on the velocities, one
//! Gauss-Seidel sweep root to tip, each joint implicit in its own rate `ė = J·v`:
//! `Δv = −W·Jᵀ·μ`, `μ = h·β·k·ė/(1 + h·β·k·W̄)` with `W̄ ≥ ‖J·W·Jᵀ‖` (a Frobenius bound), so every
//! joint's update removes kinetic energy, at any `β·k·h`, and none at rest.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::lane_model::LaneNode;
use crate::dynamics::lane_springs::LaneFrame;
use crate::dynamics::lanes::{LaneVec3, Lanes};

/// The spring damping sweep of the XPBD step for every lane: root to tip, each joint implicit in
/// its own rate, `μ = h·β·k·ė/(1 + h·β·k·W̄)`. `gain` is `h·β` [s²], `root_spin` the root
/// frame's angular velocity [rad/s] (it moves `r_1`); node 0 weighs `root_weight` [1/kg] (0
/// for an attached root); with free roots (`first` 0) the root bend has no spring.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn damp_bending<const N: usize>(
    positions: &[LaneVec3; N],
    velocities: &mut [LaneVec3; N],
    constants: &[LaneNode],
    first: usize,
    root_weight: Lanes,
    n: usize,
    root_frame: LaneFrame,
    root_spin: LaneVec3,
    gain: Lanes,
) {
    let one = Lanes::splat(1.0);
    let two = Lanes::splat(2.0);
    let four = Lanes::splat(4.0);
    let zero = Lanes::splat(0.0);
    let spin = root_spin;
    let weight = |i: usize| {
        if i == 0 {
            root_weight
        } else {
            constants[i].inverse_mass
        }
    };
    let mut frame = root_frame;
    let mut parent_direction = LaneVec3::default();
    let mut parent_inverse_length = zero;
    for i in 1..n {
        let c = &constants[i];
        let segment = frame.segment(positions[i - 1], positions[i], c.rest_local);
        let (d, r, il) = (segment.direction, segment.rest, segment.inverse_length);
        let q = |u: LaneVec3| (u - d.scale(d.dot(u))).scale(il);
        let (w_node, w_parent) = (c.inverse_mass, weight(i - 1));
        let il2 = il * il;
        let (rate, bound) = if i >= 2 {
            let (dp, ilp) = (parent_direction, parent_inverse_length);
            let ilp2 = ilp * ilp;
            let w_grandparent = weight(i - 2);
            let s = r
                .cross(dp.cross(velocities[i - 1] - velocities[i - 2]))
                .scale(ilp);
            (
                q(velocities[i] - velocities[i - 1]) + s,
                two * w_node * il2 + four * w_parent * (il2 + ilp2) + two * w_grandparent * ilp2,
            )
        } else {
            (
                q(velocities[i] - velocities[i - 1]) - spin.cross(r),
                two * (w_node + w_parent) * il2,
            )
        };
        let k = if i == 1 && first == 0 {
            zero
        } else {
            c.stiffness
        };
        let gk = gain * k;
        let mu = rate.scale(gk / (one + gk * bound));
        let q_mu = q(mu);
        velocities[i] -= q_mu.scale(w_node);
        if i >= 2 {
            let s_mu = parent_direction
                .cross(r.cross(mu))
                .scale(parent_inverse_length);
            velocities[i - 1] -= (s_mu - q_mu).scale(w_parent);
            velocities[i - 2] += s_mu.scale(weight(i - 2));
        } else {
            velocities[i - 1] += q_mu.scale(w_parent);
        }
        // Transport the frame to d (as `lane_springs::joint`).
        frame = frame.transported(&segment);
        parent_direction = d;
        parent_inverse_length = il;
    }
}
