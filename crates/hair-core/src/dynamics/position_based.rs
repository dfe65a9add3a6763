//! The position-based integrator (Müller, Kim, Chentanez 2012, with dynamic follow-the-leader)
//! for [`LANES`] chains at once: every number is widened to one lane per chain, in struct-of-arrays form on the
//! stack, so that the compiler vectorises across chains. It is the only implementation of the
//! step: a chain alone is a run of one.
//!
//! One substep:
//! 1. Verlet prediction under the external forces: `v ← v + h·F/m`, `p = x + h·v`.
//! 2. The angular springs as one shape target per chain: the chain's bending energy `E` as an
//!    XPBD constraint `C = √(2E)` (Macklin et al. 2016) with compliance `1` (the stiffnesses are
//!    inside `E`): `Δx_j = w_j·F_j / (Σ w|F|²/(2E) + 1/h²)` with `F = −∇E` the exact spring forces
//!    and `w = 1/m` (0 at an attached root). For small `h` this is the springs' own displacement
//!    `h²·F/m`; for large `h` it is the Gauss-Newton step onto the rest shape, which can neither
//!    overshoot nor be unstable.
//! 3. Follow-the-leader lengths, recording each node's correction `c_i`.
//! 4. `v_i = (p_i − x_i)/h − s_damping·c_{i+1}/h`, with `p − x = h·v_pred + Δshape + c` summed
//!    from its small parts rather than subtracted from rounded positions (which quantises `v` to
//!    `ulp(x)/h`).
//!
//! A run's chains have the same node count (2 to [`MAX_CHAIN_NODES`]); lanes past the run's last
//! chain repeat that chain and are discarded. The constants come laid out in lane form
//! ([`LaneModel`](crate::dynamics::lane_model::LaneModel)); the state is gathered once per step,
//! stepped through all substeps, checked, and scattered into the new state's arrays (the
//! simulation swaps them in when every chain succeeded, so nothing is copied to back it up). Per
//! step, not per substep: the external velocity kick `h·F_ext/m`, and the head's rotation matrices
//! (the roots are rotated lane-wise). A chain that fails the check (a non-finite value, an energy
//! blow-up) is not written but reported, and the caller redoes it with half the substep where its
//! failure policy allows.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::constraints::LENGTH_TOLERANCE;
use crate::dynamics::lane_batch::{
    Attempt, BatchState, BatchStep, LaneOutcome, carried_roots, check_and_scatter, gather,
};
#[cfg(doc)]
use crate::dynamics::lane_model::MAX_CHAIN_NODES;
use crate::dynamics::lane_model::{LaneNode, LaneRoots};
use crate::dynamics::lane_springs::{LaneFrame, SpringScratch, spring_forces};
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::params::RootMode;

/// The state of a batch, `N` ≥ the node count.
struct LaneState<const N: usize> {
    positions: [LaneVec3; N],
    velocities: [LaneVec3; N],
    /// Velocity change of the external forces over one substep, held over the step:
    /// `h·(m·g + m·γ·w + F_col)/m` [m/s].
    kicks: [LaneVec3; N],
}

/// Steps a run through all its substeps as `attempt` asks (its `adaptive` mask is XPBD's and
/// unused here); returns how each lane ended (the lanes that pass and are in `attempt.write`
/// are written).
#[inline(always)]
pub(crate) fn step_position_based<const N: usize>(
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
    let (substeps, h) = attempt.substeps(settings);
    let hv = Lanes::splat(h);
    let mut s = LaneState::<N> {
        positions: [LaneVec3::default(); N],
        velocities: [LaneVec3::default(); N],
        kicks: [LaneVec3::default(); N],
    };
    // Gather; the kicks hold the collision forces at first.
    gather(&state, n, &mut s.positions, &mut s.velocities, &mut s.kicks);
    // External forces held over the step, as a velocity kick: h·(m·g + m·γ·w + F_col)/m, with
    // the wind sampled once per step (not at attached roots, which the head moves).
    let gravity = step.environment.gravity;
    let drag = Lanes::splat(step.air_drag_rate);
    for i in usize::from(attached)..n {
        let c = &constants[i];
        let wind = step
            .environment
            .wind
            .velocity_at_lanes(&s.positions[i], step.time);
        let collision = s.kicks[i];
        let force = LaneVec3 {
            x: Lanes::splat(gravity.x) * c.mass + collision.x,
            y: Lanes::splat(gravity.y) * c.mass + collision.y,
            z: Lanes::splat(gravity.z) * c.mass + collision.z,
        } + wind.scale(c.mass * drag);
        s.kicks[i] = force.scale(hv * c.inverse_mass);
    }
    let mut springs = SpringScratch::<N>::new();
    let inverse_h = Lanes::splat(1.0 / h);
    let chains = (state.first_chain, state.end_chain);
    let poses = step.root_poses(chains.0, chains.1, attempt.halvings, 0);
    let (mut root_start, _) = carried_roots(roots, &poses);
    for k in 0..substeps {
        let poses = step.root_poses(chains.0, chains.1, attempt.halvings, k + 1);
        let (root_end, root_frame) = carried_roots(roots, &poses);
        let root = attached.then_some(root_end);
        substep(
            &mut s,
            &mut springs,
            constants,
            n,
            h,
            step.air_drag_rate,
            settings.follow_the_leader_damping,
            root,
            root_frame,
        );
        if attached {
            s.velocities[0] = (root_end - root_start).scale(inverse_h);
        }
        root_start = root_end;
    }
    // Check every lane and write the ones that pass.
    check_and_scatter(
        state,
        constants,
        &s.positions,
        &s.velocities,
        settings.max_speed,
        Lanes::splat(0.0),
        [None; LANES],
        attempt.write,
    )
}

