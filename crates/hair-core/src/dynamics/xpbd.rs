//! The XPBD integrator with small steps (Macklin, Müller, Chentanez 2016, "XPBD: position-based
//! simulation of compliant constrained dynamics"; Macklin et al. 2019, "Small steps in physics
//! simulation"): one substep is a prediction under the external forces, one Gauss-Seidel sweep of
//! compliant bending constraints root to tip, and an exact projection onto the segment lengths.
//!
//! **Bending as compliant constraints.** The spring of node `i` is the scalar constraint
//! `C_i = α_i`, the angle between the segment direction `d_i` and its rest direction `r_i` in the
//! parent frame parallel-transported along the current chain (as in
//! [`forces`](crate::dynamics::forces)), with compliance `1/k_i`: its energy is the springs'
//! `½·k_i·α_i²` exactly. Its gradient follows from `e = d − r` (`|e| = 2·sin(α/2)`): `∇α = Jᵀg`,
//! `g = ê/cos(α/2)`, where `J = ∂e/∂x` has the blocks `Q` (node `i`), `S − Q` (node `i − 1`) and
//! `−S` (node `i − 2`) of [`Joint`](crate::dynamics::Joint): `Q = (I − d·dᵀ)/l`,
//! `S = [r]ₓ[d_{i−1}]ₓ/l_{i−1}`. One XPBD iteration from `λ = 0` (small steps):
//!
//! `Δλ = −α/(W + α̃)`, `Δx_j = w_j·∇_j α·Δλ`, `W = Σ w_j·|∇_j α|²`, `α̃ = 1/(k·h²)`,
//! `w` the inverse masses (0 at an attached root).
//!
//! For `α̃ → ∞` (soft springs or short substeps) this is `h²·F/m`, the explicit spring step
//! (`F = −k·α·∇α`); for `α̃ → 0` (stiff springs or long substeps) it is one Newton step onto the
//! rest angle, which cannot overshoot: the step is stable at any stiffness. A scalar constraint
//! has no 3×3 system to solve: the bend's two degrees of freedom need no redundant third one.
//!
//! **Lengths** are constraints of zero compliance, solved exactly: the mass-weighted fast
//! projection (a tridiagonal Newton solve along the chain,
//! [`project_lengths`](crate::dynamics::constraints::project_lengths)), then follow-the-leader for
//! the last rounding. **Velocities** are `(x − x_n)/h`. **Air drag** is implicit in the
//! prediction, `v ← (v + h·(g + γ·w + F_col/m))/(1 + h·γ)`: stable at any drag.
//!
//! **Spring damping** `−β·k·Jᵀ·J·v` comes last, on the velocities: one Gauss-Seidel sweep root
//! to tip, each joint implicit in its own rate `ė = J·v`,
//! `Δv = −W·Jᵀ·μ`, `μ = h·β·k·ė/(1 + h·β·k·W̄)` with `W̄ ≥ ‖J·W·Jᵀ‖` (a Frobenius bound), so every
//! joint's update removes kinetic energy, at any `β·k·h`. It is zero at rest: damping inside the
//! position solve (XPBD's `γ̃`) would slow the one sweep's convergence and shift the static
//! equilibrium (by 64 % of a cantilever's deflection at `h·ω = 0.23`, measured).
//!
//! **The twist.** Moving segment `j` twists every later transported frame about its tangent (the
//! holonomy of parallel transport; [`add_spring_forces`](crate::dynamics::add_spring_forces)
//! includes it), so `∇α_i` reaches every node `0..=i`: `∂α_i/∂d_j = −τ_i·c_j` with
//! `τ_i = t_{i−1}·(d_i × r_i)/sin α_i`, `c_j = (κb_j + κb_{j+1})/2` (`κb_j/2` for `j = i − 1`),
//! `κb_j = 2·t_{j−1} × d_j/(1 + t_{j−1}·d_j)`. Left out, the constraints are not the gradient of
//! an energy: on curly chains (90° rest bends) the rest shape then drifts and a free swing gains
//! energy (measured: 1.6·m·g·L in 3 s). With it, a joint costs `O(i)`, a chain `O(n²)`.
//!
//! What it does not do: a single sweep per substep solves the coupled bending constraints only
//! approximately, so the chain is softer than its springs by `O((h·ω)²)` (`ω` a joint's spring
//! frequency; 12.5 % of a cantilever's deflection at `h·ω = 0.33`, 0.3 % at 0.08); it converges
//! as the substeps grow, at first order in the step (see `docs/dynamics.md`).

