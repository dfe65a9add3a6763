//! The XPBD integrator with small steps (Macklin, Müller, Chentanez 2016, "XPBD: position-based
//! simulation of compliant constrained dynamics"; Macklin et al. 2019, "Small steps in physics
//! simulation"), for [`LANES`](crate::dynamics::lanes::LANES) chains at once (the only
//! implementation: a chain alone is a run of one), with each chain's bending constraints solved
//! together: one substep is a
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

//!
//! **Lanes.** Every number is widened to one lane per chain, in struct-of-arrays form on the
//! stack (nothing is allocated). Lanes follow their own control flow under masks: each lane takes
//! its own Newton steps, line search halvings and length iterations, and a lane that is done keeps
//! its values while the others go on, so a chain's result does not depend on the other chains of
//! its run. A lane whose system cannot be factorised even with the Levenberg-Marquardt terms, or
//! whose state fails the check, is reported, and the caller redoes that chain with half the
//! substep where its failure policy allows. With attached roots node 0 follows the head; with
//! free roots it is an unknown like the others and the root bend has no spring. Per step rather
//! than per substep: the external accelerations (gravity, drag towards the wind sampled at the
//! step's start, `F_col/m`), the lengths' stiffness κ and the inertia `m·(1 + h·γ)/h²`.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::integrators::LENGTH_STIFFNESS;
use crate::dynamics::lane_batch::{
    Attempt, BatchState, BatchStep, LaneOutcome, carried_roots, check_and_scatter, gather,
};
use crate::dynamics::lane_blocks::LaneSystem;
use crate::dynamics::lane_damping::damp_bending;
use crate::dynamics::lane_lengths::{follow_the_leader, project_lengths};
use crate::dynamics::lane_model::{LaneNode, LaneRoots};
use crate::dynamics::lane_springs::SpringScratch;
use crate::dynamics::lane_xpbd_system::{LaneChainTerms, assemble, objective};
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::params::RootMode;
use crate::dynamics::twisted_cg::{self, LaneTwistScratch};

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
/// with twice the substeps (up to [`MAX_ADAPTIVE_HALVINGS`] times).
///
/// The value comes from the map (`docs/dynamics.md`, *Adaptive substeps*): at 1.5 the curly test
/// chain in a 3 rad/s shake at 1/60 s already doubles its substeps (one substep per frame cost
/// 5.4× more), at 2 it never does and no run of the map is unstable, at 3 two runs stay unstable.
pub(crate) const TOO_LONG_MOVE: f32 = 2.0;

/// How many times a chain's step may double its substeps because a substep was too long
/// ([`TOO_LONG_MOVE`]); the last try is taken as it is.
pub const MAX_ADAPTIVE_HALVINGS: u32 = 5;

/// The relative rounding of `Φ` (sums of a few dozen f32 terms) below which the line search
/// does not tell a rise from noise.
pub(crate) const ROUNDING: f32 = 1e-6;

/// How many times the line search halves a bending step before dropping it.
pub const LINE_SEARCH_HALVINGS: usize = 6;

/// The Levenberg-Marquardt terms, relative to the largest diagonal entry, tried in turn where a
/// lane's system cannot be factorised.
const REGULARIZATION: [f32; 3] = [0.0, 1e-4, 1e-2];

/// Per-node arrays of a batch, `N` ≥ the node count.
struct XpbdLanes<const N: usize> {
    /// Positions at the substep's start `x_n` [m].
    positions: [LaneVec3; N],
    velocities: [LaneVec3; N],
    /// `h·a_ext` [m/s], the external accelerations held over the step.
    kicks: [LaneVec3; N],
    /// The displacements `δ = x − x_n` [m] of the Newton iteration.
    delta: [LaneVec3; N],
    /// The prediction's `δ̃` [m].
    predicted: [LaneVec3; N],
    /// The iterate before a line search, and the trial displacements.
    base: [LaneVec3; N],
    trial: [LaneVec3; N],
    /// Positions `x_n + δ` [m] at which the system or `Φ` is evaluated; after the Newton
    /// iteration the new positions.
    here: [LaneVec3; N],
    /// The Newton step of the iteration (the band's, or the twisted one) and the system's
    /// right-hand side `b` before the solve.
    step: [LaneVec3; N],
    rhs: [LaneVec3; N],
    kappa: [Lanes; N],
    inertia: [Lanes; N],
    /// `max(l_i, l_{i+1})` [m]: the lever of a node's move in the convergence tests.
    lever: [Lanes; N],
}

