//! What a lane-wise batch step is handed ([`BatchStep`], [`BatchState`]), the head pose laid
//! on every lane's root ([`carried_roots`]), and the state gathered into lanes ([`gather`]) and
//! checked and written back ([`check_and_scatter`]): shared by the position-based and XPBD lane
//! steps.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use glam::{Mat3, Vec3};

use crate::dynamics::environment::Environment;
use crate::dynamics::lane_model::LaneNode;
use crate::dynamics::lane_model::{LaneModel, LaneRoots, rotate_lanes};
use crate::dynamics::lane_springs::LaneFrame;
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::params::SimulationSettings;
use crate::transform::RigidTransform;

/// What the batch step needs besides the state.
pub(crate) struct BatchStep<'a> {
    pub lanes: &'a LaneModel,
    pub settings: &'a SimulationSettings,
    pub environment: &'a Environment,
    /// Head poses at the substep boundaries (`substeps + 1`).
    pub head_poses: &'a [RigidTransform],
    /// Their rotations as matrices.
    pub head_rotations: &'a [Mat3],
    /// Air drag rate γ [1/s].
    pub air_drag_rate: f32,
    /// Spring damping β [s] (the XPBD step's damping sweep).
    pub bending_damping: f32,
    /// Time at the start of the step [s].
    pub time: f64,
}

/// The state of one batch: `first_chain..end_chain`, its node slices (chain-major, starting at
/// the first chain's first node) at the step's start, and where the new state goes (same
/// length).
pub(crate) struct BatchState<'a> {
    pub first_chain: usize,
    pub end_chain: usize,
    pub positions: &'a [Vec3],
    pub velocities: &'a [Vec3],
    pub collision: &'a [Vec3],
    pub new_positions: &'a mut [Vec3],
    pub new_velocities: &'a mut [Vec3],
}

/// A head pose applied to every lane's root: position [m] and frame.
#[inline(always)]
pub(crate) fn carried_roots(
    roots: &LaneRoots,
    pose: &RigidTransform,
    rotation: &Mat3,
) -> (LaneVec3, LaneFrame) {
    let t = pose.translation;
    let position = rotate_lanes(rotation, &roots.position)
        + LaneVec3 {
            x: Lanes::splat(t.x),
            y: Lanes::splat(t.y),
            z: Lanes::splat(t.z),
        };
    let frame = LaneFrame {
        normal: rotate_lanes(rotation, &roots.normal),
        binormal: rotate_lanes(rotation, &roots.binormal),
        tangent: rotate_lanes(rotation, &roots.tangent),
    };
    (position, frame)
}

/// Gathers a batch's state into lane form: positions, velocities and collision forces of nodes
/// `0..n` of every chain (lanes past the batch's last chain repeat it).
#[inline(always)]
pub(crate) fn gather<const N: usize>(
    state: &BatchState,
    n: usize,
    positions: &mut [LaneVec3; N],
    velocities: &mut [LaneVec3; N],
    collision: &mut [LaneVec3; N],
) {
    let chains = state.end_chain - state.first_chain;
    for lane in 0..LANES {
        let node0 = lane.min(chains - 1) * n;
        for i in 0..n {
            positions[i].set(lane, state.positions[node0 + i]);
            velocities[i].set(lane, state.velocities[node0 + i]);
            collision[i].set(lane, state.collision[node0 + i]);
        }
    }
}

/// Checks every chain's lane after a step (finite values, kinetic energy per unit mass
/// `Σm·v²/(2·Σm)` at most `½·max_speed²` [m/s], 0 in every lane mask of `failures`) and writes
/// the chains that pass into the new state (nodes `0..constants.len()`); returns the bit mask of
/// the chains (bit `c − first_chain`) that failed and whose new state was not written.
#[inline(always)]
pub(crate) fn check_and_scatter<const N: usize>(
    state: BatchState,
    constants: &[LaneNode],
    positions: &[LaneVec3; N],
    velocities: &[LaneVec3; N],
    max_speed: f32,
    failures: &[Lanes],
) -> u32 {
    let n = constants.len();
    let chains = state.end_chain - state.first_chain;
    let mut kinetic = Lanes::splat(0.0);
    let mut mass = Lanes::splat(0.0);
    let mut finite = Lanes::splat(0.0);
    for i in 0..n {
        let (p, v) = (positions[i], velocities[i]);
        // 0 for finite values, NaN otherwise; NaN survives the sums.
        for value in [p.x, p.y, p.z, v.x, v.y, v.z] {
            finite = finite + value.nan_unless_finite();
        }
        kinetic = kinetic + constants[i].mass * v.length_squared();
        mass = mass + constants[i].mass;
    }
    let limit = max_speed * max_speed;
    let mut failed = 0u32;
    for lane in 0..chains {
        let energy = kinetic.0[lane] / mass.0[lane].max(f32::MIN_POSITIVE);
        let ok = finite.0[lane] == 0.0
            && failures.iter().all(|mask| mask.0[lane] == 0.0)
            && energy <= limit;
        if !ok {
            failed |= 1 << lane;
            continue;
        }
        let node0 = lane * n;
        for i in 0..n {
            state.new_positions[node0 + i] = positions[i].get(lane);
            state.new_velocities[node0 + i] = velocities[i].get(lane);
        }
    }
    failed
}
