//! The frame pipeline (DESIGN "One frame"): control → level selection and transitions → dynamics
//! with collision → skeletons for the renderer, with the wall-clock time of each stage.

use std::sync::Arc;

use hair_collide::CollisionBody;
use hair_core::dynamics::{DynamicsModel, DynamicsParams, Environment, Simulation};
use hair_core::lod::{
    ErrorModel, LevelDeviation, LodSelector, SectionChoice, SectionObservation, SectionWork,
};
use hair_core::{Frame, Level, PerLevel, RigidTransform, Scene};

use super::block::LevelBlock;
use super::budget::FrameBudget;
use super::checkpoint::Checkpoint;
use super::error::{PipelineError, Result};
use super::hand_over::HandOverModel;
use super::levels::SectionLevels;
use super::report::{LodChanges, StageTimes};
use super::settings::{LodMode, PipelineSettings};
use super::state::PipelineState;
use super::step::BlockStep;
use super::work::Workspace;

mod control;
mod frame;

/// A hair simulation with levels of detail. It keeps three things apart (like rapier's
/// `PhysicsPipeline` and MuJoCo's `mjModel`/`mjData`):
/// - the model: the [`Scene`] (groom and head), the environment and the settings, fixed for the
///   run;
/// - the state: a [`PipelineState`], everything that evolves (skeletons at each level, levels,
///   blends, visibility, the selector's memory, time), which [`Pipeline::state`] returns and
///   [`Pipeline::resume`] starts from;
/// - working memory: each level's solver and collision stage (each posing its own copy of the
///   head's collision body, whose mesh and tree are shared), the level selector's constants,
///   per-frame buffers. Nothing of it is saved: a resumed run rebuilds it from the state.
///
/// ```
/// use hairlod::pipeline::{Pipeline, PipelineSettings};
/// use hairlod::core::dynamics::Environment;
/// use hairlod::{Camera, Scene};
///
/// let scene = Scene::preset("curly")?;
/// let mut pipeline = Pipeline::new(scene, Environment::default(), PipelineSettings::default())?;
/// let camera = Camera::default();
/// let report = pipeline.advance(&camera)?;
/// assert_eq!(report.sections_at.iter().sum::<usize>(), pipeline.scene().groom.section_count());
/// # Ok::<(), hairlod::pipeline::PipelineError>(())
/// ```
pub struct Pipeline {
    /// The scene, shared with the other characters of a crowd that wear the same groom.
    scene: Arc<Scene>,
    environment: Environment,
    settings: PipelineSettings,
    params: DynamicsParams,
    state: PipelineState,
    /// Every level's solvers (each poses its own copy of the collision body).
    work: Workspace,
    /// The head's collision body (collision on), posed at the head at the state's time.
    body: Option<CollisionBody>,
    selector: Option<LodSelector>,
    /// The frame budget that minimises error: the budget [s] and the calibrated cost model
    /// (`None`: levels from the pixel tolerance).
    budget: Option<FrameBudget>,
    /// The levels the budget chose this frame (scratch).
    budget_levels: Vec<Level>,
    /// What each section simulates and draws at each level (for the cost model).
    section_work: Vec<SectionWork>,
    /// Screen area each section covers this frame [pixels] (its bounding disc, for the cost
    /// model).
    section_pixels: Vec<f64>,
    observations: Vec<SectionObservation>,
    frames_scratch: Vec<Frame>,
    /// A frame whose levels are chosen but whose dynamics step has not run
    /// ([`Pipeline::begin_frame`]).
    pending: Option<PendingFrame>,
    /// The frame whose budget options were made ([`Pipeline::budget_options`]) and the time it
    /// took [s], counted into that frame's level-of-detail stage.
    options_made: Option<(usize, f64)>,
}

/// What a pipeline is given already built instead of building it ([`Pipeline::with_shared`]).
#[derive(Default, Clone, Copy)]
struct Shared<'a> {
    deviations: Option<&'a [LevelDeviation]>,
    body: Option<&'a CollisionBody>,
}