/// One substep of every lane; `root_end` is where attached roots go (the caller sets their
/// velocities).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn substep<const N: usize>(
    s: &mut LaneState<N>,
    springs: &mut SpringScratch<N>,
    constants: &[LaneNode],
    n: usize,
    h: f32,
    gamma: f32,
    follow_the_leader_damping: f32,
    root_end: Option<LaneVec3>,
    root_frame: LaneFrame,
) {
    let first = usize::from(root_end.is_some());
    let hv = Lanes::splat(h);
    let drag = Lanes::splat(gamma * h);
    // 1. Prediction under the external forces: v ← v + h·(F_ext/m − γ·v), x ← x + h·v.
    for i in first..n {
        let v = s.velocities[i];
        let v = v + s.kicks[i] - v.scale(drag);
        s.velocities[i] = v;
        s.positions[i] += v.scale(hv);
    }
    if let Some(root) = root_end {
        s.positions[0] = root;
    }
    // 2. Shape target: spring forces (exact gradient of the bending energy, twist included); the
    // root bend has no spring with free roots.
    let zero = Lanes::splat(0.0);
    let (energy, weighted) = spring_forces(
        springs,
        &s.positions,
        n,
        first,
        |i| constants[i].rest_local,
        |i| {
            if i == 1 && first == 0 {
                zero
            } else {
                constants[i].stiffness
            }
        },
        |i| constants[i].inverse_mass,
        root_frame,
    );
    let mut scale = zero;
    for lane in 0..LANES {
        scale.0[lane] = shape_target_scale(energy.0[lane], weighted.0[lane], h);
    }
    // 3. The shape target's displacement, follow-the-leader with the corrections c_i, and
    // 4. v += (Δshape + c_i)/h − s·c_{i+1}/h, one node behind.
    let tolerance = Lanes::splat(LENGTH_TOLERANCE);
    let tiny = Lanes::splat(1e-12);
    let one = Lanes::splat(1.0);
    let inverse_h = Lanes::splat(1.0 / h);
    let damping = Lanes::splat(follow_the_leader_damping / h);
    // Displacement plus correction of the node before, whose velocity waits for c_i.
    let mut motion = LaneVec3::default();
    if first == 0 {
        motion = springs.forces[0].scale(scale * constants[0].inverse_mass);
        s.positions[0] += motion;
    }
    for i in 1..n {
        let c = &constants[i];
        let displacement = springs.forces[i].scale(scale * c.inverse_mass);
        let position = s.positions[i] + displacement;
        let segment = position - s.positions[i - 1];
        let length = segment.length_squared().sqrt();
        let stretched = (length - c.rest_length).abs().greater(tolerance * length);
        let apply = Lanes::select(length.greater(tiny), stretched, zero);
        let factor = Lanes::select(apply, c.rest_length / length - one, zero);
        let correction = segment.scale(factor);
        s.positions[i] = position + correction;
        if i > first {
            s.velocities[i - 1] += motion.scale(inverse_h) - correction.scale(damping);
        }
        motion = displacement + correction;
    }
    if n > first {
        s.velocities[n - 1] += motion.scale(inverse_h);
    }
}

/// The XPBD step size `1 / (Σ w|F|²/(2E) + 1/h²)` of the shape target for bending energy `E` [J],
/// `Σ w|F|²` = `weighted` [N²/kg] and substep `h` [s]; 0 where the chain is at rest (`E` ≤ 1e-30
/// J) or a value is not a number.
#[inline(always)]
pub(crate) fn shape_target_scale(energy: f32, weighted: f32, h: f32) -> f32 {
    if energy.is_nan() || energy <= 1e-30 || weighted.is_nan() || weighted <= 0.0 {
        return 0.0;
    }
    1.0 / (weighted / (2.0 * energy) + 1.0 / (h * h))
}
