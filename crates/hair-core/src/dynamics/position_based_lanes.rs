//! The position-based integrator for [`LANES`] chains at once: the step of
//! [`position_based`](crate::dynamics::integrators) with every number widened to one lane per
//! chain, in struct-of-arrays form on the stack, so that the compiler vectorises across chains.
//!
//! A batch is stepped this way when its chains have the same node count (up to
//! [`MAX_LANE_NODES`]); lanes past the batch's last chain repeat that chain and are discarded.
//! The state is gathered once per step, stepped through all substeps, checked, and scattered
//! back; a chain that fails the check (a non-finite value, an energy blow-up, or a segment turned
//! back on its parent, where the fast frame transport is undefined) is left untouched and reported,
//! and the caller redoes it with the one-chain integrator and its failure policy.

use glam::Vec3;

use crate::dynamics::constraints::LENGTH_TOLERANCE;
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::model::DynamicsModel;
use crate::dynamics::params::{RootMode, SimulationSettings};
use crate::dynamics::simulation::Environment;
use crate::frame::Frame;
use crate::transform::RigidTransform;

/// The longest chain (in nodes) the lane-parallel step takes.
pub(crate) const MAX_LANE_NODES: usize = 64;

/// What the batch step needs besides the model and the state.
pub(crate) struct BatchStep<'a> {
    pub model: &'a DynamicsModel,
    pub settings: &'a SimulationSettings,
    pub environment: &'a Environment,
    /// Head poses at the substep boundaries (`substeps + 1`).
    pub head_poses: &'a [RigidTransform],
    /// Time at the start of the step [s].
    pub time: f64,
}

/// The state of one batch: `first_chain..end_chain`, its node slices (chain-major, starting at
/// the first chain's first node).
pub(crate) struct BatchState<'a> {
    pub first_chain: usize,
    pub end_chain: usize,
    pub positions: &'a mut [Vec3],
    pub velocities: &'a mut [Vec3],
    pub collision: &'a [Vec3],
}

/// Steps a batch if it can; returns `None` when it cannot (unequal or too long chains), else a
/// bit mask of the chains (bit `c − first_chain`) that failed and were left untouched.
pub(crate) fn step_batch(step: &BatchStep, state: BatchState) -> Option<u32> {
    let rest = &step.model.rest;
    let nodes = rest.chain_node_count(state.first_chain);
    if nodes > MAX_LANE_NODES
        || (state.first_chain..state.end_chain).any(|c| rest.chain_node_count(c) != nodes)
    {
        return None;
    }
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return Some(unsafe { step_batch_avx2(step, state, nodes) });
        }
    }
    Some(step_batch_sized(step, state, nodes))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn step_batch_avx2(step: &BatchStep, state: BatchState, nodes: usize) -> u32 {
    step_batch_sized(step, state, nodes)
}

#[inline(always)]
fn step_batch_sized(step: &BatchStep, state: BatchState, nodes: usize) -> u32 {
    if nodes <= 16 {
        step_lanes::<16>(step, state, nodes)
    } else if nodes <= 32 {
        step_lanes::<32>(step, state, nodes)
    } else {
        step_lanes::<MAX_LANE_NODES>(step, state, nodes)
    }
}

/// Per-node arrays of a batch, `N` ≥ the node count.
struct LaneArrays<const N: usize> {
    positions: [LaneVec3; N],
    velocities: [LaneVec3; N],
    /// External force held over the step: `m·g + m·γ·w + F_col` [N].
    constant_forces: [LaneVec3; N],
    /// Spring forces, then the shape target's displacements [m].
    forces: [LaneVec3; N],
    /// Follow-the-leader corrections [m].
    corrections: [LaneVec3; N],
    rest_local: [LaneVec3; N],
    directions: [LaneVec3; N],
    half_binormals: [LaneVec3; N],
    masses: [Lanes; N],
    inverse_masses: [Lanes; N],
    rest_lengths: [Lanes; N],
    stiffness: [Lanes; N],
    /// `1/l` of every segment's current length [1/m].
    inverse_lengths: [Lanes; N],
    twist: [Lanes; N],
}