use glam::Vec3;

use crate::dynamics::constraints::{follow_the_leader, project_lengths};
use crate::dynamics::forces::{rest_direction, transport, walk_joints};
use crate::dynamics::integrators::{ChainArrays, ChainConstants, Substep, root_motion};
use crate::frame::Frame;

/// Newton iterations of the length projection (it converges quadratically and stops when within
/// [`LENGTH_TOLERANCE`](crate::dynamics::constraints::LENGTH_TOLERANCE)).
const LENGTH_ITERATIONS: usize = 3;

/// The position change of one bending constraint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendCorrection {
    /// Displacement [m] of the node at the end of the bent segment (node `i`).
    pub node: Vec3,
    /// Displacement [m] of the node at the bend (node `i − 1`).
    pub parent: Vec3,
    /// Displacement [m] of the node before it (node `i − 2`); zero for the root bend.
    pub grandparent: Vec3,
}

/// One bend as the XPBD constraint sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendConstraint {
    /// Unit direction `d_i` of the bent segment.
    pub direction: Vec3,
    /// Its current length [m].
    pub length: f32,
    /// Unit direction and length [m] of the parent segment; `None` at the root bend (the parent
    /// frame is the head-carried root frame).
    pub parent: Option<(Vec3, f32)>,
    /// The rest direction `r_i` in the transported parent frame.
    pub rest_direction: Vec3,
    /// Spring stiffness `k_i` [N·m/rad].
    pub stiffness: f32,
    /// Inverse masses [1/kg] of nodes `i`, `i − 1`, `i − 2` (0 for an attached root; the third is
    /// unused at the root bend).
    pub inverse_masses: [f32; 3],
}

/// The smallest `cos(α/2)` used in the gradient: a segment folded back onto its rest direction
/// (α → π) has an ill-defined bend plane, and the step there is capped rather than infinite.
const MIN_HALF_ANGLE_COSINE: f32 = 1e-3;

/// The bend angle α [rad] of one constraint, `g = ∂α/∂e` [1], and the local blocks of `∇α`
/// [1/m] on nodes `i`, `i − 1`, `i − 2` (module docs; without the twist terms). `None` at the
/// rest direction (α = 0, where the direction of `∇α` is undefined and nothing moves).
#[inline]
pub fn bend_gradient(bend: &BendConstraint) -> Option<(f32, Vec3, [Vec3; 3])> {
    let d = bend.direction;
    let r = bend.rest_direction;
    let residual = d - r;
    let distance = residual.length();
    if distance <= 1e-7 {
        return None;
    }
    let angle = d.cross(r).length().atan2(d.dot(r));
    // ∂α/∂e = ê/cos(α/2), cos(α/2) = √(1 − |e|²/4).
    let half_cosine = (1.0 - 0.25 * distance * distance)
        .max(0.0)
        .sqrt()
        .max(MIN_HALF_ANGLE_COSINE);
    let g = residual * (1.0 / (distance * half_cosine));
    // Q·g with Q = (I − d·dᵀ)/l.
    let node_gradient = (g - d * d.dot(g)) * (1.0 / bend.length);
    let (parent_gradient, grandparent_gradient) = match bend.parent {
        // Sᵀ·g = d_{i−1} × (r × g)/l_{i−1}.
        Some((parent_direction, parent_length)) => {
            let s_g = parent_direction.cross(r.cross(g)) * (1.0 / parent_length);
            (s_g - node_gradient, -s_g)
        }
        None => (-node_gradient, Vec3::ZERO),
    };
    Some((
        angle,
        g,
        [node_gradient, parent_gradient, grandparent_gradient],
    ))
}

