//! Grooms that are hairstyles at rest: every level starts in a static equilibrium under gravity
//! and collision, in the combed, hanging shape the hair takes on the body, instead of the shape it
//! was grown in (which sticks out from the scalp and falls for the first quarter second).
//!
//! [`hang_groom`] does it in two stages, the same for every groom source:
//! 1. **The hanging shape.** The strand groups (every section at that level) fall with the head
//!    still in the groom's pose, under gravity, with collision against the body, in calm air,
//!    through the frame pipeline's [`Pipeline::settle`]. Their shapes after
//!    [`HangSettings::seconds`] become their rest shapes (rest angles measured in the transported
//!    frames, lengths and roots kept). Clusters and patches take the shapes a hand-over from the
//!    strand groups gives ([`hand_over`], §4.2), so that a section switching level at rest
//!    arrives at the rest shape of its new level.
//! 2. **Sag-free springs.** [`make_sag_free`] turns the springs' natural directions just enough
//!    that each level's shape is a static equilibrium of the same springs (the stiffness is the
//!    style's, unchanged), gravity and the friction the collision stage puts on resting nodes (as
//!    measured in a first step from rest). Where a spring would have to turn past
//!    [`MAX_NATURAL_TURN`](hair_core::dynamics::MAX_NATURAL_TURN) it is clamped, the body has to
//!    carry the rest, and the level falls again onto it with the new springs (at most
//!    [`MAX_ROUNDS`] rounds). A level still clamped after the last round falls once more and
//!    keeps the shape it settles in, without another balance: the equilibrium the dynamics
//!    reaches with the clamped springs and the body.
//!
//! The hair then moves as the settled groom would (the same shape, the same stiffness), without
//! the fall: a still head simulated from t = 0 stays where it is drawn.
//!
//! ```no_run
//! use hairlod::rest_pose::{HangSettings, hang_groom};
//! use hairlod::Scene;
//!
//! let mut scene = Scene::preset("curly")?;
//! let report = hang_groom(&mut scene, &HangSettings::default())?;
//! println!("the hair moved {:.1} mm on average into its hanging shape", report.mean_move * 1e3);
//! # Ok::<(), hairlod::PipelineError>(())
//! ```

use std::time::Instant;

use glam::Vec3;
use hair_collide::BroadPhase;
use hair_core::dynamics::{
    ChainRoots, DynamicsParams, Environment, HeadMotion, IntegratorKind, STANDARD_GRAVITY,
    SagFreeReport, SimulationSettings, TurnLimit, WindField, kinetic_energy_per_mass,
    level_skeletons, make_sag_free,
};
use hair_core::lod::{SectionStateRef, hand_over};
use hair_core::skeleton::measure_chain;
use hair_core::{Groom, Level, PerLevel, RigidTransform, Scene, SkeletonRest};
use serde::Serialize;

use crate::pipeline::{DrawnAs, LodMode, Pipeline, PipelineError, PipelineSettings, Result};

hair_core::named_enum! {
    /// The shape a groom is drawn in at rest and starts every run from.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum RestPose {
        /// Hanging on the body under gravity, and an equilibrium there ([`hang_groom`]).
        #[default]
        Hanging = "hanging",
        /// The shape the groom was grown in, its springs at rest: not an equilibrium under
        /// gravity (the hair falls at first; a run settles it before its first frame).
        Grown = "grown",
        /// The shape a groom file gives, kept, and made an equilibrium there ([`hang_groom`] with
        /// [`HangSettings::fall`] off): only a level whose springs cannot hold it alone sinks onto
        /// the body. For grooms read from files (a generated groom's grown shape is no hairstyle).
        Loaded = "loaded",
    }
}

/// How [`hang_groom`] finds the hanging shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HangSettings {
    /// Seconds of simulation for the hair to fall into place [s].
    pub seconds: f32,
    /// The integrator and step of that simulation.
    pub dynamics: SimulationSettings,
    /// Collision with the body while falling (off: the hair hangs through the head).
    pub collision: bool,
    /// Gravity [m/s²], also the gravity the equilibrium is made for.
    pub gravity: Vec3,
    /// Air drag rate γ [1/s] while falling: near critical damping of the hair's slow swings, so
    /// that it comes to rest in the time given. Drag vanishes at rest, so it does not move the
    /// equilibrium; the runs after use the style's drag.
    pub drag_rate: f32,
    /// Let the strand groups fall into their hanging shape first (stage 1 of the module docs).
    /// Off, every level keeps the rest shape it has (a groom file's shape) and is only balanced;
    /// a level whose springs had to be clamped still sinks onto the body in the rounds after.
    pub fall: bool,
}