impl<const N: usize> LaneArrays<N> {
    fn new() -> Self {
        let v = [LaneVec3::default(); N];
        let s = [Lanes::default(); N];
        LaneArrays {
            positions: v,
            velocities: v,
            constant_forces: v,
            forces: v,
            corrections: v,
            rest_local: v,
            directions: v,
            half_binormals: v,
            masses: s,
            inverse_masses: s,
            rest_lengths: s,
            stiffness: s,
            inverse_lengths: s,
            twist: s,
        }
    }
}

/// Frames of every lane.
#[derive(Clone, Copy)]
struct LaneFrame {
    normal: LaneVec3,
    binormal: LaneVec3,
    tangent: LaneVec3,
}

#[inline(always)]
fn step_lanes<const N: usize>(step: &BatchStep, state: BatchState, n: usize) -> u32 {
    let model = step.model;
    let rest = &model.rest;
    let settings = step.settings;
    let params = &model.params;
    let chains = state.end_chain - state.first_chain;
    let attached = settings.roots == RootMode::Attached;
    let gamma = params.air_drag_rate;
    let mut a = LaneArrays::<N>::new();
    let mut root_positions = [Vec3::ZERO; LANES];
    let mut root_frames = [Frame::default(); LANES];
    // Gather (lanes past the last chain repeat it).
    for lane in 0..LANES {
        let local = lane.min(chains - 1);
        let chain = state.first_chain + local;
        let global = rest.offsets[chain] as usize;
        let node0 = local * n;
        root_positions[lane] = rest.root_positions[chain];
        root_frames[lane] = rest.root_frames[chain];
        for i in 0..n {
            let m = model.node_masses[global + i];
            a.positions[i].set(lane, state.positions[node0 + i]);
            a.velocities[i].set(lane, state.velocities[node0 + i]);
            a.constant_forces[i].set(
                lane,
                step.environment.gravity * m + state.collision[node0 + i],
            );
            a.rest_local[i].set(lane, model.rest_local_directions[global + i]);
            a.masses[i].0[lane] = m;
            a.inverse_masses[i].0[lane] = 1.0 / m;
            a.rest_lengths[i].0[lane] = rest.segment_rest_lengths[global + i];
            let free_root_bend = !attached && i == 1;
            a.stiffness[i].0[lane] = if free_root_bend {
                0.0
            } else {
                model.joint_stiffness[global + i]
            };
        }
    }
    // Drag towards the wind, sampled once per step: + m·γ·w.
    for i in 0..n {
        let wind = step
            .environment
            .wind
            .velocity_at_lanes(&a.positions[i], step.time);
        a.constant_forces[i] += wind.scale(a.masses[i] * Lanes::splat(gamma));
    }
    let substeps = settings.substeps as usize;
    let h = settings.substep();
    let mut degenerate = Lanes::splat(0.0);
    for k in 0..substeps {
        let head_start = step.head_poses[k];
        let head_end = step.head_poses[k + 1];
        let mut root_end = LaneVec3::default();
        let mut root_velocity = LaneVec3::default();
        let mut frame = LaneFrame {
            normal: LaneVec3::default(),
            binormal: LaneVec3::default(),
            tangent: LaneVec3::default(),
        };
        for lane in 0..LANES {
            let start = head_start.transform_point(root_positions[lane]);
            let end = head_end.transform_point(root_positions[lane]);
            root_end.set(lane, end);
            root_velocity.set(lane, (end - start) / h);
            let f = head_end.transform_frame(&root_frames[lane]);
            frame.normal.set(lane, f.normal);
            frame.binormal.set(lane, f.binormal);
            frame.tangent.set(lane, f.tangent);
        }
        let root = attached.then_some(root_end);
        substep(&mut a, n, h, gamma, settings, root, frame, &mut degenerate);
        if attached {
            a.velocities[0] = root_velocity;
        }
    }
    // Check every lane: finite values, kinetic energy per unit mass, transport defined.
    let mut kinetic = Lanes::splat(0.0);
    let mut mass = Lanes::splat(0.0);
    let mut finite = Lanes::splat(0.0);
    for i in 0..n {
        let (p, v) = (a.positions[i], a.velocities[i]);
        // 0 for finite values, NaN otherwise; NaN survives the sums.
        for value in [p.x, p.y, p.z, v.x, v.y, v.z] {
            finite = finite + value.nan_unless_finite();
        }
        kinetic = kinetic + a.masses[i] * v.length_squared();
        mass = mass + a.masses[i];
    }
    let limit = settings.max_speed * settings.max_speed;
    let mut failed = 0u32;
    for lane in 0..chains {
        let energy = kinetic.0[lane] / mass.0[lane].max(f32::MIN_POSITIVE);
        let ok = finite.0[lane] == 0.0 && degenerate.0[lane] == 0.0 && energy <= limit;
        if !ok {
            failed |= 1 << lane;
            continue;
        }
        let node0 = lane * n;
        for i in 0..n {
            state.positions[node0 + i] = a.positions[i].get(lane);
            state.velocities[node0 + i] = a.velocities[i].get(lane);
        }
    }
    failed
}