/// The XPBD correction of one bending constraint over a substep of `h` [s] (module docs), from
/// its local gradient blocks alone (exact for the root bend, which no twist reaches). Returns
/// `None` when a value is not finite (a non-finite input).
#[inline]
pub fn bend_correction(bend: &BendConstraint, h: f32) -> Option<BendCorrection> {
    let Some((angle, _, gradient)) = bend_gradient(bend) else {
        return Some(BendCorrection {
            node: Vec3::ZERO,
            parent: Vec3::ZERO,
            grandparent: Vec3::ZERO,
        });
    };
    let w = bend.inverse_masses;
    let weight: f32 = (0..3).map(|j| w[j] * gradient[j].length_squared()).sum();
    let denominator = weight + 1.0 / (bend.stiffness * h * h);
    let multiplier = -angle / denominator;
    if !(multiplier.is_finite() && denominator > 0.0) {
        return None;
    }
    Some(BendCorrection {
        node: gradient[0] * (w[0] * multiplier),
        parent: gradient[1] * (w[1] * multiplier),
        grandparent: gradient[2] * (w[2] * multiplier),
    })
}

/// One XPBD substep of one chain (module docs). The step works on the displacements
/// `δ = x − x_n` (held in `arrays.forces`), not on the positions: a bending correction of a short
/// substep, `h²·F/m`, is far below the rounding of a position (`~1e-8 m` at 0.3 m from the origin)
/// and would be lost in it, but not in a displacement. Returns `false` when a value was not finite
/// (the state is then not usable; the caller treats it as a failure).
pub(crate) fn xpbd(chain: &ChainConstants, arrays: &mut ChainArrays, step: &Substep) -> bool {
    let h = step.h;
    let params = step.params;
    let n = arrays.positions.len();
    let first = step.first_free_node();
    let gamma = params.air_drag_rate;
    let drag_divisor = 1.0 / (1.0 + h * gamma);
    // 1. Prediction: implicit drag towards the wind, gravity and F_col held over the substep;
    //    δ = h·v_pred.
    for i in first..n {
        let acceleration =
            step.gravity + arrays.wind[i] * gamma + arrays.collision[i] * (1.0 / chain.masses[i]);
        let velocity = if gamma == 0.0 {
            arrays.velocities[i] + acceleration * h
        } else {
            (arrays.velocities[i] + acceleration * h) * drag_divisor
        };
        arrays.forces[i] = velocity * h;
    }
    let (root_end, root_velocity) = root_motion(chain, step);
    if step.attached() {
        arrays.forces[0] = root_end - arrays.positions[0];
    }
    // 2. Bending, one Gauss-Seidel sweep root to tip, on x = x_n + δ.
    let root_frame = step.head_end.transform_frame(&chain.root_frame);
    let inverse_mass = |i: usize| {
        if i < first {
            0.0
        } else {
            1.0 / chain.masses[i]
        }
    };
    let start = &*arrays.positions;
    let moved = &mut *arrays.forces;
    let position = |moved: &[Vec3], i: usize| start[i] + moved[i];
    let mut frame = root_frame;
    let mut parent: Option<(Vec3, f32)> = None;
    for i in 1..n {
        if let Some((parent_direction, _)) = parent {
            // The parent frame F_{i−1}, transported from F_{i−2} along the current d_{i−1}.
            frame = transport(&frame, parent_direction);
        }
        let segment = position(moved, i) - position(moved, i - 1);
        let length = segment.length().max(1e-12);
        let direction = if length > 1e-12 {
            segment / length
        } else {
            frame.tangent
        };
        let k = chain.stiffness[i];
        if k > 0.0 && (i >= 2 || step.attached()) {
            let rest = rest_direction(&frame, chain.rest_local[i]);
            let bend = BendConstraint {
                direction,
                length,
                parent,
                rest_direction: rest,
                stiffness: k,
                inverse_masses: [
                    inverse_mass(i),
                    inverse_mass(i - 1),
                    if i >= 2 { inverse_mass(i - 2) } else { 0.0 },
                ],
            };
            if let Some((angle, _, local)) = bend_gradient(&bend) {
                // ∇α on nodes 0..=i: the local blocks, plus the twist that moving segments
                // 1..i−1 carries into the transported frame F_{i−1} (module docs):
                // ∂α/∂d_j = −τ·c_j, τ = t_{i−1}·(d × r)/sin α, c_j = (κb_j + κb_{j+1})/2 for
                // j ≤ i − 2 and κb_{i−1}/2 for j = i − 1.
                let gradient = &mut *arrays.corrections;
                gradient[..=i].fill(Vec3::ZERO);
                gradient[i] = local[0];
                gradient[i - 1] = local[1];
                if i >= 2 {
                    gradient[i - 2] = local[2];
                }
                let sine = direction.cross(rest).length();
                let tau = frame.tangent.dot(direction.cross(rest)) / sine.max(1e-12);
                if i >= 2 && tau != 0.0 {
                    let root_tangent = root_frame.tangent;
                    let mut previous = root_tangent;
                    let mut here = segment_direction(start, moved, 1, previous);
                    for j in 1..i {
                        let next = segment_direction(start, moved, j + 1, here.0);
                        let half_binormal =
                            |a: Vec3, b: Vec3| a.cross(b) / (1.0 + a.dot(b)).max(1e-6);
                        let mut pull = half_binormal(previous, here.0);
                        if j + 1 < i {
                            pull += half_binormal(here.0, next.0);
                        }
                        let (d_j, l_j) = here;
                        let g_j = (pull - d_j * d_j.dot(pull)) * (-tau / l_j);
                        gradient[j] += g_j;
                        gradient[j - 1] -= g_j;
                        previous = d_j;
                        here = next;
                    }
                }
                let weight: f32 = (0..=i)
                    .map(|p| inverse_mass(p) * gradient[p].length_squared())
                    .sum();
                let denominator = weight + 1.0 / (k * h * h);
                let multiplier = -angle / denominator;
                if !multiplier.is_finite() {
                    return false;
                }
                for p in first..=i {
                    moved[p] += gradient[p] * (inverse_mass(p) * multiplier);
                }
            }
        }
        // The direction this joint leaves behind is the next joint's parent.
        let segment = position(moved, i) - position(moved, i - 1);
        let length = segment.length().max(1e-12);
        let direction = if length > 1e-12 {
            segment / length
        } else {
            direction
        };
        parent = Some((direction, length));
    }
    // 3. Lengths: exact mass-weighted projection, then follow-the-leader for the rounding, on the
    //    positions x_n + δ; x_n waits in the velocities meanwhile.
    for i in 0..n {
        let start = arrays.positions[i];
        arrays.velocities[i] = start;
        arrays.positions[i] = start + arrays.forces[i];
    }
    if step.attached() {
        arrays.positions[0] = root_end;
    }
    project_lengths(
        arrays.positions,
        inverse_mass,
        chain.rest_lengths,
        arrays.corrections,
        arrays.work,
        LENGTH_ITERATIONS,
    );
    follow_the_leader(arrays.positions, chain.rest_lengths);
    // 4. Velocities: v = (x − x_n)/h = (δ + c)/h, with the lengths' correction
    //    c = x − (x_n + δ) (the same rounded sum as above, so c is exactly 0 where they did
    //    nothing).
    let inverse_h = 1.0 / h;
    for i in first..n {
        let before = arrays.velocities[i] + arrays.forces[i];
        let correction = arrays.positions[i] - before;
        arrays.velocities[i] = (arrays.forces[i] + correction) * inverse_h;
    }
    if step.attached() {
        arrays.velocities[0] = root_velocity;
    }
    // 5. Spring damping on the velocities.
    if params.bending_damping > 0.0 {
        let root_frame = step.head_end.transform_frame(&chain.root_frame);
        damp_bending(
            arrays.positions,
            arrays.velocities,
            &root_frame,
            step.head_spin,
            chain,
            inverse_mass,
            h * params.bending_damping,
            step.attached(),
        );
    }
    arrays
        .velocities
        .iter()
        .chain(arrays.positions.iter())
        .all(|v| v.is_finite())
}

