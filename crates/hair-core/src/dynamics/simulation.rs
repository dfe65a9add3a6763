//! The simulation: a model, settings and solver scratch that advance a [`SimulationState`] one
//! step at a time, in parallel over chains, detecting failures.

use glam::{Mat3, Vec3, Vec4};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::dynamics::chain_step::step_chain;
use crate::dynamics::error::{ChainFailure, DynamicsError};
use crate::dynamics::integrators::ChainConstants;
use crate::dynamics::lane_batch::BatchStep;
use crate::dynamics::lane_model::LaneModel;
use crate::dynamics::lane_step::{RunState, step_run_with_retries};
use crate::dynamics::model::DynamicsModel;
use crate::dynamics::parallel::{ChainSlices, ChainWork, for_each_batch, for_each_chain};
use crate::dynamics::params::{IntegratorKind, SimulationSettings};
use crate::dynamics::root_motion::{RootCarrier, RootPoses};
use crate::dynamics::state::SimulationState;
use crate::transform::RigidTransform;

pub use super::environment::Environment;

/// What one step did.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct StepReport {
    /// Number of chains whose substep had to be halved at least once: after a failure (with
    /// [`FailurePolicy::HalveSubstep`]), or, with the XPBD integrator, because a substep was too
    /// long for the chain's motion (its adaptive substeps, whatever the failure policy).
    pub halved_chains: usize,
    /// The most halvings any chain needed.
    pub max_halvings: u32,
    /// The most substeps a chain's step started with: [`SimulationSettings::substeps`], or more
    /// where [`SimulationSettings::adaptive`] asked for them (halvings after a failure or a too
    /// long move not counted).
    pub substeps: u32,
}

/// Per-node and per-chain scratch, allocated once (never inside a step).
#[derive(Debug, Default)]
struct Scratch {
    wind: Vec<Vec3>,
    forces: Vec<Vec3>,
    corrections: Vec<Vec3>,
    work: Vec<Vec4>,
    backup_positions: Vec<Vec3>,
    backup_velocities: Vec<Vec3>,
    diagonal: Vec<Mat3>,
    first: Vec<Mat3>,
    second: Vec<Mat3>,
    rhs: Vec<Vec3>,
    failures: Vec<Option<ChainFailure>>,
    halvings: Vec<u32>,
    /// Head poses at the substep boundaries of the current step (`substeps + 1`).
    head_poses: Vec<RigidTransform>,
    /// Their rotations as matrices.
    head_rotations: Vec<Mat3>,
    /// With a root carrier: each chain's root poses at the substep boundaries, chain after chain
    /// (`substeps + 1` each); empty without one.
    chain_poses: Vec<RigidTransform>,
    /// Their rotations as matrices.
    chain_rotations: Vec<Mat3>,
    /// With a root carrier: the body's samples around each substep boundary
    /// ([`crate::MeshSequence::bracket`]), shared by the chains.
    boundary_samples: Vec<(usize, usize, f32)>,
}

/// A skeleton simulation: the model, its settings and the solver's scratch.
#[derive(Debug)]
pub struct Simulation {
    model: DynamicsModel,
    settings: SimulationSettings,
    scratch: Scratch,
    /// The model's constants in lane form for the position-based and XPBD steps (laid out when
    /// the settings first ask for one of them).
    lane_model: Option<LaneModel>,
    /// What carries the roots besides the head (a deforming body), if anything.
    carrier: Option<RootCarrier>,
    /// Each node's `1 / l` for its segment's rest length `l` [1/m] (0 at roots), which the
    /// adaptive substeps read.
    inverse_lengths: Vec<f32>,
}

