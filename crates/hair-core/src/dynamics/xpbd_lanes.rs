//! The XPBD step ([`xpbd`](crate::dynamics::xpbd), its module docs give the method) for
//! [`LANES`](crate::dynamics::lanes::LANES) chains at once, with attached roots: the same
//! prediction, line-searched Newton steps of `(M/h² + H)·Δx = −∇Φ`, exact length projection and
//! damping sweep, with every number widened to one lane per chain in struct-of-arrays form on
//! the stack (nothing is allocated).
//!
//! Lanes follow their own control flow under masks: each lane takes the Newton steps, line
//! search halvings and length iterations the one-chain step would take, and a lane that is done
//! keeps its values while the others go on, so a lane's result does not depend on the other
//! chains of its batch. A lane whose system cannot be factorised even with the
//! Levenberg-Marquardt terms, whose transport is undefined (a segment turned back on its
//! parent), or whose state fails the check is reported, and the caller redoes that chain with
//! the one-chain step and its failure policy, like the lane-parallel position-based step.
//!
//! Per step rather than per substep: the external accelerations (gravity, drag towards the wind
//! sampled at the step's start, `F_col/m`), the lengths' stiffness κ and the inertia
//! `m·(1 + h·γ)/h²`.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::head_motion::angular_velocity;
use crate::dynamics::integrators::LENGTH_STIFFNESS;
use crate::dynamics::lane_batch::{
    BatchState, BatchStep, carried_roots, check_and_scatter, gather,
};
use crate::dynamics::lane_blocks::LaneSystem;
use crate::dynamics::lane_lengths::{follow_the_leader, project_lengths};
use crate::dynamics::lane_model::{LaneNode, LaneRoots};
use crate::dynamics::lane_springs::{LaneFrame, SpringScratch};
use crate::dynamics::lane_twisted_cg::{LaneTwistScratch, twisted_step as lane_twisted_step};
use crate::dynamics::lane_xpbd_system::{LaneChainTerms, assemble, objective};
use crate::dynamics::lanes::{LaneVec3, Lanes};
use crate::dynamics::xpbd::{
    LINE_SEARCH_HALVINGS, NEWTON_ITERATIONS, NEWTON_TOLERANCE, ROUNDING, SMALL_STEP, TOO_LONG_MOVE,
};

/// The Levenberg-Marquardt terms, relative to the largest diagonal entry, tried in turn where a
/// lane's system cannot be factorised (as the one-chain step).
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

/// 1.0 in the lanes where `scale·step` moves no node `1..n` by more than `fraction` of its lever.
#[inline(always)]
fn turns_within<const N: usize>(
    step: &[LaneVec3; N],
    scale: Lanes,
    lever: &[Lanes; N],
    n: usize,
    fraction: f32,
) -> Lanes {
    let mut outside = Lanes::splat(0.0);
    let fraction = Lanes::splat(fraction);
    for i in 1..n {
        let moved = step[i].scale(scale).length_squared().sqrt();
        outside = outside.max(moved.greater(fraction * lever[i]));
    }
    Lanes::splat(1.0) - outside
}