/// One substep of every lane; `root_end` is where attached roots go (the caller sets their
/// velocities).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn substep<const N: usize>(
    a: &mut LaneArrays<N>,
    n: usize,
    h: f32,
    gamma: f32,
    settings: &SimulationSettings,
    root_end: Option<LaneVec3>,
    root_frame: LaneFrame,
    degenerate: &mut Lanes,
) {
    let first = usize::from(root_end.is_some());
    let hv = Lanes::splat(h);
    let drag = Lanes::splat(gamma * h);
    // 1. Prediction under the external forces: v ← v + h·(F_const/m − γ·v), x ← x + h·v.
    for i in first..n {
        let v = a.velocities[i];
        let v = v + a.constant_forces[i].scale(hv * a.inverse_masses[i]) - v.scale(drag);
        a.velocities[i] = v;
        a.positions[i] += v.scale(hv);
    }
    if let Some(root) = root_end {
        a.positions[0] = root;
    }
    // 2. Shape target: spring forces (exact gradient of the bending energy, twist included).
    let energy = spring_forces(a, n, root_frame, degenerate);
    let mut weighted = Lanes::splat(0.0);
    for i in first..n {
        weighted = weighted + a.forces[i].length_squared() * a.inverse_masses[i];
    }
    let mut scale = Lanes::splat(0.0);
    for lane in 0..LANES {
        scale.0[lane] =
            crate::dynamics::integrators::shape_target_scale(energy.0[lane], weighted.0[lane], h);
    }
    for i in first..n {
        let displacement = a.forces[i].scale(scale * a.inverse_masses[i]);
        a.forces[i] = displacement;
        a.positions[i] += displacement;
    }
    // 3. Follow-the-leader, keeping the corrections.
    let tolerance = Lanes::splat(LENGTH_TOLERANCE);
    let tiny = Lanes::splat(1e-12);
    let one = Lanes::splat(1.0);
    a.corrections[0] = LaneVec3::default();
    for i in 1..n {
        let segment = a.positions[i] - a.positions[i - 1];
        let length = segment.length_squared().sqrt();
        let stretched = (length - a.rest_lengths[i])
            .abs()
            .greater(tolerance * length);
        let apply = Lanes::select(length.greater(tiny), stretched, Lanes::splat(0.0));
        let factor = Lanes::select(apply, a.rest_lengths[i] / length - one, Lanes::splat(0.0));
        let correction = segment.scale(factor);
        a.corrections[i] = correction;
        a.positions[i] += correction;
    }
    // 4. v += (Δshape + c_i)/h − s·c_{i+1}/h (see the one-chain integrator).
    let inverse_h = Lanes::splat(1.0 / h);
    let damping = Lanes::splat(settings.follow_the_leader_damping / h);
    for i in first..n {
        let next = if i + 1 < n {
            a.corrections[i + 1]
        } else {
            LaneVec3::default()
        };
        a.velocities[i] += (a.forces[i] + a.corrections[i]).scale(inverse_h) - next.scale(damping);
    }
}