impl Simulation {
    /// A simulation of `model` with `settings` (validated); allocates all scratch.
    pub fn new(model: DynamicsModel, settings: SimulationSettings) -> Result<Self, DynamicsError> {
        let mut simulation = Simulation {
            model,
            settings,
            scratch: Scratch::default(),
            lane_model: None,
            carrier: None,
            inverse_lengths: Vec::new(),
        };
        simulation.inverse_lengths = simulation
            .model
            .rest
            .segment_rest_lengths
            .iter()
            .map(|&length| if length > 0.0 { 1.0 / length } else { 0.0 })
            .collect();
        simulation.set_settings(settings)?;
        Ok(simulation)
    }

    /// The model.
    pub fn model(&self) -> &DynamicsModel {
        &self.model
    }

    /// The settings.
    pub fn settings(&self) -> &SimulationSettings {
        &self.settings
    }

    /// Changes the settings (integrator, step, …), reallocating scratch as needed. Fails,
    /// changing nothing, on a setting out of range, or for the position-based and XPBD
    /// integrators on a chain of more than [`MAX_CHAIN_NODES`](crate::dynamics::MAX_CHAIN_NODES)
    /// nodes ([`DynamicsError::ChainTooLong`]).
    pub fn set_settings(&mut self, settings: SimulationSettings) -> Result<(), DynamicsError> {
        settings.validate()?;
        if settings.integrator.steps_lanes() && self.lane_model.is_none() {
            self.lane_model = Some(LaneModel::new(&self.model, settings.integrator)?);
        }
        self.settings = settings;
        let nodes = self.model.node_count();
        let chains = self.model.chain_count();
        let scratch = &mut self.scratch;
        scratch.wind.resize(nodes, Vec3::ZERO);
        scratch.forces.resize(nodes, Vec3::ZERO);
        scratch.corrections.resize(nodes, Vec3::ZERO);
        scratch.work.resize(nodes, Vec4::ZERO);
        scratch.backup_positions.resize(nodes, Vec3::ZERO);
        scratch.backup_velocities.resize(nodes, Vec3::ZERO);
        let implicit_nodes = if settings.integrator == IntegratorKind::LinearImplicit {
            nodes
        } else {
            0
        };
        for blocks in [
            &mut scratch.diagonal,
            &mut scratch.first,
            &mut scratch.second,
        ] {
            blocks.resize(implicit_nodes, Mat3::ZERO);
            blocks.shrink_to_fit();
        }
        scratch.rhs.resize(implicit_nodes, Vec3::ZERO);
        scratch.failures.resize(chains, None);
        scratch.halvings.resize(chains, 0);
        scratch
            .head_poses
            .resize(settings.substeps as usize + 1, RigidTransform::IDENTITY);
        scratch
            .head_rotations
            .resize(settings.substeps as usize + 1, Mat3::IDENTITY);
        self.resize_chain_poses();
        Ok(())
    }

    /// Lets `carrier` carry the roots besides the head: each chain's root, root frame and rest
    /// directions ride its body's triangle ([`DeformingBody::carry`]), and the head's motion is
    /// applied after it. `None`: the head alone. Fails, changing nothing, when the carrier has
    /// not one attachment per chain or names a triangle its body lacks.
    ///
    /// [`DeformingBody::carry`]: crate::dynamics::DeformingBody::carry
    pub fn set_root_carrier(&mut self, carrier: Option<RootCarrier>) -> Result<(), DynamicsError> {
        if let Some(carrier) = &carrier {
            carrier.validate(self.model.chain_count())?;
        }
        self.carrier = carrier;
        self.resize_chain_poses();
        Ok(())
    }

    /// The root carrier, if any.
    pub fn root_carrier(&self) -> Option<&RootCarrier> {
        self.carrier.as_ref()
    }

    /// Takes the root carrier out: the head alone carries the roots until one is set again.
    /// The carrier's scratch is kept for its return, so taking it out and setting it back
    /// allocates nothing.
    pub fn take_root_carrier(&mut self) -> Option<RootCarrier> {
        self.carrier.take()
    }

