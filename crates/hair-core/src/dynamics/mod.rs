//! Skeleton dynamics (§4.1): angular springs, gravity, wind, damping and collision forces on the
//! base skeleton's nodes, roots carried by the moving head, fixed segment lengths, and four
//! integrators (semi-implicit Euler, position-based, linear-implicit, XPBD) with failure detection.
//!
//! - [`DynamicsModel`]: per-node masses, spring stiffnesses and rest directions from a
//!   [`SkeletonRest`](crate::SkeletonRest) and [`DynamicsParams`];
//! - [`SimulationState`]: positions, velocities, time and the collision force slot;
//! - [`Environment`]: head motion ([`HeadMotion`]), wind ([`WindField`]), gravity;
//! - [`Simulation`]: settings ([`SimulationSettings`], [`IntegratorKind`]) and scratch;
//!   [`Simulation::step`] advances a state, in parallel over chains, and returns
//!   [`DynamicsError::Unstable`] (or halves the substep) when a chain blows up;
//! - [`level_skeletons`], [`strand_skeletons`]: models of one level of a groom, or of every strand;
//! - [`make_sag_free`]: natural spring angles that make a rest shape an equilibrium under gravity;
//! - [`stability`]: the stability sweep behind `hairlod stability`.
//!
//! ```
//! use hair_core::dynamics::*;
//! use hair_core::{Frame, HairStyle, SkeletonRest};
//! use glam::Vec3;
//!
//! let style = HairStyle::curly(50.0, 0.01, 0.02);
//! let mut rest = SkeletonRest::default();
//! let root_frame = Frame::from_tangent_and_normal(Vec3::Z, Vec3::Y).unwrap();
//! rest.push_chain(Vec3::new(0.0, 0.1, 0.1), root_frame, &style.chain_angles(0.2)?)?;
//! let model = DynamicsModel::new(rest, DynamicsParams::for_style(&style))?;
//! let settings = SimulationSettings::recommended(IntegratorKind::PositionBased);
//! let mut simulation = Simulation::new(model, settings)?;
//! let environment = Environment::default();
//! let mut state = simulation.rest_state(&environment, 0.0);
//! simulation.run(&mut state, &environment, 30)?; // half a second at 60 Hz
//! assert!(state.max_length_error(&simulation.model().rest) < 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod banded;
mod chain_step;
mod constraints;
mod environment;
mod error;
mod forces;
mod head_motion;
mod integrator_kind;
mod integrators;
mod lane_batch;
mod lane_blocks;
mod lane_damping;
mod lane_lengths;
mod lane_model;
mod lane_springs;
mod lane_step;
mod lane_xpbd_system;
mod lanes;
mod model;
mod parallel;
mod params;
mod position_based;
mod root_motion;
mod sag_free;
mod simulation;
pub mod stability;
mod state;
mod strands;
mod twisted_cg;
mod wind;
mod xpbd;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_adaptive;
#[cfg(test)]
mod tests_lanes;
#[cfg(test)]
pub(crate) mod tests_root_motion;
#[cfg(test)]
mod tests_sag_free;
#[cfg(test)]
mod tests_stability;
#[cfg(test)]
mod tests_xpbd;

pub use banded::solve_block_pentadiagonal;
pub use chain_step::kinetic_energy_per_mass;
pub use constraints::{follow_the_leader, remove_stretch_velocity};
pub use error::{ChainFailure, DynamicsError, FailedQuantity};
pub use forces::{
    Joint, STANDARD_GRAVITY, add_external_forces, add_spring_forces, bend_angle_and_factor,
    rest_local_direction, transport, walk_joints,
};
pub use head_motion::{HeadKeyframe, HeadMotion, NECK_PIVOT, angular_velocity};
pub use lane_model::MAX_CHAIN_NODES;
pub use model::DynamicsModel;
pub use params::{
    AdaptiveSubsteps, DEFAULT_LINEAR_DENSITY, DynamicsParams, FailurePolicy, IntegratorKind,
    RootMode, SimulationSettings, XPBD_MAX_COURANT, XPBD_MAX_SUBSTEPS,
};
pub use root_motion::{ChainRoots, DeformingBody, RootCarrier, SurfaceAttachment, triangle_frame};
pub use sag_free::{
    MAX_NATURAL_TURN, SAG_FREE_MAX_ITERATIONS, SAG_FREE_TOLERANCE, SagFreeReport, TurnLimit,
    make_sag_free,
};
pub use simulation::{Environment, Simulation, StepReport};
pub use state::SimulationState;
pub use strands::{level_skeletons, strand_skeletons};
pub use wind::{GUST_WAVE_COUNT, GustWave, WindField};
pub use xpbd::{LINE_SEARCH_HALVINGS, MAX_ADAPTIVE_HALVINGS};