/// Writes the angular spring forces [N] of every lane into `a.forces` (all nodes) and returns the
/// bending energies [J]: [`add_spring_forces`](crate::dynamics::add_spring_forces) without
/// damping, lane-wise. Lanes whose frame transport is undefined (a segment turned back on its
/// parent) are marked in `degenerate`.
#[inline(always)]
fn spring_forces<const N: usize>(
    a: &mut LaneArrays<N>,
    n: usize,
    root_frame: LaneFrame,
    degenerate: &mut Lanes,
) -> Lanes {
    let zero = Lanes::splat(0.0);
    let one = Lanes::splat(1.0);
    let half = Lanes::splat(0.5);
    let sixth = Lanes::splat(1.0 / 6.0);
    let tiny = Lanes::splat(1e-12);
    for force in &mut a.forces[..n] {
        *force = LaneVec3::default();
    }
    let mut energy = zero;
    let mut frame = root_frame;
    for i in 1..n {
        let segment = a.positions[i] - a.positions[i - 1];
        let raw_length = segment.length_squared().sqrt();
        let valid = raw_length.greater(tiny);
        let length = raw_length.max(tiny);
        let inverse_length = one / length;
        let direction = LaneVec3::select(valid, segment.scale(inverse_length), frame.tangent);
        let local = a.rest_local[i];
        let rest = frame.normal.scale(local.x)
            + frame.binormal.scale(local.y)
            + frame.tangent.scale(local.z);
        let parent_tangent = frame.tangent;
        let half_binormal = parent_tangent
            .cross(direction)
            .scale(one / (one + parent_tangent.dot(direction)).max(Lanes::splat(1e-6)));
        let k = a.stiffness[i];
        let axis = direction.cross(rest);
        let sin = axis.length_squared().sqrt();
        let cos = direction.dot(rest);
        let angle = Lanes::atan2_upper(sin, cos);
        let factor = Lanes::select(
            sin.greater(Lanes::splat(1e-3)),
            angle / sin,
            one + angle * angle * sixth,
        );
        energy = energy + half * k * angle * angle;
        a.twist[i] = parent_tangent.dot(axis) * (k * factor);
        a.half_binormals[i] = half_binormal;
        let g = (direction - rest).scale(factor * k);
        // Q·g = (g − d(d·g))/l.
        let qg = (g - direction.scale(direction.dot(g))).scale(inverse_length);
        a.forces[i] -= qg;
        if i >= 2 {
            // Sᵀ·g = d_{i−1} × (r × g)/l_{i−1}.
            let stg = a.directions[i - 1]
                .cross(rest.cross(g))
                .scale(a.inverse_lengths[i - 1]);
            a.forces[i - 1] += qg - stg;
            a.forces[i - 2] += stg;
        } else {
            a.forces[i - 1] += qg;
        }
        a.directions[i] = direction;
        a.inverse_lengths[i] = inverse_length;
        // Transport the frame to the new tangent (see `forces::transport`).
        let one_plus_cos = one + frame.tangent.dot(direction);
        *degenerate = *degenerate + Lanes::splat(1e-4).greater(one_plus_cos);
        let sum = frame.tangent + direction;
        let normal = frame.normal - sum.scale(sum.dot(frame.normal) / one_plus_cos)
            + direction.scale(Lanes::splat(2.0) * frame.tangent.dot(frame.normal));
        let normal = normal - direction.scale(direction.dot(normal));
        let normal = normal.scale(one / normal.length_squared().sqrt());
        frame = LaneFrame {
            binormal: direction.cross(normal),
            normal,
            tangent: direction,
        };
    }
    // Twist pass, tip to root (see `add_spring_forces`).
    let mut suffix = zero;
    let mut next_half_binormal = LaneVec3::default();
    for j in (1..n).rev() {
        let a_next = suffix;
        let a_here = if j + 1 < n {
            suffix + a.twist[j + 1]
        } else {
            suffix
        };
        let half_binormal = a.half_binormals[j];
        let pull = half_binormal.scale(a_here) + next_half_binormal.scale(a_next);
        let direction = a.directions[j];
        let force = (pull - direction.scale(direction.dot(pull))).scale(a.inverse_lengths[j]);
        a.forces[j] += force;
        a.forces[j - 1] -= force;
        suffix = a_here;
        next_half_binormal = half_binormal;
    }
    energy
}
