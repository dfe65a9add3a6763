//! What a lane-wise batch step is handed ([`BatchStep`], [`BatchState`]) and the head pose laid
//! on every lane's root ([`carried_roots`]): shared by the position-based and XPBD lane steps.

use glam::{Mat3, Vec3};

use crate::dynamics::environment::Environment;
use crate::dynamics::lane_model::{LaneModel, LaneRoots, rotate_lanes};
use crate::dynamics::lane_springs::LaneFrame;
use crate::dynamics::lanes::{LaneVec3, Lanes};
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