/// What [`Pipeline::begin_frame`] leaves for [`Pipeline::finish_frame`].
#[derive(Debug, Clone, Copy, Default)]
struct PendingFrame {
    changes: LodChanges,
    times: StageTimes,
}

impl Pipeline {
    /// A pipeline for `scene` driven by `environment` (head motion, wind, gravity), every section
    /// at rest at the finest level, strand groups (automatic mode: [`settle`](Self::settle) lets
    /// the hair fall into place at full detail, and the first frame hands each section down to
    /// the level it is given), or at the fixed level.
    /// The scene may be an `Arc<Scene>` shared with other pipelines (a crowd's characters that
    /// wear one groom share its model).
    pub fn new(
        scene: impl Into<Arc<Scene>>,
        environment: Environment,
        settings: PipelineSettings,
    ) -> Result<Self> {
        let scene = scene.into();
        let params = DynamicsParams::for_style(&scene.groom.params.style);
        Pipeline::with_material(scene, environment, settings, params)
    }

    /// [`Pipeline::new`] with the skeletons' material given instead of the groom style's
    /// ([`DynamicsParams::for_style`]): mass, stiffness, damping and drag.
    pub fn with_material(
        scene: impl Into<Arc<Scene>>,
        environment: Environment,
        settings: PipelineSettings,
        params: DynamicsParams,
    ) -> Result<Self> {
        Pipeline::build(
            scene.into(),
            environment,
            settings,
            params,
            Shared::default(),
        )
    }

    /// [`Pipeline::new`] with what characters of a crowd that wear one groom on one head build
    /// once and share: the sections' level deviations [m]
    /// ([`level_deviations`](hair_core::lod::level_deviations) of this scene's groom, one per
    /// section) and the head's collision body (a clone of
    /// `CollisionBody::from_mesh(&scene.head.mesh)`, which shares its mesh and tree; read only
    /// with collision on). Errors when the body has another triangle count than the scene's head.
    pub fn with_shared(
        scene: impl Into<Arc<Scene>>,
        environment: Environment,
        settings: PipelineSettings,
        deviations: &[LevelDeviation],
        body: &CollisionBody,
    ) -> Result<Self> {
        let scene = scene.into();
        let triangles = scene.head.mesh.triangles.len();
        if body.triangle_count() != triangles {
            return Err(PipelineError::SharedBodyMismatch {
                body: body.triangle_count(),
                head: triangles,
            });
        }
        let params = DynamicsParams::for_style(&scene.groom.params.style);
        let shared = Shared {
            deviations: Some(deviations),
            body: Some(body),
        };
        Pipeline::build(scene, environment, settings, params, shared)
    }

    fn build(
        scene: Arc<Scene>,
        environment: Environment,
        settings: PipelineSettings,
        params: DynamicsParams,
        shared: Shared<'_>,
    ) -> Result<Self> {
        settings.dynamics.validate()?;
        params.validate()?;
        let groom = &scene.groom;
        let sections = groom.section_count();
        let occluders = scene.head.occluder_boxes();
        let (selector, start_level) = match settings.lod {
            LodMode::Auto(lod) => {
                let mut selector = match shared.deviations {
                    Some(deviations) if lod.error_model == ErrorModel::Deviation => {
                        LodSelector::with_deviations(groom, &occluders, lod, deviations)?
                    }
                    _ => LodSelector::new(groom, &occluders, lod)?,
                };
                selector.set_frame_time(settings.dynamics.time_step)?;
                (Some(selector), Level::StrandGroup)
            }
            LodMode::Fixed(level) => (None, level),
        };
        let body = if settings.collision {
            Some(match shared.body {
                Some(body) => body.clone(),
                None => CollisionBody::from_mesh(&scene.head.mesh)?,
            })
        } else {
            None
        };
        let work = Workspace::new(body.as_ref())?;
        let visible_choice = SectionChoice {
            level: start_level,
            visible: true,
            reason: hair_core::lod::Reason::Fixed,
        };
        let state = PipelineState {
            frame: 0,
            time: 0.0,
            levels: SectionLevels::new(sections, start_level),
            choices: vec![visible_choice; sections],
            pixel_tolerance: selector.as_ref().map(|s| s.settings().pixel_tolerance),
            selector_depths: Vec::new(),
            blocks: PerLevel::from_fn(|level| LevelBlock::empty(level, 0.0)),
        };
        let mut pipeline = Pipeline {
            environment,
            settings,
            params,
            state,
            work,
            body,
            selector,
            budget: None,
            budget_levels: Vec::new(),
            section_work: super::drawn::section_work(&scene.groom),
            section_pixels: vec![0.0; sections],
            observations: vec![SectionObservation::default(); sections],
            frames_scratch: Vec::new(),
            pending: None,
            options_made: None,
            scene,
        };
        let head = pipeline.head_pose();
        pipeline.hand_over(|model, state, work| {
            super::hand_over::start_at_rest(model, state, work, &head)
        })?;
        pipeline.pose_body()?;
        Ok(pipeline)
    }