/// The spring damping sweep (module docs): `gain` is `h·β` [s²], `root_spin` the root frame's
/// angular velocity [rad/s] (it moves `r_1`); with free roots the root bend has no spring.
#[allow(clippy::too_many_arguments)]
fn damp_bending(
    positions: &[Vec3],
    velocities: &mut [Vec3],
    root_frame: &Frame,
    root_spin: Vec3,
    chain: &ChainConstants,
    inverse_mass: impl Fn(usize) -> f32,
    gain: f32,
    attached: bool,
) {
    walk_joints(positions, root_frame, chain.rest_local, |joint| {
        let i = joint.node;
        let k = chain.stiffness[i];
        if k == 0.0 || (i == 1 && !attached) {
            return;
        }
        let (w_node, w_parent) = (inverse_mass(i), inverse_mass(i - 1));
        let inverse_length_squared = 1.0 / (joint.length * joint.length);
        // W̄ = Σ w_j·‖J_j‖²_F ≥ ‖J·W·Jᵀ‖: ‖Q‖² = 2/l², ‖S‖² = (1 + (r·d_{i−1})²)/l²_{i−1} ≤ 2/l²_{i−1},
        // ‖S − Q‖² ≤ 2‖S‖² + 2‖Q‖².
        let (mut rate, bound) = match joint.parent {
            Some((_, parent_length)) => {
                let w_grandparent = inverse_mass(i - 2);
                let inverse_parent_squared = 1.0 / (parent_length * parent_length);
                (
                    joint.q(velocities[i] - velocities[i - 1])
                        + joint.s(velocities[i - 1] - velocities[i - 2]),
                    2.0 * w_node * inverse_length_squared
                        + 4.0 * w_parent * (inverse_length_squared + inverse_parent_squared)
                        + 2.0 * w_grandparent * inverse_parent_squared,
                )
            }
            None => (
                joint.q(velocities[i] - velocities[i - 1]),
                2.0 * (w_node + w_parent) * inverse_length_squared,
            ),
        };
        if joint.parent.is_none() {
            rate -= root_spin.cross(joint.rest_direction);
        }
        let c = gain * k;
        let mu = rate * (c / (1.0 + c * bound));
        let q_mu = joint.q(mu);
        velocities[i] -= q_mu * w_node;
        let s_mu = joint.s_transpose(mu);
        velocities[i - 1] -= (s_mu - q_mu) * w_parent;
        if i >= 2 {
            velocities[i - 2] += s_mu * inverse_mass(i - 2);
        }
    });
}

/// The unit direction and length [m] of segment `j` (nodes `j − 1` to `j`) at `start + moved`;
/// `fallback` for a segment of zero length.
#[inline]
fn segment_direction(start: &[Vec3], moved: &[Vec3], j: usize, fallback: Vec3) -> (Vec3, f32) {
    if j >= start.len() {
        return (fallback, 1.0);
    }
    let segment = (start[j] + moved[j]) - (start[j - 1] + moved[j - 1]);
    let length = segment.length();
    if length > 1e-12 {
        (segment / length, length)
    } else {
        (fallback, 1e-12)
    }
}
