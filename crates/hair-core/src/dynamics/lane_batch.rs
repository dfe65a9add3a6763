//! What a lane-wise run step is handed ([`BatchStep`], [`BatchState`], [`Attempt`]) and what it
//! returns ([`LaneOutcome`]), the head pose laid on every lane's root ([`carried_roots`]), and the
//! state gathered into lanes ([`gather`]) and checked and written back ([`check_and_scatter`]):
//! shared by the position-based and XPBD lane steps.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use glam::{Mat3, Vec3};

use crate::dynamics::environment::Environment;
use crate::dynamics::error::FailedQuantity;
use crate::dynamics::head_motion::angular_velocity;
use crate::dynamics::lane_model::LaneNode;
use crate::dynamics::lane_model::{LaneRoots, rotate_lanes};
use crate::dynamics::lane_springs::LaneFrame;
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::params::SimulationSettings;
use crate::dynamics::root_motion::RootPoses;
use crate::transform::RigidTransform;

/// What the batch step needs besides the state.
pub(crate) struct BatchStep<'a> {
    pub settings: &'a SimulationSettings,
    pub environment: &'a Environment,
    /// The roots' poses at the substep boundaries: the head's, or each chain's own.
    pub roots: RootPoses<'a>,
    /// Air drag rate γ [1/s].
    pub air_drag_rate: f32,
    /// Spring damping β [s] (the XPBD step's damping sweep).
    pub bending_damping: f32,
    /// Time at the start of the step [s].
    pub time: f64,
}

impl BatchStep<'_> {
    /// The root poses of chains `first_chain..end_chain` (one per lane; lanes past the last
    /// chain repeat it) at substep boundary `k` of a step split into `substeps << halvings`
    /// substeps ([`RootPoses::pose`]): one shared pose without a carrier.
    #[inline]
    pub(crate) fn root_poses(
        &self,
        first_chain: usize,
        end_chain: usize,
        halvings: u32,
        k: usize,
    ) -> LanePoses {
        if self.roots.shared() {
            let (pose, rotation) = self.roots.pose(first_chain, halvings, k);
            return LanePoses::Shared(pose, rotation);
        }
        let mut poses = [RigidTransform::IDENTITY; LANES];
        let mut rotations = [Mat3::IDENTITY; LANES];
        for lane in 0..LANES {
            let chain = (first_chain + lane).min(end_chain - 1);
            (poses[lane], rotations[lane]) = self.roots.pose(chain, halvings, k);
        }
        LanePoses::PerLane(poses, rotations)
    }
}

/// The root poses of a run's lanes at one substep boundary: one for every lane (the head's), or
/// one per lane (a deforming body's carry after the head's).
#[derive(Debug, Clone, Copy)]
// Lives on the lane kernels' stack: boxing the large variant would allocate every substep.
#[allow(clippy::large_enum_variant)]
pub(crate) enum LanePoses {
    /// Every lane's, with its rotation matrix.
    Shared(RigidTransform, Mat3),
    /// Each lane's, with their rotation matrices.
    PerLane([RigidTransform; LANES], [Mat3; LANES]),
}

impl LanePoses {
    /// The roots' angular velocity [rad/s] per lane from `self` to `end` over `h` [s]
    /// ([`angular_velocity`]).
    #[inline]
    pub(crate) fn spin_to(&self, end: &LanePoses, h: f32) -> LaneVec3 {
        match (self, end) {
            (LanePoses::Shared(start, _), LanePoses::Shared(end, _)) => {
                LaneVec3::splat(angular_velocity(start.rotation, end.rotation, h))
            }
            _ => {
                let mut spin = LaneVec3::default();
                for lane in 0..LANES {
                    let w = angular_velocity(self.lane(lane).rotation, end.lane(lane).rotation, h);
                    spin.set(lane, w);
                }
                spin
            }
        }
    }

    /// Lane `lane`'s pose.
    #[inline]
    fn lane(&self, lane: usize) -> RigidTransform {
        match self {
            LanePoses::Shared(pose, _) => *pose,
            LanePoses::PerLane(poses, _) => poses[lane],
        }
    }
}

/// One try at a run's step: the substep is halved `halvings` times (the step takes
/// `substeps << halvings` substeps); XPBD's too-long check runs in the lanes of `adaptive`
/// (1.0 / 0.0); the lanes of `write` (bit `lane`) that pass are written into the new state.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Attempt {
    pub halvings: u32,
    pub adaptive: Lanes,
    pub write: u32,
}