    /// A pipeline for `scene`, `environment` and `settings` that goes on from `checkpoint`,
    /// stepping exactly as the run that wrote it would have. Refuses a checkpoint of another
    /// scene, environment or settings ([`Pipeline::fingerprint`]) or one whose state does not fit
    /// the groom.
    pub fn resume(
        scene: Scene,
        environment: Environment,
        settings: PipelineSettings,
        checkpoint: Checkpoint,
    ) -> Result<Self> {
        let mut pipeline = Pipeline::new(scene, environment, settings)?;
        let ours = pipeline.fingerprint();
        if checkpoint.scene_fingerprint != ours {
            return Err(PipelineError::ForeignCheckpoint {
                theirs: checkpoint.scene_fingerprint,
                ours,
            });
        }
        pipeline.restore(checkpoint.state)?;
        Ok(pipeline)
    }

    /// The head's collision body (`None` with collision off): shared with the pipelines built
    /// with a clone of it ([`Pipeline::with_shared`]), posed at this pipeline's head.
    pub fn collision_body(&self) -> Option<&CollisionBody> {
        self.body.as_ref()
    }

    /// Poses the collision body at the head at the state's time.
    fn pose_body(&mut self) -> Result<()> {
        let head = self.head_pose();
        if let Some(body) = &mut self.body {
            body.set_pose(head.rotation, head.translation)?;
        }
        Ok(())
    }