/// `1.0` where `a` and not `b`, per lane (both 1.0 / 0.0 masks).
#[inline(always)]
fn and_not(a: Lanes, b: Lanes) -> Lanes {
    a * (Lanes::splat(1.0) - b)
}

/// 1.0 in the lanes where `scale·step` moves no node `first..n` by more than `fraction` of its
/// lever.
#[inline(always)]
fn turns_within<const N: usize>(
    step: &[LaneVec3; N],
    scale: Lanes,
    lever: &[Lanes; N],
    first: usize,
    n: usize,
    fraction: f32,
) -> Lanes {
    let mut outside = Lanes::splat(0.0);
    let fraction = Lanes::splat(fraction);
    for i in first..n {
        let moved = step[i].scale(scale).length_squared().sqrt();
        outside = outside.max(moved.greater(fraction * lever[i]));
    }
    Lanes::splat(1.0) - outside
}

/// `x_n + δ` of nodes `0..n` into `here`, an attached root at `root`.
#[inline(always)]
fn displaced<const N: usize>(
    here: &mut [LaneVec3; N],
    positions: &[LaneVec3; N],
    delta: &[LaneVec3; N],
    n: usize,
    root: Option<LaneVec3>,
) {
    for i in 0..n {
        here[i] = positions[i] + delta[i];
    }
    if let Some(root) = root {
        here[0] = root;
    }
}

/// The largest move of a node `first..n` of lane `lane` of `step`, over its lever (as
/// [`turns_within`] measures it).
fn largest_move<const N: usize>(
    step: &[LaneVec3; N],
    lever: &[Lanes; N],
    first: usize,
    n: usize,
    lane: usize,
) -> f32 {
    (first..n)
        .map(|i| step[i].get(lane).length() / lever[i].0[lane])
        .fold(0.0, f32::max)
}

