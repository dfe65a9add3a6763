//! The XPBD integrator with small steps (Macklin, Müller, Chentanez 2016, "XPBD: position-based
//! simulation of compliant constrained dynamics"; Macklin et al. 2019, "Small steps in physics
//! simulation"), with each chain's bending constraints solved together: one substep is a
//! prediction under the external forces, one Gauss-Newton step of all the chain's compliant
//! bending constraints (a block-pentadiagonal solve along the chain) with a line search, an exact
//! projection onto the segment lengths, and a dissipative damping sweep on the velocities.
//!
//! **Bending as compliant constraints.** The spring of node `i` is the constraint `α_i = 0` with
//! compliance `1/k_i`, `α_i` the angle between the segment direction `d_i` and its rest direction
//! `r_i` in the parent frame parallel-transported along the current chain (as in
//! [`forces`](crate::dynamics::forces)): its energy is the springs' `½·k_i·α_i²`. One XPBD
//! iteration of all of them from `λ = 0` is, by the Woodbury identity, the position step
//!
//! `(M/h² + H)·Δx = F(x̃)`,
//!
//! from the prediction `x̃`, with `F = −∇E` the springs' exact forces (twist included, as in
//! [`add_spring_forces`](crate::dynamics::add_spring_forces)) and `H = Σ k_i·J_iᵀJ_i` the
//! Gauss-Newton stiffness of the local blocks `J_i = ∂(d_i − r_i)/∂x` on nodes `i`, `i − 1`,
//! `i − 2` (block-pentadiagonal: the linear-implicit integrator's solver). It is one Newton step
//! of implicit Euler's objective `Φ(x) = ½·|x − x̃|²_M/h² + E(x)`: for soft springs or short
//! substeps it is `h²·F/m`, the explicit spring step; for stiff springs or long ones a projection
//! onto the rest shape. `M/h² + H` is symmetric positive definite, so `Δx` is a descent direction
//! of `Φ`, and a **line search** takes it whole where `Φ(x̃ + Δx) ≤ Φ(x̃)`, else halves it (up to
//! [`LINE_SEARCH_HALVINGS`] times, then drops it): the step cannot pump energy into the springs,
//! at any stiffness and step.
//!
//! **The twisted step.** Where the band's whole step raises `Φ`, the line search next tries,
//! whole, the step of the system with the twist's long-range coupling in `H`
//! ([`twisted_cg`](crate::dynamics::twisted_cg): a few conjugate-gradient iterations
//! preconditioned by the band's factorisation), and halves that one. On fine curly chains the
//! band misses the stiffness the twist adds and every whole band step is rejected (32 nodes at
//! 1/480 s: 7.7 Newton iterations a substep; with the twisted step 1.0). Where the band's whole
//! step is taken (the presets' 13-node chains at the recommended substeps) nothing changes.
//!
//! Why not the usual XPBD: solving the bends one after the other (one Gauss-Seidel sweep per
//! substep) leaves the chain softer than its springs by `O((h·ω)²)` (`ω` a joint's spring
//! frequency; measured, 12.5 % of a cantilever's deflection at `h·ω = 0.33`, and on the stability
//! map 3–27× the reference's motion at 10× and 100× stiffness); solving them together in
//! constraint space with the local blocks alone, the twist that moving a segment carries into
//! every later transported frame (`O(n)` long-range coupling) is missing from the system, and on
//! curly chains the step stops being a descent direction and blows up at `h·ω ≳ 1`.
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
//! position solve (XPBD's `γ̃`) shifts the static equilibrium (measured: by 64 % of a
//! cantilever's deflection at `h·ω = 0.23` with a Gauss-Seidel sweep).
//!
//! **Adaptive substeps.** Where the first Newton step of a substep moves a node by more than
//! [`TOO_LONG_MOVE`] segment lengths, the substep is too long for that chain's motion (a stiff
//! curly chain turned far in one substep): the chain's whole step is redone with twice the
//! substeps, up to [`MAX_ADAPTIVE_HALVINGS`] times and as long as each halving shortens that move
//! (a chain folded on itself moves far at any substep; it is then stepped without adapting),
//! whatever the failure policy ([`StepReport`](crate::dynamics::StepReport) counts the chains).
//! At the recommended substeps it does not happen on the paper-curly groom in a 3 rad/s shake and
//! 3 m/s wind; at one substep per 1/15 s it is what keeps the stiffest chains of the stability
//! map from moving several times their reference.
//!
//! The step works on the displacements `δ = x − x_n`, not on the positions: a bending correction
//! of a short substep, `h²·F/m`, is far below the rounding of a position (`~1e-8 m` at 0.3 m from
//! the origin) and would be lost in it, but not in a displacement.