/// Steps a batch with attached roots through all substeps (see the module docs); returns the bit
/// mask of the chains (bit `c − first_chain`) that failed and whose new state was not written.
#[inline(always)]
pub(crate) fn step_xpbd_lanes<const N: usize>(
    step: &BatchStep,
    state: BatchState,
    constants: &[LaneNode],
    roots: &LaneRoots,
) -> u32 {
    let settings = step.settings;
    let n = constants.len().min(N);
    let constants = &constants[..n];
    let substeps = settings.substeps as usize;
    let h = settings.substep();
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
    let gamma = step.air_drag_rate;
    let gravity = step.environment.gravity;
    let inverse_h_squared = 1.0 / (h * h);
    let inertia_scale = Lanes::splat((1.0 + h * gamma) * inverse_h_squared);
    for i in 1..n {
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
        // κ_i = LENGTH_STIFFNESS·max(m_i/h², max(k_i, k_{i+1})/l_i²) (`length_stiffness`).
        let next = if i + 1 < n {
            constants[i + 1].stiffness
        } else {
            zero
        };
        let bending = c.stiffness.max(next) / (c.rest_length * c.rest_length);
        s.kappa[i] = Lanes::splat(LENGTH_STIFFNESS)
            * (c.mass * Lanes::splat(inverse_h_squared)).max(bending);
        s.inertia[i] = c.mass * inertia_scale;
        let next_length = if i + 1 < n {
            constants[i + 1].rest_length
        } else {
            zero
        };
        s.lever[i] = c.rest_length.max(next_length);
    }
    let mut springs = SpringScratch::<N>::new();
    let mut system = LaneSystem::<N>::new();
    let mut twist = LaneTwistScratch::<N>::new();
    let mut degenerate = zero;
    let mut unsolved = zero;
    let drag_divisor = Lanes::splat(1.0 / (1.0 + h * gamma));
    let hv = Lanes::splat(h);
    let inverse_h = Lanes::splat(1.0 / h);
    let (mut root_start, _) = carried_roots(roots, &step.head_poses[0], &step.head_rotations[0]);
    for k in 0..substeps {
        let (root_end, root_frame) =
            carried_roots(roots, &step.head_poses[k + 1], &step.head_rotations[k + 1]);
        // 1. Prediction with implicit drag: δ̃ = h·(v + h·a)/(1 + h·γ).
        for i in 1..n {
            let predicted = (s.velocities[i] + s.kicks[i]).scale(drag_divisor).scale(hv);
            s.predicted[i] = predicted;
            s.delta[i] = predicted;
        }
        s.delta[0] = root_end - s.positions[0];
        s.predicted[0] = s.delta[0];
        let terms = LaneChainTerms {
            constants,
            kappa: &s.kappa,
            inertia: &s.inertia,
            predicted: &s.predicted,
            root_frame,
        };
        // 2. Newton steps with a line search, each lane until it is done.
        let mut active = one;
        for iteration in 0..NEWTON_ITERATIONS {
            if !active.any() {
                break;
            }
            for i in 1..n {
                s.here[i] = s.positions[i] + s.delta[i];
            }
            s.here[0] = root_end;
            let mut regularization = zero;
            let mut objective_here = zero;
            for attempt in 0..REGULARIZATION.len() {
                objective_here = assemble(
                    &terms,
                    &mut springs,
                    &mut system,
                    &s.here,
                    &s.delta,
                    n,
                    &mut degenerate,
                );
                if regularization.any() {
                    let mut largest = zero;
                    for i in 1..n {
                        largest = largest.max(system.diagonal[i].largest_diagonal());
                    }
                    let term = regularization * largest;
                    for i in 1..n {
                        system.diagonal[i].add_to_diagonal(term);
                    }
                }
                s.rhs = system.rhs;
                let solved = system.solve(1, n);
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
            // too long for that chain, which the one-chain step redoes with more substeps.
            if iteration == 0 {
                let too_long = and_not(
                    active,
                    turns_within(&s.step, one, &s.lever, n, TOO_LONG_MOVE),
                );
                if too_long.any() {
                    unsolved = unsolved.max(too_long);
                    active = and_not(active, too_long);
                    if !active.any() {
                        break;
                    }
                }
            }
            // A first step that turns no segment by more than SMALL_STEP rad is taken whole.
            if iteration == 0 {
                let small = active * turns_within(&s.step, one, &s.lever, n, SMALL_STEP);
                if small.any() {
                    for i in 1..n {
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
                for i in 1..n {
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
                for i in 1..n {
                    s.delta[i] = LaneVec3::select(accepted, s.trial[i], s.delta[i]);
                }
                taken = Lanes::select(accepted, scale, taken);
                pending = and_not(pending, accepted);
                if !pending.any() {
                    break;
                }
                // The band's whole step raised Φ: next the twisted step (`lane_twisted_cg`),
                // whole, in the lanes where it is finite.
                let mut retry = zero;
                if !twisted {
                    twisted = true;
                    let mut twisted_step = s.step;
                    let finite = lane_twisted_step(
                        &system,
                        &springs,
                        constants,
                        &s.rhs,
                        &mut twist,
                        n,
                        &mut twisted_step,
                    );
                    retry = pending * finite;
                    for i in 1..n {
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
            let converged = turns_within(&s.step, taken, &s.lever, n, NEWTON_TOLERANCE);
            let whole = Lanes::zip(taken, one, |a, b| f32::from(a == b));
            let second = if iteration >= 1 { one } else { zero };
            active = and_not(active, whole * converged.max(second));
        }
        // 3. Lengths: exact mass-weighted projection, then follow-the-leader, on x_n + δ.
        for i in 1..n {
            s.here[i] = s.positions[i] + s.delta[i];
        }
        s.here[0] = root_end;
        project_lengths(&mut s.here, constants, n);
        follow_the_leader(&mut s.here, constants, n);
        // 4. v = (δ + c)/h with the lengths' correction c = x − (x_n + δ).
        for i in 1..n {
            let before = s.positions[i] + s.delta[i];
            let correction = s.here[i] - before;
            s.velocities[i] = (s.delta[i] + correction).scale(inverse_h);
        }
        s.velocities[0] = (root_end - root_start).scale(inverse_h);
        // 5. Spring damping on the velocities.
        if step.bending_damping > 0.0 {
            let start = &step.head_poses[k];
            let end = &step.head_poses[k + 1];
            let spin = angular_velocity(start.rotation, end.rotation, h);
            damp_bending(
                &s.here,
                &mut s.velocities,
                constants,
                n,
                root_frame,
                spin,
                Lanes::splat(h * step.bending_damping),
                &mut degenerate,
            );
        }
        s.positions = s.here;
        root_start = root_end;
    }
    // Check every lane (transport defined, solved) and write the ones that pass.
    check_and_scatter(
        state,
        constants,
        &s.positions,
        &s.velocities,
        settings.max_speed,
        &[degenerate, unsolved],
    )
}

/// The spring damping sweep of [`xpbd`](crate::dynamics::xpbd) (`damp_bending`) for every lane:
/// root to tip, each joint implicit in its own rate, `μ = h·β·k·ė/(1 + h·β·k·W̄)`. `gain` is
/// `h·β` [s²], `root_spin` the root frame's angular velocity [rad/s].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn damp_bending<const N: usize>(
    positions: &[LaneVec3; N],
    velocities: &mut [LaneVec3; N],
    constants: &[LaneNode],
    n: usize,
    root_frame: LaneFrame,
    root_spin: glam::Vec3,
    gain: Lanes,
    degenerate: &mut Lanes,
) {
    let one = Lanes::splat(1.0);
    let two = Lanes::splat(2.0);
    let four = Lanes::splat(4.0);
    let zero = Lanes::splat(0.0);
    let spin = LaneVec3 {
        x: Lanes::splat(root_spin.x),
        y: Lanes::splat(root_spin.y),
        z: Lanes::splat(root_spin.z),
    };
    let weight = |i: usize| {
        if i == 0 {
            zero
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
        segment.mark_degenerate(degenerate);
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
        let gk = gain * c.stiffness;
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