impl Attempt {
    /// The substeps of this try, `substeps << halvings`, and their length [s].
    #[inline]
    pub(crate) fn substeps(&self, settings: &SimulationSettings) -> (usize, f32) {
        substeps_halved(settings, self.halvings)
    }
}

/// The substeps of a step whose substep is halved `halvings` times, `substeps << halvings`, and
/// their length [s].
#[inline]
pub(crate) fn substeps_halved(settings: &SimulationSettings, halvings: u32) -> (usize, f32) {
    let substeps = (settings.substeps as usize) << halvings;
    (substeps, settings.time_step / substeps as f32)
}

/// How a failing lane failed: the quantity and, where one node is to blame, that node.
pub(crate) type LaneFailure = (FailedQuantity, Option<usize>);

/// How each lane of a run's try ended (lanes past the run's last chain are `None`).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LaneOutcome {
    /// The lanes that failed the check (their new state is not written).
    pub failures: [Option<LaneFailure>; LANES],
    /// The lanes whose first Newton move of some substep was too long (XPBD's adaptive substeps),
    /// with that move over its segment; their new state is not written either.
    pub too_long: [Option<f32>; LANES],
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

/// The lanes' root poses applied to their rest roots: position [m] and frame.
#[inline(always)]
pub(crate) fn carried_roots(roots: &LaneRoots, poses: &LanePoses) -> (LaneVec3, LaneFrame) {
    let (pose, rotation) = match poses {
        LanePoses::Shared(pose, rotation) => (pose, rotation),
        LanePoses::PerLane(poses, rotations) => {
            let mut position = LaneVec3::default();
            let mut frame = LaneFrame {
                normal: LaneVec3::default(),
                binormal: LaneVec3::default(),
                tangent: LaneVec3::default(),
            };
            for lane in 0..LANES {
                let (pose, rotation) = (&poses[lane], &rotations[lane]);
                position.set(
                    lane,
                    *rotation * roots.position.get(lane) + pose.translation,
                );
                frame.normal.set(lane, *rotation * roots.normal.get(lane));
                frame
                    .binormal
                    .set(lane, *rotation * roots.binormal.get(lane));
                frame.tangent.set(lane, *rotation * roots.tangent.get(lane));
            }
            return (position, frame);
        }
    };
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
/// `½·Σm·v²/Σm` at most `½·max_speed²` [J/kg], 0 in the lane mask `unsolved`, not `too_long`),
/// writes the chains that pass and are in `write` (bit `c − first_chain`) into the new state
/// (nodes `0..constants.len()`), and returns how the lanes ended.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn check_and_scatter<const N: usize>(
    state: BatchState,
    constants: &[LaneNode],
    positions: &[LaneVec3; N],
    velocities: &[LaneVec3; N],
    max_speed: f32,
    unsolved: Lanes,
    too_long: [Option<f32>; LANES],
    write: u32,
) -> LaneOutcome {
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
    let mut outcome = LaneOutcome {
        too_long,
        ..LaneOutcome::default()
    };
    for lane in 0..chains {
        if too_long[lane].is_some() {
            continue;
        }
        let energy = kinetic.0[lane] / mass.0[lane].max(f32::MIN_POSITIVE);
        let failure = if unsolved.0[lane] != 0.0 {
            Some((FailedQuantity::NonFiniteVelocity, None))
        } else if finite.0[lane] != 0.0 {
            let node_of =
                |values: &[LaneVec3; N]| (0..n).find(|&i| !values[i].get(lane).is_finite());
            Some(match node_of(positions) {
                Some(node) => (FailedQuantity::NonFinitePosition, Some(node)),
                None => (FailedQuantity::NonFiniteVelocity, node_of(velocities)),
            })
        } else if energy.is_nan() || energy > limit {
            Some((
                FailedQuantity::EnergyBlowUp {
                    energy_per_mass: 0.5 * energy,
                    limit: 0.5 * limit,
                },
                None,
            ))
        } else {
            None
        };
        outcome.failures[lane] = failure;
        if failure.is_some() || write & (1 << lane) == 0 {
            continue;
        }
        let node0 = lane * n;
        for i in 0..n {
            state.new_positions[node0 + i] = positions[i].get(lane);
            state.new_velocities[node0 + i] = velocities[i].get(lane);
        }
    }
    outcome
}