use glam::{Mat3, Vec3};

use crate::dynamics::banded::solve_block_pentadiagonal;
use crate::dynamics::constraints::{follow_the_leader, project_lengths};
use crate::dynamics::forces::{add_spring_forces, bend_angle_and_factor, walk_joints};
use crate::dynamics::integrators::{
    ChainArrays, ChainConstants, Substep, add_length_springs, add_spring_blocks, length_stiffness,
    root_motion,
};
use crate::dynamics::twisted_cg::with_scratch;
use crate::frame::Frame;

/// Newton iterations of the length projection (it converges quadratically and stops when within
/// [`LENGTH_TOLERANCE`](crate::dynamics::constraints::LENGTH_TOLERANCE)).
pub(crate) const LENGTH_ITERATIONS: usize = 3;

/// Newton steps per substep at most: a second one only where the first moved a node by more than
/// [`NEWTON_TOLERANCE`] of its segment (large rotations in one substep, where the objective is far
/// from quadratic).
pub(crate) const NEWTON_ITERATIONS: usize = 8;

/// A first Newton step that moves no node by more than this fraction of its segment (a turn of
/// 1e-3 rad) skips the line search.
pub(crate) const SMALL_STEP: f32 = 1e-3;

/// A Newton step that moves no node by more than this fraction of its segment ends the iteration.
pub(crate) const NEWTON_TOLERANCE: f32 = 0.03;

/// A first Newton step that moves a node by more than this many lengths of its segment says the
/// substep is too long for the chain's motion: the step then lies far outside the region where
/// the bending energy is close to its quadratic model, and Newton steps capped at
/// [`NEWTON_ITERATIONS`] leave a stiff curly chain looser than its springs, or walk it into
/// another twisted minimum of the bending energy (measured on the stability map: motion ratios of
/// 2.2–11.7 at 10× and 100× the curly stiffness at 1/30–1/15 s). Such a chain's step is redone
/// with twice the substeps ([`XpbdOutcome::TooLong`], up to [`MAX_ADAPTIVE_HALVINGS`] times).
///
/// The value comes from the map (`docs/dynamics.md`, *Adaptive substeps*): at 1.5 the curly test
/// chain in a 3 rad/s shake at 1/60 s already doubles its substeps (one substep per frame cost
/// 5.4× more), at 2 it never does and no run of the map is unstable, at 3 two runs stay unstable.
pub(crate) const TOO_LONG_MOVE: f32 = 2.0;

/// How many times a chain's step may double its substeps because a substep was too long
/// ([`TOO_LONG_MOVE`]); the last try is taken as it is.
pub const MAX_ADAPTIVE_HALVINGS: u32 = 5;

/// How one XPBD substep of a chain ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum XpbdOutcome {
    /// The substep is done.
    Done,
    /// A value was not finite or the system could not be factorised (the state is not usable).
    Failed,
    /// The first Newton step moved a node by more than [`TOO_LONG_MOVE`] segments (by the
    /// number held, the largest move over its segment): the state is mid-step (not usable) and
    /// the chain's step should be redone with shorter substeps.
    TooLong(f32),
}

/// The relative rounding of `Φ` (sums of a few dozen f32 terms) below which the line search
/// does not tell a rise from noise.
pub(crate) const ROUNDING: f32 = 1e-6;