/// Steps a run through all its substeps (see the module docs) as `attempt` asks; returns how
/// each lane ended (the lanes that pass and are in `attempt.write` are written).
#[inline(always)]
pub(crate) fn step_xpbd<const N: usize>(
    step: &BatchStep,
    state: BatchState,
    constants: &[LaneNode],
    roots: &LaneRoots,
    attempt: Attempt,
) -> LaneOutcome {
    let settings = step.settings;
    let n = constants.len().min(N);
    let constants = &constants[..n];
    let attached = settings.roots == RootMode::Attached;
    // The first unknown: node 0 follows the head where the roots are attached.
    let first = usize::from(attached);
    let (substeps, h) = attempt.substeps(settings);
    let zero = Lanes::splat(0.0);
    let one = Lanes::splat(1.0);
    let mut s = XpbdLanes::<N> {
        positions: [LaneVec3::default(); N],
        velocities: [LaneVec3::default(); N],
        kicks: [LaneVec3::default(); N],
        delta: [LaneVec3::default(); N],
        predicted: [LaneVec3::default(); N],
        base: [LaneVec3::default(); N],
        trial: [LaneVec3::default(); N],
        here: [LaneVec3::default(); N],
        step: [LaneVec3::default(); N],
        rhs: [LaneVec3::default(); N],
        kappa: [zero; N],
        inertia: [zero; N],
        lever: [zero; N],
    };
    // Gather; the kicks hold the collision forces at first.
    gather(&state, n, &mut s.positions, &mut s.velocities, &mut s.kicks);
    let chains = (state.first_chain, state.end_chain);
    let gamma = step.air_drag_rate;
    let gravity = step.environment.gravity;
    let inverse_h_squared = 1.0 / (h * h);
    let inertia_scale = Lanes::splat((1.0 + h * gamma) * inverse_h_squared);
    for i in first..n {
        let c = &constants[i];
        // h·(g + γ·w + F_col/m), the wind sampled at the step's start.
        let wind = step
            .environment
            .wind
            .velocity_at_lanes(&s.positions[i], step.time);
        let collision = s.kicks[i];
        let acceleration = LaneVec3 {
            x: Lanes::splat(gravity.x) + collision.x * c.inverse_mass,
            y: Lanes::splat(gravity.y) + collision.y * c.inverse_mass,
            z: Lanes::splat(gravity.z) + collision.z * c.inverse_mass,
        } + wind.scale(Lanes::splat(gamma));
        s.kicks[i] = acceleration.scale(Lanes::splat(h));
    }
    for i in 0..n {
        let c = &constants[i];
        let next = |value: fn(&LaneNode) -> Lanes| {
            if i + 1 < n {
                value(&constants[i + 1])
            } else {
                zero
            }
        };
        if i >= 1 {
            // κ_i = LENGTH_STIFFNESS·max(m_i/h², max(k_i, k_{i+1})/l_i²) (`length_stiffness`).
            let bending = c.stiffness.max(next(|c| c.stiffness)) / (c.rest_length * c.rest_length);
            s.kappa[i] = Lanes::splat(LENGTH_STIFFNESS)
                * (c.mass * Lanes::splat(inverse_h_squared)).max(bending);
        }
        s.inertia[i] = c.mass * inertia_scale;
        s.lever[i] = c.rest_length.max(next(|c| c.rest_length));
    }
    // The lanes XPBD's adaptive substeps stopped (a first Newton move too long) and those whose
    // system could not be factorised: both are done for this try.
    let mut too_long = [None; LANES];
    let mut stopped = zero;
    let mut unsolved = zero;
    let mut springs = SpringScratch::<N>::new();
    let mut system = LaneSystem::<N>::new();
    let mut twist = LaneTwistScratch::<N>::new();
    let drag_divisor = Lanes::splat(1.0 / (1.0 + h * gamma));
    let hv = Lanes::splat(h);
    let inverse_h = Lanes::splat(1.0 / h);
    let root_weight = if attached {
        zero
    } else {
        constants[0].inverse_mass
    };
    let mut poses_start = step.root_poses(chains.0, chains.1, attempt.halvings, 0);
    let (mut root_start, _) = carried_roots(roots, &poses_start);
    for k in 0..substeps {
        let poses_end = step.root_poses(chains.0, chains.1, attempt.halvings, k + 1);
        let (root_end, root_frame) = carried_roots(roots, &poses_end);
        // 1. Prediction with implicit drag: δ̃ = h·(v + h·a)/(1 + h·γ).
        for i in first..n {
            let predicted = (s.velocities[i] + s.kicks[i]).scale(drag_divisor).scale(hv);
            s.predicted[i] = predicted;
            s.delta[i] = predicted;
        }
        if attached {
            s.delta[0] = root_end - s.positions[0];
            s.predicted[0] = s.delta[0];
        }
        let terms = LaneChainTerms {
            constants,
            first,
            kappa: &s.kappa,
            inertia: &s.inertia,
            predicted: &s.predicted,
            root_frame,
        };
        let root = attached.then_some(root_end);
        // 2. Newton steps with a line search, each lane until it is done.
        let mut active = one - stopped.max(unsolved);
        for iteration in 0..NEWTON_ITERATIONS {
            if !active.any() {
                break;
            }
            displaced(&mut s.here, &s.positions, &s.delta, n, root);
            let mut regularization = zero;
            let mut objective_here = zero;
            for attempt in 0..REGULARIZATION.len() {
                objective_here = assemble(&terms, &mut springs, &mut system, &s.here, &s.delta, n);
                if regularization.any() {
                    let mut largest = zero;
                    for i in first..n {
                        largest = largest.max(system.diagonal[i].largest_diagonal());
                    }
                    let term = regularization * largest;
                    for i in first..n {
                        system.diagonal[i].add_to_diagonal(term);
                    }
                }
                s.rhs = system.rhs;
                let solved = system.solve(first, n);
                let failed = and_not(active, solved);
                if !failed.any() {
                    break;
                }
                if attempt + 1 == REGULARIZATION.len() {
                    unsolved = unsolved.max(failed);
                    active = and_not(active, failed);
                    break;
                }
                regularization = Lanes::select(
                    failed,
                    Lanes::splat(REGULARIZATION[attempt + 1]),
                    regularization,
                );
            }
            s.step = system.rhs;
            // A first step that moves a node by more than TOO_LONG_MOVE segments: the substep is
            // too long for that chain, which the caller redoes with more substeps.
            if iteration == 0 {
                let adapting = active * attempt.adaptive;
                let long = and_not(
                    adapting,
                    turns_within(&s.step, one, &s.lever, first, n, TOO_LONG_MOVE),
                );
                if long.any() {
                    for (lane, moved) in too_long.iter_mut().enumerate() {
                        if long.0[lane] > 0.0 {
                            *moved = Some(largest_move(&s.step, &s.lever, first, n, lane));
                        }
                    }
                    stopped = stopped.max(long);
                    active = and_not(active, long);
                    if !active.any() {
                        break;
                    }
                }
            }
            // A first step that turns no segment by more than SMALL_STEP rad is taken whole.
            if iteration == 0 {
                let small = active * turns_within(&s.step, one, &s.lever, first, n, SMALL_STEP);
                if small.any() {
                    for i in first..n {
                        s.delta[i] = LaneVec3::select(small, s.delta[i] + s.step[i], s.delta[i]);
                    }
                    active = and_not(active, small);
                    if !active.any() {
                        break;
                    }
                }
            }
            // Line search on Φ: the whole step where Φ does not rise, then (once) the twisted
            // step whole, else halved, down to 1/2^LINE_SEARCH_HALVINGS.
            s.base = s.delta;
            let mut scale = one;
            let mut taken = zero;
            let mut pending = active;
            let mut dropped = zero;
            let mut twisted = false;
            let smallest = Lanes::splat(0.5f32.powi(LINE_SEARCH_HALVINGS as i32));
            loop {
                for i in first..n {
                    s.trial[i] = s.base[i] + s.step[i].scale(scale);
                    s.here[i] = s.positions[i] + s.trial[i];
                }
                let trial = objective(&terms, &s.here, &s.trial, n);
                let slack = if iteration == 0 {
                    Lanes::splat(ROUNDING) * (objective_here.abs() + trial.abs())
                } else {
                    zero
                };
                // `trial ≤ objective + slack` (NaN rejects).
                let bound = objective_here + slack;
                let accepted = pending * Lanes::zip(trial, bound, |a, b| f32::from(a <= b));
                for i in first..n {
                    s.delta[i] = LaneVec3::select(accepted, s.trial[i], s.delta[i]);
                }
                taken = Lanes::select(accepted, scale, taken);
                pending = and_not(pending, accepted);
                if !pending.any() {
                    break;
                }
                // The band's whole step raised Φ: next the twisted step (`twisted_cg`), whole,
                // in the lanes where it is finite.
                let mut retry = zero;
                if !twisted {
                    twisted = true;
                    let mut twisted_step = s.step;
                    let finite = twisted_cg::twisted_step(
                        &system,
                        &springs,
                        constants,
                        &s.rhs,
                        &mut twist,
                        first,
                        n,
                        &mut twisted_step,
                    );
                    retry = pending * finite;
                    for i in first..n {
                        s.step[i] = LaneVec3::select(retry, twisted_step[i], s.step[i]);
                    }
                }
                let halving = and_not(pending, retry);
                let exhausted = halving * (one - scale.greater(smallest));
                dropped = dropped.max(exhausted);
                pending = and_not(pending, exhausted);
                if !pending.any() {
                    break;
                }
                scale = Lanes::select(
                    and_not(halving, exhausted),
                    scale * Lanes::splat(0.5),
                    scale,
                );
            }
            // Lanes whose step was dropped are done (their δ is the iterate before it).
            active = and_not(active, dropped);
            // A whole step ends a lane's iteration once converged or after a second one; a
            // shortened step goes on.
            let converged = turns_within(&s.step, taken, &s.lever, first, n, NEWTON_TOLERANCE);
            let whole = Lanes::zip(taken, one, |a, b| f32::from(a == b));
            let second = if iteration >= 1 { one } else { zero };
            active = and_not(active, whole * converged.max(second));
        }
        // 3. Lengths: exact mass-weighted projection, then follow-the-leader, on x_n + δ.
        displaced(&mut s.here, &s.positions, &s.delta, n, root);
        project_lengths(&mut s.here, constants, root_weight, n);
        follow_the_leader(&mut s.here, constants, n);
        // 4. v = (δ + c)/h with the lengths' correction c = x − (x_n + δ).
        for i in first..n {
            let before = s.positions[i] + s.delta[i];
            let correction = s.here[i] - before;
            s.velocities[i] = (s.delta[i] + correction).scale(inverse_h);
        }
        if attached {
            s.velocities[0] = (root_end - root_start).scale(inverse_h);
        }
        // 5. Spring damping on the velocities.
        if step.bending_damping > 0.0 {
            let spin = poses_start.spin_to(&poses_end, h);
            damp_bending(
                &s.here,
                &mut s.velocities,
                constants,
                first,
                root_weight,
                n,
                root_frame,
                spin,
                Lanes::splat(h * step.bending_damping),
            );
        }
        s.positions = s.here;
        root_start = root_end;
        poses_start = poses_end;
    }
    // Check every lane (solved, not stopped) and write the ones that pass.
    check_and_scatter(
        state,
        constants,
        &s.positions,
        &s.velocities,
        settings.max_speed,
        unsolved,
        too_long,
        attempt.write,
    )
}