    /// Runs a hand-over stage function on the model, the state and the working memory.
    fn hand_over<T>(
        &mut self,
        stage: impl FnOnce(HandOverModel<'_>, &mut PipelineState, &mut Workspace) -> Result<T>,
    ) -> Result<T> {
        let model = HandOverModel {
            groom: &self.scene.groom,
            params: self.params,
            settings: &self.settings,
        };
        stage(model, &mut self.state, &mut self.work)
    }

    /// The fingerprint of this run's model: the groom (parameters and skeleton rest data:
    /// lengths, rest and natural angles, roots), the head mesh, the environment and the
    /// settings, hashed (FNV-1a, 64 bits) to 16 hex digits.
    /// A checkpoint resumes only where the fingerprint is the same.
    pub fn fingerprint(&self) -> String {
        super::fingerprint::model_fingerprint(
            &self.scene,
            &self.environment,
            &self.settings,
            &self.params,
        )
    }

    /// Everything of the run that evolves, for a checkpoint ([`Checkpoint::new`] with
    /// [`Pipeline::fingerprint`]); between frames (a frame begun with
    /// [`begin_frame`](Self::begin_frame) and not finished is refused).
    pub fn state(&self) -> Result<PipelineState> {
        if self.pending.is_some() {
            return Err(PipelineError::FrameBegun {
                action: "take the state between frames",
            });
        }
        let mut state = self.state.clone();
        for (level, block) in state.blocks.iter_mut() {
            if let Some(solver) = &self.work.levels[level].solver {
                block.collision_memory = solver.velocity_memory();
            }
        }
        Ok(state)
    }

    /// A checkpoint of the run now.
    pub fn checkpoint(&self) -> Result<Checkpoint> {
        Ok(Checkpoint::new(self.fingerprint(), self.state()?))
    }

    /// Replaces the state with `state` (checked against the groom and the settings) and
    /// rebuilds every solver around it.
    fn restore(&mut self, state: PipelineState) -> Result<()> {
        state.check(&self.scene.groom, self.settings.dynamics.time_step)?;
        match (&mut self.selector, state.pixel_tolerance) {
            (Some(selector), Some(tolerance)) => {
                selector.set_pixel_tolerance(tolerance)?;
                selector.restore_choices(&state.choices)?;
                selector.restore_depths(&state.selector_depths)?;
            }
            (None, None) => {}
            _ => {
                return Err(PipelineError::LodModeMismatch);
            }
        }
        self.state = state;
        self.hand_over(|model, state, work| super::hand_over::rebuild_all(model, state, work))?;
        self.pose_body()
    }

    /// Lets the hair settle from its rest shape under gravity (and the environment at time 0)
    /// for `seconds` [s] at the current levels, without choosing levels or advancing the clock:
    /// a groom's rest shape is not an equilibrium under gravity, and a run should not start with
    /// hair falling into place (which the motion criterion would rightly read as motion).
    pub fn settle(&mut self, seconds: f32) -> Result<()> {
        let steps = self.settle_steps(seconds);
        let still = self.settle_environment();
        for _ in 0..steps {
            super::step::step_blocks(self.block_steps(Some(&still), 0.0))?;
        }
        self.settled();
        Ok(())
    }

    /// The settling fall's still environment: the head held at its pose now, the rest as the
    /// run's ([`settle`](Self::settle)).
    pub(crate) fn settle_environment(&self) -> Environment {
        Environment {
            head: hair_core::dynamics::HeadMotion::Still(self.head_pose()),
            ..self.environment.clone()
        }
    }

    /// Puts the blocks' clocks back on the run's after the settling fall.
    pub(crate) fn settled(&mut self) {
        for (_, block) in self.state.blocks.iter_mut() {
            block.state.time = self.state.time;
        }
    }

    /// Every level block with its working memory, to step in `environment` (the run's when
    /// `None`) from `time` [s] ([`super::step::step_blocks`]).
    pub(crate) fn block_steps<'a>(
        &'a mut self,
        environment: Option<&'a Environment>,
        time: f64,
    ) -> Vec<BlockStep<'a>> {
        let environment = environment.unwrap_or(&self.environment);
        super::step::character_steps(
            self.state.blocks.iter_mut(),
            self.work.levels.iter_mut(),
            environment,
            time,
        )
        .collect()
    }

    /// The steps of a settling fall of `seconds` [s].
    pub(crate) fn settle_steps(&self, seconds: f32) -> usize {
        (seconds / self.settings.dynamics.time_step).ceil().max(0.0) as usize
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The settings.
    pub fn settings(&self) -> &PipelineSettings {
        &self.settings
    }

    /// The environment (head motion, wind, gravity).
    pub fn environment(&self) -> &Environment {
        &self.environment
    }

    /// The level selector (`None` with a fixed level).
    pub fn selector(&self) -> Option<&LodSelector> {
        self.selector.as_ref()
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// Frames advanced so far.
    pub fn frame(&self) -> usize {
        self.state.frame
    }

    /// The current level of every section.
    pub fn section_levels(&self) -> &[Level] {
        self.state.levels.current()
    }

    /// The last choice of every section (level, visibility, reason).
    pub fn choices(&self) -> &[SectionChoice] {
        &self.state.choices
    }

    /// The block of `level`: the sections simulated at it and their state.
    pub fn block(&self, level: Level) -> &LevelBlock {
        &self.state.blocks[level]
    }

    /// The dynamics model `level`'s block is stepped with (none while the block is empty): its
    /// chains are the block's, in the block's order, and its nodes index the block's state.
    pub fn level_model(&self, level: Level) -> Option<&DynamicsModel> {
        self.work.levels[level]
            .simulation
            .as_ref()
            .map(Simulation::model)
    }

    /// The head's pose at the time the skeletons are at (the end of the last frame stepped).
    pub fn head_pose(&self) -> RigidTransform {
        self.environment.head.transform_at(self.state.time)
    }
}