/// How many times the line search halves a bending step before dropping it.
pub const LINE_SEARCH_HALVINGS: usize = 6;

/// One XPBD substep of one chain (module docs). `arrays.forces` holds `δ = x − x_n` during the
/// step, `arrays.corrections` the prediction's `δ`. With `adaptive`, a first Newton step that
/// moves a node by more than [`TOO_LONG_MOVE`] segment lengths stops the substep
/// ([`XpbdOutcome::TooLong`]).
pub(crate) fn xpbd(
    chain: &ChainConstants,
    arrays: &mut ChainArrays,
    step: &Substep,
    adaptive: bool,
) -> XpbdOutcome {
    let h = step.h;
    let params = step.params;
    let n = arrays.positions.len();
    let first = step.first_free_node();
    let attached = step.attached();
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
    if attached {
        arrays.forces[0] = root_end - arrays.positions[0];
    }
    arrays.corrections.copy_from_slice(arrays.forces);
    // 2. Bending: Newton steps (M/h² + H)·Δx = −∇Φ, linearised at x = x_n + δ (held in the
    //    velocities meanwhile), each with a line search on Φ.
    let root_frame = step.head_end.transform_frame(&chain.root_frame);
    let inverse_h_squared = 1.0 / (h * h);
    // The inertia of implicit Euler with the drag in it: M·(1 + h·γ)/h² (the prediction already
    // divides by 1 + h·γ), so that drag slows motion but does not lift a hanging chain.
    let inertia_scale = (1.0 + h * gamma) * inverse_h_squared;
    let Some(implicit) = arrays.implicit.as_mut() else {
        return XpbdOutcome::Failed;
    };
    let inertia = |moved: &[Vec3], predicted: &[Vec3]| {
        (first..n)
            .map(|i| 0.5 * chain.masses[i] * (moved[i] - predicted[i]).length_squared())
            .sum::<f32>()
            * inertia_scale
    };
    for iteration in 0..NEWTON_ITERATIONS {
        for i in 0..n {
            arrays.velocities[i] = arrays.positions[i] + arrays.forces[i];
        }
        if attached {
            arrays.velocities[0] = root_end;
        }
        // Assemble and solve; where f32 cannot factorise the system (stiffness 10⁴× the
        // inertia's and beyond), again with a Levenberg-Marquardt term μ·I on the diagonal, which
        // keeps the step a descent direction for the line search.
        let mut solved = None;
        for regularization in [0.0f32, 1e-4, 1e-2] {
            for i in 0..n {
                implicit.diagonal[i] =
                    Mat3::from_diagonal(Vec3::splat(chain.masses[i] * inertia_scale));
                implicit.first[i] = Mat3::ZERO;
                implicit.second[i] = Mat3::ZERO;
                implicit.rhs[i] =
                    (arrays.corrections[i] - arrays.forces[i]) * (chain.masses[i] * inertia_scale);
            }
            let here = &*arrays.velocities;
            let mut energy = add_spring_forces(
                here,
                here,
                &root_frame,
                Vec3::ZERO,
                chain.rest_local,
                chain.stiffness,
                0.0,
                !attached,
                arrays.work,
                implicit.rhs,
            );
            walk_joints(here, &root_frame, chain.rest_local, |joint| {
                let k = chain.stiffness[joint.node];
                if k > 0.0 && (joint.node >= 2 || attached) {
                    add_spring_blocks(joint, k, implicit);
                }
            });
            // The lengths, in the same step, as stiff springs: so that the step bends the chain
            // instead of stretching it (the exact projection below then has little to do). Left
            // out, the step and the projection undo each other on curly chains at h·ω ≳ 1.
            energy += add_length_springs(
                chain,
                here,
                inverse_h_squared,
                1.0,
                Some(implicit.rhs),
                implicit.diagonal,
                implicit.first,
            );
            let objective = energy + inertia(arrays.forces, arrays.corrections);
            if regularization > 0.0 {
                let largest = implicit.diagonal[first..n]
                    .iter()
                    .map(|block| block.x_axis.x.max(block.y_axis.y).max(block.z_axis.z))
                    .fold(0.0f32, f32::max);
                for block in &mut implicit.diagonal[first..n] {
                    *block += Mat3::from_diagonal(Vec3::splat(regularization * largest));
                }
            }
            if attached {
                implicit.diagonal[0] = Mat3::IDENTITY;
                implicit.rhs[0] = Vec3::ZERO;
                if n > 1 {
                    implicit.first[1] = Mat3::ZERO;
                }
                if n > 2 {
                    implicit.second[2] = Mat3::ZERO;
                }
            }
            with_scratch(|scratch| scratch.keep_rhs(implicit.rhs));
            if solve_block_pentadiagonal(
                implicit.diagonal,
                implicit.first,
                implicit.second,
                implicit.rhs,
            ) {
                solved = Some(objective);
                break;
            }
        }
        let Some(objective) = solved else {
            return XpbdOutcome::Failed;
        };
        // A first step that turns no segment by more than SMALL_STEP rad is taken as it is: there
        // the objective is quadratic to ~1e-6 of the step, so the line search could only confirm
        // it (it costs a walk of the chain; a substep at ×32 costs 15 % less). At 0.01 rad a
        // substep at ×8 cost 18 % less too, but the free swing of a curly chain at 100× stiffness
        // gained three times the energy (1.8 % of m·g·L in 3 s against 0.55 %).
        if adaptive && iteration == 0 {
            let moved = largest_move(chain, first, implicit.rhs);
            // NaN is not too long: the step goes on and fails as a non-finite value.
            if moved > TOO_LONG_MOVE {
                return XpbdOutcome::TooLong(moved);
            }
        }
        let small = iteration == 0 && turns_within(chain, first, implicit.rhs, 1.0, SMALL_STEP);
        if small {
            for i in first..n {
                arrays.forces[i] += implicit.rhs[i];
            }
            break;
        }
        // Line search: the whole step where Φ does not rise, else halved; the iterate waits in
        // `work` meanwhile, the trial positions x_n + δ in the velocities (the root stays at its
        // end position there).
        for i in 0..n {
            arrays.work[i] = arrays.forces[i].extend(0.0);
        }
        let mut scale = 1.0f32;
        let mut accepted = false;
        let mut twisted = false;
        let mut halvings = 0;
        loop {
            for i in first..n {
                arrays.forces[i] = arrays.work[i].truncate() + implicit.rhs[i] * scale;
                arrays.velocities[i] = arrays.positions[i] + arrays.forces[i];
            }
            let trial = step_energy(
                chain,
                arrays.velocities,
                &root_frame,
                attached,
                inverse_h_squared,
            ) + inertia(arrays.forces, arrays.corrections);
            // The first step within the rounding of the sums (a relative 1e-6): at short
            // substeps a whole step changes Φ by less than that, and rounding must not reject it;
            // later ones (large rotations) must lower Φ.
            let slack = if iteration == 0 {
                ROUNDING * (objective.abs() + trial.abs())
            } else {
                0.0
            };
            if trial <= objective + slack {
                accepted = true;
                break;
            }
            // The band's whole step raised Φ: next the step with the twist's coupling
            // (`twisted_cg`), whole, before any halving.
            if !twisted {
                twisted = true;
                for i in first..n {
                    arrays.velocities[i] = arrays.positions[i] + arrays.work[i].truncate();
                }
                let factorised = (&*implicit.diagonal, &*implicit.first, &*implicit.second);
                let finite = with_scratch(|scratch| {
                    scratch.twisted_step(
                        factorised,
                        arrays.velocities,
                        &root_frame,
                        chain.rest_local,
                        chain.stiffness,
                        attached,
                        implicit.rhs,
                    )
                });
                if finite {
                    continue;
                }
            }
            if halvings == LINE_SEARCH_HALVINGS {
                break;
            }
            halvings += 1;
            scale *= 0.5;
        }
        if !accepted {
            for i in first..n {
                arrays.forces[i] = arrays.work[i].truncate();
            }
            break;
        }
        // Converged when the step moved no node by more than NEWTON_TOLERANCE of its segment
        // (rotations below ~0.03 rad, where the linearisation's error, of their square, is below
        // 1e-3 of the step).
        let converged = turns_within(chain, first, implicit.rhs, scale, NEWTON_TOLERANCE);
        // A whole step ends the iteration once converged or after a second one (more whole
        // steps on a curly chain can walk it into another twisted minimum of the bending energy:
        // measured on the stability map, motion ratios above 2 at 10× stiffness); a shortened
        // step goes on.
        if scale == 1.0 && (converged || iteration >= 1) {
            break;
        }
    }
    // 3. Lengths: exact mass-weighted projection, then follow-the-leader for the rounding, on the
    //    positions x_n + δ; x_n waits in the velocities meanwhile.
    let inverse_mass = |i: usize| {
        if i < first {
            0.0
        } else {
            1.0 / chain.masses[i]
        }
    };
    for i in 0..n {
        let start = arrays.positions[i];
        arrays.velocities[i] = start;
        arrays.positions[i] = start + arrays.forces[i];
    }
    if attached {
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
    if attached {
        arrays.velocities[0] = root_velocity;
    }
    // 5. Spring damping on the velocities.
    if params.bending_damping > 0.0 {
        damp_bending(
            arrays.positions,
            arrays.velocities,
            &root_frame,
            step.head_spin,
            chain,
            inverse_mass,
            h * params.bending_damping,
            attached,
        );
    }
    let finite = arrays
        .velocities
        .iter()
        .chain(arrays.positions.iter())
        .all(|v| v.is_finite());
    if finite {
        XpbdOutcome::Done
    } else {
        XpbdOutcome::Failed
    }
}

/// The step's energy [J] of one chain at `positions`: the bending energy `Σ ½·k_i·α_i²`, with
/// the parent frames parallel-transported along it from `root_frame` (the springs' own
/// definition), and the lengths' `Σ ½·κ_j·(|x_j − x_{j−1}| − l_j)²` (the step's stiff springs).
fn step_energy(
    chain: &ChainConstants,
    positions: &[Vec3],
    root_frame: &Frame,
    attached: bool,
    inverse_h_squared: f32,
) -> f32 {
    let mut energy = 0.0f32;
    walk_joints(positions, root_frame, chain.rest_local, |joint| {
        let i = joint.node;
        let k = chain.stiffness[i];
        if k > 0.0 && (i >= 2 || attached) {
            let (angle, _) = bend_angle_and_factor(joint.direction, joint.rest_direction);
            energy += 0.5 * k * angle * angle;
        }
        let stretch = (positions[i] - positions[i - 1]).length() - chain.rest_lengths[i];
        energy += 0.5 * length_stiffness(chain, i, inverse_h_squared) * stretch * stretch;
    });
    energy
}

/// Whether `scale·step` moves no free node (from `first`) by more than `fraction` of the longer
/// of its two segments: a turn of at most about `fraction` rad.
fn turns_within(
    chain: &ChainConstants,
    first: usize,
    step: &[Vec3],
    scale: f32,
    fraction: f32,
) -> bool {
    (first..step.len()).all(|i| (step[i] * scale).length() <= fraction * lever(chain, i))
}

/// The longer of the two segments node `i` joins [m]: the length its moves are measured in.
fn lever(chain: &ChainConstants, i: usize) -> f32 {
    chain.rest_lengths[i].max(chain.rest_lengths.get(i + 1).copied().unwrap_or(0.0))
}

/// The largest move of a node `first..` in `step`, over its [`lever`] (as [`turns_within`]
/// measures it).
fn largest_move(chain: &ChainConstants, first: usize, step: &[Vec3]) -> f32 {
    (first..step.len())
        .map(|i| step[i].length() / lever(chain, i))
        .fold(0.0, f32::max)
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
