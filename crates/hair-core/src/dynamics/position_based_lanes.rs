//! The position-based integrator for [`LANES`] chains at once: the step of
//! [`position_based`](crate::dynamics::integrators) with every number widened to one lane per
//! chain, in struct-of-arrays form on the stack, so that the compiler vectorises across chains.
//!
//! A batch is stepped this way when its chains have the same node count (2 to
//! [`MAX_LANE_NODES`]); lanes past the batch's last chain repeat that chain and are discarded.
//! The constants come laid out in lane form
//! ([`LaneModel`](crate::dynamics::lane_model::LaneModel)); the state is gathered once per step,
//! stepped through all substeps, checked, and scattered into the new state's arrays (the
//! simulation swaps them in when every chain succeeded, so nothing is copied to back it up). Per step, not per substep: the external velocity kick `h·F_ext/m`, and
//! the head's rotation matrices (the roots are rotated lane-wise). A chain that fails the check
//! (a non-finite value, an energy blow-up, or a segment turned back on its parent, where the fast
//! frame transport is undefined) is not written but reported, and the caller redoes it with the
//! one-chain integrator and its failure policy.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::constraints::LENGTH_TOLERANCE;
use crate::dynamics::integrators::shape_target_scale;
use crate::dynamics::lane_batch::{
    BatchState, BatchStep, carried_roots, check_and_scatter, gather,
};
use crate::dynamics::lane_model::{LaneNode, LaneRoots};
use crate::dynamics::lane_springs::{LaneFrame, SpringScratch, spring_forces};
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::params::{IntegratorKind, RootMode};
use crate::dynamics::xpbd_lanes::step_xpbd_lanes;

use crate::dynamics::lane_model::MAX_LANE_NODES;

/// Steps a batch if it can; returns `None` when it cannot (unequal, too short or too long
/// chains; nothing is written then), else a bit mask of the chains (bit `c − first_chain`) that
/// failed and whose new state was not written.
// The one `unsafe` of the workspace (`unsafe_code` is denied in the root Cargo.toml): calling the
// AVX2 instance after checking at run time that the CPU has AVX2.
#[allow(unsafe_code)]
pub(crate) fn step_batch(step: &BatchStep, state: BatchState) -> Option<u32> {
    let (nodes, roots) = step.lanes.batch(state.first_chain)?;
    // The XPBD lanes take attached roots only (node 0 is not an unknown of their system).
    if step.settings.integrator == IntegratorKind::Xpbd && step.settings.roots != RootMode::Attached
    {
        return None;
    }
    let xpbd = step.settings.integrator == IntegratorKind::Xpbd;
    let n = nodes.len();
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return Some(unsafe {
                match (xpbd, n <= 16, n <= 32) {
                    (true, true, _) => kernel_avx2::<16, true>(step, state, nodes, roots),
                    (true, false, true) => kernel_avx2::<32, true>(step, state, nodes, roots),
                    (true, false, false) => {
                        kernel_avx2::<MAX_LANE_NODES, true>(step, state, nodes, roots)
                    }
                    (false, true, _) => kernel_avx2::<16, false>(step, state, nodes, roots),
                    (false, false, true) => kernel_avx2::<32, false>(step, state, nodes, roots),
                    (false, false, false) => {
                        kernel_avx2::<MAX_LANE_NODES, false>(step, state, nodes, roots)
                    }
                }
            });
        }
    }
    Some(match (xpbd, n <= 16, n <= 32) {
        (true, true, _) => kernel::<16, true>(step, state, nodes, roots),
        (true, false, true) => kernel::<32, true>(step, state, nodes, roots),
        (true, false, false) => kernel::<MAX_LANE_NODES, true>(step, state, nodes, roots),
        (false, true, _) => kernel::<16, false>(step, state, nodes, roots),
        (false, false, true) => kernel::<32, false>(step, state, nodes, roots),
        (false, false, false) => kernel::<MAX_LANE_NODES, false>(step, state, nodes, roots),
    })
}

/// One instance of the batch kernels: chains of at most `N` nodes, XPBD or the position-based
/// step. Each instance is a function of its own (never inlined into [`step_batch`]), so a
/// batch's stack frame holds one instance's scratch (up to about 80 KiB of lane arrays), not
/// all six: nested rayon jobs can stack several batch frames on one worker thread, and with the
/// six instances in one frame a crowd of 100 small characters overflowed the 2 MiB worker
/// stacks.
#[inline(never)]
fn kernel<const N: usize, const XPBD: bool>(
    step: &BatchStep,
    state: BatchState,
    nodes: &[LaneNode],
    roots: &LaneRoots,
) -> u32 {
    kernel_body::<N, XPBD>(step, state, nodes, roots)
}

/// [`kernel`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline(never)]
fn kernel_avx2<const N: usize, const XPBD: bool>(
    step: &BatchStep,
    state: BatchState,
    nodes: &[LaneNode],
    roots: &LaneRoots,
) -> u32 {
    kernel_body::<N, XPBD>(step, state, nodes, roots)
}

#[inline(always)]
fn kernel_body<const N: usize, const XPBD: bool>(
    step: &BatchStep,
    state: BatchState,
    nodes: &[LaneNode],
    roots: &LaneRoots,
) -> u32 {
    if XPBD {
        step_xpbd_lanes::<N>(step, state, nodes, roots)
    } else {
        step_lanes::<N>(step, state, nodes, roots)
    }
}

/// The state of a batch, `N` ≥ the node count.
struct LaneState<const N: usize> {
    positions: [LaneVec3; N],
    velocities: [LaneVec3; N],
    /// Velocity change of the external forces over one substep, held over the step:
    /// `h·(m·g + m·γ·w + F_col)/m` [m/s].
    kicks: [LaneVec3; N],
}

#[inline(always)]
fn step_lanes<const N: usize>(
    step: &BatchStep,
    state: BatchState,
    constants: &[LaneNode],
    roots: &LaneRoots,
) -> u32 {
    let settings = step.settings;
    let n = constants.len().min(N);
    let constants = &constants[..n];
    let attached = settings.roots == RootMode::Attached;
    let substeps = settings.substeps as usize;
    let h = settings.substep();
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
    let mut degenerate = Lanes::splat(0.0);
    let inverse_h = Lanes::splat(1.0 / h);
    let (mut root_start, _) = carried_roots(roots, &step.head_poses[0], &step.head_rotations[0]);
    for k in 0..substeps {
        let (root_end, root_frame) =
            carried_roots(roots, &step.head_poses[k + 1], &step.head_rotations[k + 1]);
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
            &mut degenerate,
        );
        if attached {
            s.velocities[0] = (root_end - root_start).scale(inverse_h);
        }
        root_start = root_end;
    }
    // Check every lane (transport defined) and write the ones that pass.
    check_and_scatter(
        state,
        constants,
        &s.positions,
        &s.velocities,
        settings.max_speed,
        &[degenerate],
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
    degenerate: &mut Lanes,
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
        degenerate,
    );
    let mut scale = zero;
    for lane in 0..LANES {
        scale.0[lane] = shape_target_scale(energy.0[lane], weighted.0[lane], h);
    }
    // 3. The shape target's displacement, follow-the-leader with the corrections c_i, and
    // 4. v += (Δshape + c_i)/h − s·c_{i+1}/h (see the one-chain integrator), one node behind.
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