    fn resize_chain_poses(&mut self) {
        let count = match self.carrier {
            Some(_) => self.model.chain_count() * (self.settings.substeps as usize + 1),
            None => 0,
        };
        let scratch = &mut self.scratch;
        scratch.chain_poses.resize(count, RigidTransform::IDENTITY);
        scratch.chain_rotations.resize(count, Mat3::IDENTITY);
        scratch.chain_poses.shrink_to_fit();
        scratch.chain_rotations.shrink_to_fit();
    }

    /// Chain `chain`'s root pose at `time` [s]: the head's, after the carrier's where there is
    /// one.
    pub fn root_pose(&self, chain: usize, environment: &Environment, time: f64) -> RigidTransform {
        match &self.carrier {
            None => environment.head.transform_at(time),
            Some(carrier) => carrier.pose(chain, &environment.head, time),
        }
    }

    /// A state at rest in the rest shape with the head posed as `environment.head` at `time` [s]
    /// (each chain carried by the root carrier too, where there is one).
    pub fn rest_state(&self, environment: &Environment, time: f64) -> SimulationState {
        let rest = &self.model.rest;
        let mut state = SimulationState::at_rest(rest, &environment.head.transform_at(time), time);
        if self.carrier.is_some() {
            for chain in 0..rest.chain_count() {
                let pose = self.root_pose(chain, environment, time);
                rest.rest_positions_of(chain, &pose, &mut state.node_positions[rest.nodes(chain)]);
            }
        }
        state
    }

    fn check_state(&self, state: &SimulationState) -> Result<(), DynamicsError> {
        let expected = self.model.node_count();
        for (what, actual) in [
            ("node_positions", state.node_positions.len()),
            ("node_velocities", state.node_velocities.len()),
            ("collision_forces", state.collision_forces.len()),
        ] {
            if actual != expected {
                return Err(DynamicsError::StateMismatch {
                    what,
                    actual,
                    expected,
                });
            }
        }
        Ok(())
    }