impl Default for HangSettings {
    /// Two seconds of the default integrator at its recommended step, collision on, standard
    /// gravity, drag 6/s, falling first.
    fn default() -> Self {
        HangSettings {
            seconds: 2.0,
            dynamics: SimulationSettings::recommended(IntegratorKind::DEFAULT),
            collision: true,
            gravity: STANDARD_GRAVITY,
            drag_rate: 6.0,
            fall: true,
        }
    }
}

/// What [`hang_groom`] did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HangReport {
    /// Seconds of simulation the hair fell for [s].
    pub seconds: f32,
    /// Mean distance of a skeleton node from its grown shape to its hanging shape [m], over every
    /// level.
    pub mean_move: f32,
    /// The largest such distance [m].
    pub max_move: f32,
    /// The sag-free springs of each level (of its last round).
    pub sag_free: PerLevel<SagFreeReport>,
    /// Rounds of falling and balancing each level took (more than one where a spring was clamped
    /// and the shape had to sink onto the body), at most [`MAX_ROUNDS`].
    pub rounds: PerLevel<usize>,
    /// Wall-clock time of the whole [`hang_groom`] [s].
    pub wall_seconds: f64,
}

/// Makes the rest shape of every level of `scene`'s groom its hanging shape on the body, and a
/// static equilibrium there (see the module docs; with [`HangSettings::fall`] off, the shape it
/// has is kept where the springs can hold it). The groom's head space is the world during the
/// fall: the head stands still in its rest pose. Fails, leaving `scene` as it was, when a level's
/// simulation fails or a shape cannot be held by its springs.
pub fn hang_groom(scene: &mut Scene, settings: &HangSettings) -> Result<HangReport> {
    let started = Instant::now();
    let head = RigidTransform::IDENTITY;
    let environment = Environment {
        head: HeadMotion::Still(head),
        wind: WindField::Calm,
        gravity: settings.gravity,
    };
    let grown = scene.groom.skeletons.rest_positions(&head);
    let params = DynamicsParams::for_style(&scene.groom.params.style);
    // The scene as it is being hung; `scene` takes it only when every level succeeded. The hair
    // hangs on the body at rest: a deforming body's motion plays in the run, not here.
    let mut hung = scene.clone();
    let body_motion = hung.body_motion.take();
    let mut sag_free = PerLevel::from_fn(|_| SagFreeReport::default());
    let mut rounds = PerLevel::from_fn(|_| 0);
    // Strand groups fall; the coarser levels take the shapes a hand-over from them gives (§4.2),
    // so that a section switching level at rest arrives at the rest shape of its new level. Each
    // level is then balanced; where a spring could not hold its part alone (it was clamped), the
    // level sinks onto the body with the new springs and its shape is taken again.
    for level in [Level::StrandGroup, Level::Cluster, Level::Patch] {
        for round in 1..=MAX_ROUNDS {
            rounds[level] = round;
            if round > 1 || (settings.fall && level == Level::StrandGroup) {
                settle_level(&mut hung, level, &environment, settings, false)?;
            } else if settings.fall {
                hand_down_shapes(&mut hung.groom, level)?;
            }
            let contact_forces = if settings.collision {
                resting_contact_forces(&hung, level, &environment, settings)?
            } else {
                Vec::new()
            };
            sag_free[level] =
                balance_level(&mut hung.groom, level, &params, settings, &contact_forces)?;
            if sag_free[level].clamped_joints == 0 {
                break;
            }
        }
        if sag_free[level].clamped_joints > 0 {
            // Still clamped after the last round: the balanced shape is not an equilibrium of
            // the clamped springs. The level sinks once more with them and keeps the shape it
            // settles in, unbalanced: the dynamics reached it, so it is an equilibrium of these
            // springs, gravity and the body (balancing it again would turn the springs anew).
            settle_level(&mut hung, level, &environment, settings, true)?;
        }
    }
    let hanging = hung.groom.skeletons.rest_positions(&head);
    let moves: Vec<f32> = grown
        .iter()
        .zip(&hanging)
        .map(|(a, b)| a.distance(*b))
        .collect();
    let max_move = moves.iter().copied().fold(0.0f32, f32::max);
    let mean_move = moves.iter().sum::<f32>() / moves.len().max(1) as f32;
    hung.body_motion = body_motion;
    *scene = hung;
    Ok(HangReport {
        seconds: settings.seconds,
        mean_move,
        max_move,
        sag_free,
        rounds,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

/// Rounds of falling and balancing per level at most.
pub const MAX_ROUNDS: usize = 3;

/// The settings of a pipeline that runs every section at `level`.
fn level_settings(level: Level, settings: &HangSettings, collision: bool) -> PipelineSettings {
    PipelineSettings {
        lod: LodMode::Fixed(level),
        drawn_as: DrawnAs::default(),
        dynamics: settings.dynamics,
        collision,
        broad_phase: BroadPhase::default(),
    }
}

/// Node speed [m/s] under which a level's final fall (after its last round) has come to rest.
pub const STILL_SPEED: f32 = 1e-3;

/// The longest final fall, in multiples of [`HangSettings::seconds`].
pub const FINAL_FALL_LIMIT: f32 = 4.0;

/// Lets `level`'s skeletons fall from their rest shapes for `settings.seconds` and makes the
/// shapes they reach their rest shapes (measured in the transported frames; the springs keep
/// pulling where they did). With `until_still`, the fall goes on in half-`seconds` steps until
/// no node is faster than [`STILL_SPEED`] or it has lasted [`FINAL_FALL_LIMIT`] times
/// `seconds`: the shape it keeps is then the equilibrium, not a moment of a swing.
fn settle_level(
    scene: &mut Scene,
    level: Level,
    environment: &Environment,
    settings: &HangSettings,
    until_still: bool,
) -> Result<()> {
    let mut params = DynamicsParams::for_style(&scene.groom.params.style);
    params.air_drag_rate = settings.drag_rate;
    let mut pipeline = Pipeline::with_material(
        scene.clone(),
        environment.clone(),
        level_settings(level, settings, settings.collision),
        params,
    )?;
    // An unstable step while falling says which level and what to change.
    let in_the_hang = |error: PipelineError| {
        if error.is_unstable() {
            PipelineError::HangUnstable {
                level,
                integrator: settings.dynamics.integrator,
                error: Box::new(error),
            }
        } else {
            error
        }
    };
    pipeline.settle(settings.seconds).map_err(in_the_hang)?;
    let mut fallen = settings.seconds;
    if until_still {
        let fastest = |pipeline: &Pipeline| {
            pipeline
                .block(level)
                .state
                .node_velocities
                .iter()
                .map(|v| v.length())
                .fold(0.0f32, f32::max)
        };
        while fastest(&pipeline) > STILL_SPEED && fallen < FINAL_FALL_LIMIT * settings.seconds {
            pipeline
                .settle(0.5 * settings.seconds)
                .map_err(in_the_hang)?;
            fallen += 0.5 * settings.seconds;
        }
    }
    check_energy(level, &pipeline, settings, fallen)?;
    let block = pipeline.block(level);
    set_rest_shapes(
        &mut scene.groom.skeletons,
        &block.chains,
        &block.state.node_positions,
    )
}

/// Fails with [`PipelineError::Unsettled`] when a chain of `level` has more kinetic energy per
/// unit mass after its fall than gravity could give it. The fall starts at rest and nothing but
/// gravity does work on the hair (the head is still, the air calm; drag and friction take energy
/// out), so `½·Σm|v|²/Σm ≤ g·Δh` for the drop `Δh` of the chain's centre of mass, and with every
/// node within the chain's length `L` of its root, `Δh ≤ 2L`. More is energy the integrator made.
fn check_energy(
    level: Level,
    pipeline: &Pipeline,
    settings: &HangSettings,
    seconds: f32,
) -> Result<()> {
    let Some(model) = pipeline.level_model(level) else {
        return Ok(());
    };
    let block = pipeline.block(level);
    let gravity = settings.gravity.length();
    // The chain (of the model) furthest over its bound: energy [J/kg], bound [J/kg], index.
    let mut worst: Option<(f32, f32, usize)> = None;
    for local in 0..model.rest.chain_count() {
        let nodes = model.rest.nodes(local);
        let energy = kinetic_energy_per_mass(
            &model.node_masses[nodes.clone()],
            &block.state.node_velocities[nodes],
        );
        let limit = 2.0 * gravity * model.rest.chain_length(local);
        // NaN counts as over (a non-finite velocity is energy made too).
        let over = energy.is_nan() || energy > limit;
        if over && worst.is_none_or(|(e, l, _)| energy / limit > e / l) {
            worst = Some((energy, limit, local));
        }
    }
    let Some((energy_per_mass, limit, local)) = worst else {
        return Ok(());
    };
    Err(PipelineError::Unsettled {
        level,
        chain: block.chains[local],
        nodes: model.rest.chain_node_count(local),
        seconds,
        energy_per_mass,
        limit,
        integrator: settings.dynamics.integrator,
        substep: settings.dynamics.substep(),
    })
}

/// Gives `level`'s skeletons, section by section, the shapes that handing the strand groups'
/// rest shapes over to `level` gives ([`hand_over`], as the pipeline does when a section
/// switches level).
fn hand_down_shapes(groom: &mut Groom, level: Level) -> Result<()> {
    let head = RigidTransform::IDENTITY;
    let skeletons = &groom.skeletons;
    let fine = skeletons.rest_positions(&head);
    let mut positions = Vec::new();
    let mut chains = Vec::new();
    let (mut shape, mut still, mut velocities) = (Vec::new(), Vec::new(), Vec::new());
    for section in 0..groom.section_count() {
        let from = groom.section_chains(section, Level::StrandGroup);
        let nodes = skeletons.offsets[from.start] as usize..skeletons.offsets[from.end] as usize;
        still.resize(nodes.len(), Vec3::ZERO);
        let to = groom.section_chains(section, level);
        let count = skeletons.offsets[to.end] as usize - skeletons.offsets[to.start] as usize;
        shape.resize(count, Vec3::ZERO);
        velocities.resize(count, Vec3::ZERO);
        hand_over(
            groom,
            section,
            Level::StrandGroup,
            SectionStateRef {
                positions: &fine[nodes],
                velocities: &still,
            },
            level,
            &mut shape,
            &mut velocities,
            &ChainRoots::rigid(head),
        )?;
        positions.extend_from_slice(&shape);
        chains.extend(to);
    }
    set_rest_shapes(&mut groom.skeletons, &chains, &positions)
}

/// Makes `positions` (the nodes of `chains` one after the other, head at rest) the rest shapes of
/// those chains: rest angles measured in the transported frames; lengths, roots and the springs'
/// natural angles kept.
fn set_rest_shapes(
    skeletons: &mut SkeletonRest,
    chains: &[usize],
    positions: &[Vec3],
) -> Result<()> {
    let head = RigidTransform::IDENTITY;
    let mut start = 0;
    for &chain in chains {
        let count = skeletons.chain_node_count(chain);
        let shape = &positions[start..start + count];
        start += count;
        let angles = measure_chain(&skeletons.world_root_frame(chain, &head), shape)?;
        skeletons.set_rest_angles(chain, &angles.polar_angles, &angles.azimuth_angles)?;
    }
    Ok(())
}

/// Makes the rest shapes of `level`'s skeletons an equilibrium under gravity and
/// `contact_forces` (one per node of the level, or empty), clamping springs that cannot hold.
fn balance_level(
    groom: &mut Groom,
    level: Level,
    params: &DynamicsParams,
    settings: &HangSettings,
    contact_forces: &[Vec3],
) -> Result<SagFreeReport> {
    let mut level_rest = level_skeletons(groom, level)?;
    let report = make_sag_free(
        &mut level_rest,
        params,
        &RigidTransform::IDENTITY,
        settings.gravity,
        contact_forces,
        TurnLimit::Clamp,
    )?;
    for (local, chain) in groom.level_chains(level).enumerate() {
        let nodes = level_rest.nodes(local);
        groom.skeletons.set_natural_angles(
            chain,
            &level_rest.natural_polar_angles[nodes.clone()],
            &level_rest.natural_azimuth_angles[nodes],
        )?;
    }
    Ok(report)
}

/// The contact forces [N] on `level`'s nodes (in the groom's chain order) in the first step of a
/// run of `scene` from rest: a run from rest meets the same.
fn resting_contact_forces(
    scene: &Scene,
    level: Level,
    environment: &Environment,
    settings: &HangSettings,
) -> Result<Vec<Vec3>> {
    let mut pipeline = Pipeline::new(
        scene.clone(),
        environment.clone(),
        level_settings(level, settings, true),
    )?;
    pipeline.settle(settings.dynamics.time_step)?;
    let block = pipeline.block(level);
    // A fixed level lays its sections out in the groom's chain order.
    debug_assert!(block.chains.windows(2).all(|pair| pair[0] < pair[1]));
    Ok(block.state.collision_forces.clone())
}