    /// Advances `state` by one step of `settings.time_step` seconds (in `settings.substeps`
    /// substeps, more for a chain whose nodes move fast where `settings.adaptive` asks; in
    /// parallel over chains; the result does not depend on the thread count).
    ///
    /// After each chain's step its positions and velocities are checked: a non-finite value or a
    /// kinetic energy per unit mass above `½·max_speed²` is a failure. With
    /// [`FailurePolicy::HalveSubstep`] the chain's step is redone from its start with half the
    /// substep, up to the limit. The position-based and XPBD integrators step chains in runs
    /// of up to eight through their lane kernels, the others one chain at a time. The XPBD
    /// integrator also redoes a chain's step with half the
    /// substep where a first Newton step moves a node by more than two segment lengths (the
    /// substep is too long for that chain's motion), up to five times and while halving shortens
    /// that move, whatever the policy. A failure that remains restores the whole state to its value
    /// before the step and returns [`DynamicsError::Unstable`] for the lowest failing chain.
    pub fn step(
        &mut self,
        state: &mut SimulationState,
        environment: &Environment,
    ) -> Result<StepReport, DynamicsError> {
        self.check_state(state)?;
        let settings = self.settings;
        let most_doublings = self.seed_doublings(state);
        let substeps = settings.substeps as usize;
        let h = settings.substep();
        for (k, pose) in self.scratch.head_poses.iter_mut().enumerate() {
            *pose = environment
                .head
                .transform_at(state.time + (k as f64) * h as f64);
        }
        debug_assert_eq!(self.scratch.head_poses.len(), substeps + 1);
        for (rotation, pose) in self
            .scratch
            .head_rotations
            .iter_mut()
            .zip(&self.scratch.head_poses)
        {
            *rotation = Mat3::from_quat(pose.rotation);
        }
        if let Some(carrier) = &self.carrier {
            // Each chain's root poses: the head's after the body's carry, at every boundary.
            let stride = substeps + 1;
            let start = state.time;
            let samples = &mut self.scratch.boundary_samples;
            samples.clear();
            samples.extend((0..stride).map(|k| {
                let time = start + (k as f64) * h as f64;
                carrier.body.sequence().bracket(time)
            }));
            let (head_poses, samples) = (&self.scratch.head_poses, &self.scratch.boundary_samples);
            self.scratch
                .chain_poses
                .par_chunks_mut(stride)
                .zip(self.scratch.chain_rotations.par_chunks_mut(stride))
                .enumerate()
                .for_each(|(chain, (poses, rotations))| {
                    let attachment = &carrier.attachments[chain];
                    for k in 0..stride {
                        let carried = carrier.body.carry_between(attachment, samples[k]);
                        let pose = head_poses[k].after(&carried);
                        poses[k] = pose;
                        rotations[k] = Mat3::from_quat(pose.rotation);
                    }
                });
        }
        let scratch = &mut self.scratch;
        let roots = RootPoses {
            head: &scratch.head_poses,
            head_rotations: &scratch.head_rotations,
            chains: &scratch.chain_poses,
            chain_rotations: &scratch.chain_rotations,
            carrier: self.carrier.as_ref(),
            head_motion: &environment.head,
            time: state.time,
            time_step: settings.time_step,
            substeps: settings.substeps,
        };
        let model = &self.model;
        let time = state.time;
        let slices = ChainSlices {
            first_chain: 0,
            positions: &mut state.node_positions,
            velocities: &mut state.node_velocities,
            collision: &state.collision_forces,
            wind: &mut scratch.wind,
            forces: &mut scratch.forces,
            corrections: &mut scratch.corrections,
            work: &mut scratch.work,
            backup_positions: &mut scratch.backup_positions,
            backup_velocities: &mut scratch.backup_velocities,
            diagonal: &mut scratch.diagonal,
            first: &mut scratch.first,
            second: &mut scratch.second,
            rhs: &mut scratch.rhs,
            failures: &mut scratch.failures,
            halvings: &mut scratch.halvings,
        };
        let step_one_chain = |chain: usize, chain_slices: ChainWork<'_>| {
            let constants = ChainConstants {
                masses: &model.node_masses[model.rest.nodes(chain)],
                rest_lengths: &model.rest.segment_rest_lengths[model.rest.nodes(chain)],
                stiffness: &model.joint_stiffness[model.rest.nodes(chain)],
                rest_local: &model.rest_local_directions[model.rest.nodes(chain)],
                root_position: model.rest.root_positions[chain],
                root_frame: model.rest.root_frames[chain],
            };
            let (failure, halvings) = step_chain(
                chain,
                &constants,
                chain_slices.arrays,
                chain_slices.backup_positions,
                chain_slices.backup_velocities,
                &settings,
                &model.params,
                environment,
                &roots,
                time,
                *chain_slices.halvings,
            );
            *chain_slices.failure = failure;
            *chain_slices.halvings = halvings;
        };
        let lane_model = self
            .lane_model
            .as_ref()
            .filter(|_| settings.integrator.steps_lanes());
        let double_buffered = lane_model.is_some();
        if let Some(lane_model) = lane_model {
            // The state stays as it was; the new one is written to the backup arrays and swapped
            // in below when every chain succeeded (so nothing is copied to back it up).
            let batch_step = BatchStep {
                settings: &settings,
                environment,
                roots,
                air_drag_rate: model.params.air_drag_rate,
                bending_damping: model.params.bending_damping,
                time,
            };
            let offsets = &model.rest.offsets;
            for_each_batch(
                offsets,
                slices,
                &|first_chain, _end_chain, batch: ChainSlices<'_>| {
                    let base = offsets[first_chain] as usize;
                    for run in lane_model.runs(first_chain) {
                        let nodes = offsets[run.first_chain] as usize - base
                            ..offsets[run.end_chain] as usize - base;
                        let chains = run.first_chain - first_chain..run.end_chain - first_chain;
                        step_run_with_retries(
                            &batch_step,
                            &run,
                            RunState {
                                positions: &batch.positions[nodes.clone()],
                                velocities: &batch.velocities[nodes.clone()],
                                collision: &batch.collision[nodes.clone()],
                                new_positions: &mut batch.backup_positions[nodes.clone()],
                                new_velocities: &mut batch.backup_velocities[nodes],
                                failures: &mut batch.failures[chains.clone()],
                                halvings: &mut batch.halvings[chains],
                            },
                        );
                    }
                },
            );
        } else {
            for_each_chain(&model.rest.offsets, slices, &step_one_chain);
        }
        if let Some(failure) = scratch.failures.iter().flatten().next() {
            let failure = *failure;
            if !double_buffered {
                state
                    .node_positions
                    .copy_from_slice(&scratch.backup_positions);
                state
                    .node_velocities
                    .copy_from_slice(&scratch.backup_velocities);
            }
            return Err(DynamicsError::Unstable(failure));
        }
        if double_buffered {
            std::mem::swap(&mut state.node_positions, &mut scratch.backup_positions);
            std::mem::swap(&mut state.node_velocities, &mut scratch.backup_velocities);
        }
        state.time += settings.time_step as f64;
        let mut report = StepReport {
            substeps: settings.substeps << most_doublings,
            ..StepReport::default()
        };
        for &halvings in &scratch.halvings {
            report.halved_chains += usize::from(halvings > 0);
            report.max_halvings = report.max_halvings.max(halvings);
        }
        Ok(report)
    }

    /// Chain `chain`'s fastest node's speed relative to the chain's root, in rest lengths of its
    /// segment per second [1/s]: what [`SimulationSettings::adaptive`] measures at a step's start.
    /// `None` for a chain the model lacks or a state of another node count.
    pub fn relative_speed(&self, state: &SimulationState, chain: usize) -> Option<f32> {
        let fits = chain < self.model.chain_count()
            && state.node_velocities.len() == self.model.node_count();
        fits.then(|| {
            chain_relative_speed(
                &self.model.rest,
                &self.inverse_lengths,
                &state.node_velocities,
                chain,
            )
        })
    }

    /// Writes each chain's adaptive doublings for this step into the halvings scratch (the
    /// steps start there; zeros without adaptive substeps) and returns the most of them.
    fn seed_doublings(&mut self, state: &SimulationState) -> u32 {
        let seeds = &mut self.scratch.halvings;
        let Some(adaptive) = self.settings.adaptive else {
            seeds.fill(0);
            return 0;
        };
        let (time_step, substeps) = (self.settings.time_step, self.settings.substeps);
        let (rest, inverse) = (&self.model.rest, &self.inverse_lengths);
        // A task takes 512 chains (about 7,000 nodes, a few microseconds), so a small model is
        // measured on one thread.
        seeds
            .par_iter_mut()
            .with_min_len(512)
            .enumerate()
            .for_each(|(chain, seed)| {
                let speed = chain_relative_speed(rest, inverse, &state.node_velocities, chain);
                *seed = adaptive.doublings(time_step, substeps, speed);
            });
        seeds.iter().copied().max().unwrap_or(0)
    }

    /// Runs `steps` steps, stopping at the first error.
    pub fn run(
        &mut self,
        state: &mut SimulationState,
        environment: &Environment,
        steps: usize,
    ) -> Result<(), DynamicsError> {
        for _ in 0..steps {
            self.step(state, environment)?;
        }
        Ok(())
    }
}

/// Chain `chain`'s fastest node's speed relative to its root over its segment's rest length
/// [1/s] (`inverse`: each node's `1 / l`, 0 at roots). Squared until the end: one square root.
fn chain_relative_speed(
    rest: &crate::skeleton::SkeletonRest,
    inverse: &[f32],
    velocities: &[Vec3],
    chain: usize,
) -> f32 {
    let nodes = rest.nodes(chain);
    let root = velocities[nodes.start];
    nodes
        .fold(0.0f32, |fastest, node| {
            let inverse = inverse[node];
            fastest.max((velocities[node] - root).length_squared() * (inverse * inverse))
        })
        .sqrt()
}
