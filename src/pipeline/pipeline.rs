//! The frame pipeline (DESIGN "One frame"): control → level selection and transitions → dynamics
//! with collision → skeletons for the renderer, with the wall-clock time of each stage.

use std::sync::Arc;
use std::time::Instant;

use hair_collide::{
    CollisionBody, CollisionChain, CollisionSettings, CollisionSolver, groom_chain,
};
use hair_core::dynamics::{DynamicsModel, DynamicsParams, Environment, Simulation};
use hair_core::lod::{
    CostModel, ErrorModel, LevelDeviation, LodSelector, SectionChoice, SectionObservation,
    SectionOptions, SectionWork,
};
use hair_core::{Camera, Frame, Level, PerLevel, RigidTransform, Scene, SkeletonRest};
use hair_render::ActiveSkeletons;

use super::block::LevelBlock;
use super::checkpoint::Checkpoint;
use super::error::{PipelineError, Result};
use super::levels::SectionLevels;
use super::report::{FrameReport, LodChanges, StageTimes};
use super::settings::{LodMode, PipelineSettings};
use super::state::PipelineState;

/// A hair simulation with levels of detail. It keeps three things apart (like rapier's
/// `PhysicsPipeline` and MuJoCo's `mjModel`/`mjData`):
/// - the model: the [`Scene`] (groom and head), the environment and the settings, fixed for the
///   run;
/// - the state: a [`PipelineState`], everything that evolves (skeletons at each level, levels,
///   blends, visibility, the selector's memory, time), which [`Pipeline::state`] returns and
///   [`Pipeline::resume`] starts from;
/// - scratch: each level's solver and collision stage, the collision bodies (one per mesh,
///   shared by the levels), the level selector's constants, per-frame buffers.
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
    work: PerLevel<LevelWork>,
    /// One collision body per mesh (the head), shared by every level's collision stage.
    bodies: Vec<CollisionBody>,
    selector: Option<LodSelector>,
    /// The frame budget that minimises error: the budget [s] and the calibrated cost model
    /// (`None`: levels from the pixel tolerance).
    budget: Option<(f64, CostModel)>,
    /// What each section simulates and draws at each level (for the cost model).
    section_work: Vec<SectionWork>,
    /// Screen area each section covers this frame [pixels] (its bounding disc, for the cost
    /// model).
    section_pixels: Vec<f64>,
    observations: Vec<SectionObservation>,
    frames_scratch: Vec<Frame>,
    collision_chains: Vec<CollisionChain>,
    /// A frame whose levels are chosen but whose dynamics step has not run
    /// ([`Pipeline::begin_frame`]).
    pending: Option<PendingFrame>,
    /// The frame whose budget options were made ([`Pipeline::budget_options`]) and the time it
    /// took [s], counted into that frame's level-of-detail stage.
    options_made: Option<(usize, f64)>,
}

/// The solvers of one level's block: the integrator and its scratch (`None` while no section is
/// at the level), and the collision stage (`None` with collision off).
struct LevelWork {
    simulation: Option<Simulation>,
    solver: Option<CollisionSolver>,
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
            return Err(PipelineError::State(format!(
                "the shared collision body has {} triangles, the scene's head {triangles}: share \
                 the body built from this scene's head mesh",
                body.triangle_count()
            )));
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
        let bodies = if settings.collision {
            vec![match shared.body {
                Some(body) => body.clone(),
                None => CollisionBody::from_mesh(&scene.head.mesh)?,
            }]
        } else {
            Vec::new()
        };
        let work = PerLevel::from_fn(|_| -> Result<LevelWork> {
            Ok(LevelWork {
                simulation: None,
                solver: settings
                    .collision
                    .then(|| CollisionSolver::new(CollisionSettings::default()))
                    .transpose()?,
            })
        });
        let work = PerLevel {
            patch: work.patch?,
            cluster: work.cluster?,
            strand_group: work.strand_group?,
        };
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
            bodies,
            selector,
            budget: None,
            section_work: super::drawn::section_work(&scene.groom),
            section_pixels: vec![0.0; sections],
            observations: vec![SectionObservation::default(); sections],
            frames_scratch: Vec::new(),
            collision_chains: Vec::new(),
            pending: None,
            options_made: None,
            scene,
        };
        pipeline.start_at_rest()?;
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
            return Err(PipelineError::State(format!(
                "the checkpoint is of another scene (its fingerprint {}, this scene's {ours}): \
                 resume with the scene file, groom and settings that wrote it",
                checkpoint.scene_fingerprint
            )));
        }
        pipeline.restore(checkpoint.state)?;
        Ok(pipeline)
    }

    /// The head's collision body (`None` with collision off): shared with the pipelines built
    /// with a clone of it ([`Pipeline::with_shared`]), posed at this pipeline's head.
    pub fn collision_body(&self) -> Option<&CollisionBody> {
        self.bodies.first()
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
            return Err(PipelineError::State(
                "a frame is begun and not finished: take the state between frames".into(),
            ));
        }
        let mut state = self.state.clone();
        for (level, block) in state.blocks.iter_mut() {
            if let Some(solver) = &self.work[level].solver {
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
                return Err(PipelineError::State(
                    "the state is of automatic levels and the settings fix one (or the other \
                     way round)"
                        .into(),
                ));
            }
        }
        self.state = state;
        for level in Level::ALL {
            self.rebuild_simulation(level)?;
            if let Some(solver) = &mut self.work[level].solver {
                solver.set_velocity_memory(&self.state.blocks[level].collision_memory);
            }
        }
        self.refresh_collision_chains()?;
        Ok(())
    }

    /// Builds the solver of `level` for the chains of its block (none when it is empty).
    fn rebuild_simulation(&mut self, level: Level) -> Result<()> {
        let block = &self.state.blocks[level];
        self.work[level].simulation = if block.sections.is_empty() {
            None
        } else {
            let mut rest = SkeletonRest::default();
            for &chain in &block.chains {
                rest.push_chain_from(&self.scene.groom.skeletons, chain)?;
            }
            Some(Simulation::new(
                DynamicsModel::new(rest, self.params)?,
                self.settings.dynamics,
            )?)
        };
        Ok(())
    }

    /// Builds the blocks of the starting levels and puts every skeleton in its rest shape.
    fn start_at_rest(&mut self) -> Result<()> {
        let head = self.environment.head.transform_at(self.state.time);
        for level in Level::ALL {
            let sections = self.state.levels.members(level);
            let block = LevelBlock::laid_out(&self.scene.groom, level, sections, self.state.time);
            self.state.blocks[level] = block;
            self.rebuild_simulation(level)?;
            if let Some(simulation) = &self.work[level].simulation {
                self.state.blocks[level].state.node_positions =
                    simulation.model().rest.rest_positions(&head);
            }
        }
        self.refresh_collision_chains()?;
        Ok(())
    }

    /// Rebuilds the blocks whose sections changed (a section switched level or a blend ended):
    /// sections that stay keep their state bit for bit, arriving ones are handed over (§4.2).
    fn apply_level_changes(&mut self, head: &RigidTransform) -> Result<()> {
        let mut rebuilt = PerLevel::from_fn(|_| None);
        for level in Level::ALL {
            let members = self.state.levels.members(level);
            if members == self.state.blocks[level].sections {
                continue;
            }
            rebuilt[level] = Some(LevelBlock::handed_over(
                &self.scene.groom,
                level,
                members,
                &self.state.blocks,
                self.state.time,
                head,
            )?);
        }
        for level in Level::ALL {
            if let Some(block) = rebuilt[level].take() {
                self.state.blocks[level] = block;
                self.rebuild_simulation(level)?;
            }
        }
        self.refresh_collision_chains()
    }

    /// Lets the hair settle from its rest shape under gravity (and the environment at time 0)
    /// for `seconds` [s] at the current levels, without choosing levels or advancing the clock:
    /// a groom's rest shape is not an equilibrium under gravity, and a run should not start with
    /// hair falling into place (which the motion criterion would rightly read as motion).
    pub fn settle(&mut self, seconds: f32) -> Result<()> {
        let step = self.settings.dynamics.time_step;
        let steps = (seconds / step).ceil().max(0.0) as usize;
        let still = Environment {
            head: hair_core::dynamics::HeadMotion::Still(
                self.environment.head.transform_at(self.state.time),
            ),
            ..self.environment.clone()
        };
        for _ in 0..steps {
            for level in Level::ALL {
                let block = &mut self.state.blocks[level];
                let work = &mut self.work[level];
                let Some(simulation) = work.simulation.as_mut() else {
                    continue;
                };
                block.state.time = 0.0;
                match &mut work.solver {
                    Some(solver) => {
                        solver.step(&mut self.bodies, simulation, &mut block.state, &still)?;
                    }
                    None => {
                        simulation.step(&mut block.state, &still)?;
                    }
                }
            }
        }
        for (_, block) in self.state.blocks.iter_mut() {
            block.state.time = self.state.time;
        }
        Ok(())
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

    /// Chooses levels within a frame budget of `seconds` [s] from the next frame on, minimising
    /// the total estimated error ([`LodSelector::select_within_budget`]) with costs from
    /// `model`, which [`observe_frame`](Self::observe_frame) calibrates; `None` goes back to the
    /// pixel tolerance. Errors at a fixed level (there is nothing to choose) and for a budget
    /// that is not a positive number of seconds.
    pub fn set_frame_budget(&mut self, budget: Option<(f64, CostModel)>) -> Result<()> {
        if let Some((seconds, _)) = &budget {
            if self.selector.is_none() {
                return Err(PipelineError::State(
                    "a frame budget needs automatic levels (the levels are fixed)".into(),
                ));
            }
            if !(seconds.is_finite() && *seconds > 0.0) {
                return Err(hair_core::HairError::invalid(
                    "frame budget (s)",
                    seconds,
                    "a positive number of seconds",
                )
                .into());
            }
        }
        self.budget = budget;
        Ok(())
    }

    /// The frame budget [s] and cost model, when levels are chosen within a budget.
    pub fn frame_budget(&self) -> Option<&(f64, CostModel)> {
        self.budget.as_ref()
    }

    /// Calibrates the frame budget's cost model with a finished frame's `report` (its rendering
    /// time filled in when the frame was drawn). Does nothing without a budget.
    pub fn observe_frame(&mut self, report: &FrameReport) {
        if let Some((_, model)) = &mut self.budget {
            report.calibrate(model);
        }
    }

    /// Sets the selector's pixel tolerance [pixels] from the next frame on (a frame-budget
    /// controller steers it); nothing at a fixed level.
    pub fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        if let Some(selector) = self.selector.as_mut() {
            selector.set_pixel_tolerance(pixel_tolerance)?;
            self.state.pixel_tolerance = Some(pixel_tolerance);
        }
        Ok(())
    }

    /// Switches between automatic levels and a fixed level from the next frame on (an
    /// interactive viewer's "force a level"). To a fixed level, every section is switched through
    /// the same hand-over (§4.2) and blend as an automatic change (blending over the current
    /// selector's blend time) and shown whether in view or not, as a fixed-level run does; back to
    /// automatic levels, a selector with `lod` settings starts from the levels the sections are at
    /// and chooses at the next frame. The run's fingerprint follows the settings. Refused while a
    /// frame is begun and not finished.
    pub fn set_lod_mode(&mut self, mode: LodMode) -> Result<()> {
        if self.pending.is_some() {
            return Err(PipelineError::State(
                "a frame is begun and not finished: change the level mode between frames".into(),
            ));
        }
        if mode == self.settings.lod {
            return Ok(());
        }
        match mode {
            LodMode::Auto(lod) => {
                let mut selector =
                    LodSelector::new(&self.scene.groom, &self.scene.head.occluder_boxes(), lod)?;
                selector.set_frame_time(self.settings.dynamics.time_step)?;
                selector.restore_choices(&self.state.choices)?;
                // Depths from before a fixed spell are stale: the first choice does not look
                // ahead.
                self.state.selector_depths.clear();
                self.state.pixel_tolerance = Some(lod.pixel_tolerance);
                self.selector = Some(selector);
            }
            LodMode::Fixed(level) => {
                let blend = self
                    .selector
                    .as_ref()
                    .map_or(0.0, |s| s.settings().blend_time);
                let time = self.state.time;
                for section in 0..self.scene.groom.section_count() {
                    if self.state.levels.current()[section] != level {
                        self.state.levels.switch(section, level, time, blend);
                    }
                    self.state.levels.set_visible(section, true, time, blend);
                    self.state.choices[section] = SectionChoice {
                        level,
                        visible: true,
                        reason: hair_core::lod::Reason::Fixed,
                    };
                }
                self.selector = None;
                self.state.pixel_tolerance = None;
                let head = self.environment.head.transform_at(time);
                self.apply_level_changes(&head)?;
            }
        }
        self.settings.lod = mode;
        Ok(())
    }

    /// Replaces the environment (head motion, wind, gravity) from the next frame on (an
    /// interactive viewer's wind and head-motion switches). The head's pose jumps to the new
    /// motion's pose at the current time. The run's fingerprint follows the environment.
    /// Refused while a frame is begun and not finished.
    pub fn set_environment(&mut self, environment: Environment) -> Result<()> {
        if self.pending.is_some() {
            return Err(PipelineError::State(
                "a frame is begun and not finished: change the environment between frames".into(),
            ));
        }
        self.environment = environment;
        Ok(())
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
        self.work[level].simulation.as_ref().map(Simulation::model)
    }

    /// The head's pose at the time the skeletons are at (the end of the last frame stepped).
    pub fn head_pose(&self) -> RigidTransform {
        self.environment.head.transform_at(self.state.time)
    }

    /// Advances one frame of `settings.dynamics.time_step` seconds seen by `camera`: chooses
    /// levels, hands state over where a section changed level, steps every block with collision.
    /// The same as [`Pipeline::begin_frame`] then [`Pipeline::finish_frame`].
    pub fn advance(&mut self, camera: &Camera) -> Result<FrameReport> {
        self.begin_frame(camera)?;
        self.finish_frame()
    }

    /// The level-of-detail stage of a frame seen by `camera`: chooses levels, starts and ends
    /// blends and hands state over where a section changed level, without stepping the dynamics;
    /// returns how many sections changed level or visibility. Drawing now
    /// ([`Pipeline::gather_drawn`]) shows the frame's levels and blend coverages on the skeletons
    /// of the frame before, so the image change that the level decisions alone make can be
    /// measured (the popping measure). A frame already begun is not begun again (its changes are
    /// returned).
    pub fn begin_frame(&mut self, camera: &Camera) -> Result<LodChanges> {
        self.begin_frame_from(camera, None)
    }

    /// Every section's options for a frame budget shared with other pipelines (a crowd's): the
    /// sections are observed through `camera` and their estimated errors, costs (from `model`)
    /// and floors returned ([`LodSelector::budget_options`]). Run
    /// [`refine_within_budget`](hair_core::lod::refine_within_budget) over the options of every
    /// pipeline, then begin the frame with each one's levels
    /// ([`begin_frame_with_levels`](Self::begin_frame_with_levels)). Errors at a fixed level and
    /// while a frame is begun.
    pub fn budget_options(
        &mut self,
        camera: &Camera,
        model: &CostModel,
    ) -> Result<&[SectionOptions]> {
        if self.pending.is_some() {
            return Err(PipelineError::State(
                "a frame is begun and not finished: make the budget options before it".into(),
            ));
        }
        if self.selector.is_none() {
            return Err(PipelineError::State(
                "a shared frame budget needs automatic levels (the levels are fixed)".into(),
            ));
        }
        camera.validate()?;
        let started = Instant::now();
        let head = self.environment.head.transform_at(self.state.time);
        self.observe_sections(camera)?;
        let selector = self.selector.as_mut().expect("checked above");
        let options = selector.budget_options(
            &self.observations,
            camera,
            &head,
            model,
            &self.section_work,
        )?;
        self.options_made = Some((self.state.frame, started.elapsed().as_secs_f64()));
        Ok(options)
    }

    /// [`begin_frame`](Self::begin_frame) with the sections' `levels` given (one per section,
    /// each raised to its floor if below it), chosen from this frame's
    /// [`budget_options`](Self::budget_options) by a budget shared with other pipelines. Errors
    /// when the options were not made this frame.
    pub fn begin_frame_with_levels(
        &mut self,
        camera: &Camera,
        levels: &[Level],
    ) -> Result<LodChanges> {
        if let Some(pending) = self.pending {
            return Ok(pending.changes);
        }
        match self.options_made {
            Some((frame, _)) if frame == self.state.frame => {}
            _ => {
                return Err(PipelineError::State(
                    "the budget options were not made this frame: call budget_options first".into(),
                ));
            }
        }
        self.begin_frame_from(camera, Some(levels))
    }

    /// [`begin_frame`](Self::begin_frame) with the levels chosen by the selector (`None`) or
    /// given from budget options already made (`Some`).
    fn begin_frame_from(&mut self, camera: &Camera, given: Option<&[Level]>) -> Result<LodChanges> {
        if let Some(pending) = self.pending {
            return Ok(pending.changes);
        }
        camera.validate()?;
        let mut times = StageTimes::default();
        let started = Instant::now();
        let head = self.environment.head.transform_at(self.state.time);
        let (levels, visibility) = self.select_levels(camera, &head, given)?;
        let changes = LodChanges { levels, visibility };
        let blends_ended = self.state.levels.blends_finished(self.state.time);
        if levels > 0 || blends_ended {
            self.apply_level_changes(&head)?;
        }
        times.lod = started.elapsed().as_secs_f64();
        if given.is_some() {
            times.lod += self.options_made.take().map_or(0.0, |(_, seconds)| seconds);
        }
        self.pending = Some(PendingFrame { changes, times });
        Ok(changes)
    }

    /// The rest of a frame begun with [`Pipeline::begin_frame`]: one dynamics step with collision
    /// per block, the clock advanced by `settings.dynamics.time_step`. Without a begun frame it
    /// steps with the levels as they are (no selection).
    pub fn finish_frame(&mut self) -> Result<FrameReport> {
        let PendingFrame { changes, mut times } = self.pending.take().unwrap_or_default();
        let mut contacts = 0;
        let mut max_stretch = 0.0f32;
        let mut level_seconds = [0.0; 3];
        let time = self.state.time;
        for level in Level::ALL {
            let before = times.dynamics + times.collision;
            let block = &mut self.state.blocks[level];
            let work = &mut self.work[level];
            let Some(simulation) = work.simulation.as_mut() else {
                continue;
            };
            block.state.time = time;
            let environment = &self.environment;
            match &mut work.solver {
                Some(solver) => {
                    let started = Instant::now();
                    let report = solver.before_step(
                        &mut self.bodies,
                        simulation,
                        &mut block.state,
                        environment,
                    )?;
                    contacts += report.contact_segments;
                    times.collision += started.elapsed().as_secs_f64();
                    let started = Instant::now();
                    simulation.step(&mut block.state, environment)?;
                    times.dynamics += started.elapsed().as_secs_f64();
                    let started = Instant::now();
                    let projection = solver.after_step(
                        &mut self.bodies,
                        simulation,
                        &mut block.state,
                        environment,
                    )?;
                    max_stretch = max_stretch.max(projection.max_stretch);
                    times.collision += started.elapsed().as_secs_f64();
                }
                None => {
                    let started = Instant::now();
                    simulation.step(&mut block.state, environment)?;
                    times.dynamics += started.elapsed().as_secs_f64();
                }
            }
            level_seconds[level as usize] = times.dynamics + times.collision - before;
        }
        self.state.time += f64::from(self.settings.dynamics.time_step);
        let (drawn_at, pixels_at) = self.drawn_work();
        let report = FrameReport {
            frame: self.state.frame,
            time: self.state.time,
            sections_at: self.state.sections_at(),
            visible_sections: self.state.choices.iter().filter(|c| c.visible).count(),
            level_changes: changes.levels,
            visibility_changes: changes.visibility,
            blending_sections: self.state.levels.blending_count(),
            simulated_nodes: self.state.simulated_nodes(),
            drawn_segments: drawn_at.iter().sum(),
            drawn_at,
            pixels_at,
            level_seconds,
            level_nodes: Level::ALL.map(|level| self.state.blocks[level].node_count()),
            contacts,
            max_stretch,
            times,
        };
        self.state.frame += 1;
        Ok(report)
    }

    /// Observes every section on its current level (its observation and covered pixels this
    /// frame, for the selector and the cost model); nothing at a fixed level.
    fn observe_sections(&mut self, camera: &Camera) -> Result<()> {
        let Some(selector) = self.selector.as_ref() else {
            return Ok(());
        };
        super::observe::observe_sections(
            super::observe::Observed {
                groom: &self.scene.groom,
                environment: &self.environment,
                air_drag_rate: self.params.air_drag_rate,
                frame_time: self.settings.dynamics.time_step,
                state: &self.state,
                lod: selector.settings(),
            },
            camera,
            &mut self.observations,
            &mut self.section_pixels,
        )
    }

    /// Chooses levels (from the selector, or the `given` levels of a shared budget) and starts
    /// the changes; returns how many sections changed level and how many came into view or left
    /// it (their transitions and fades are started in the state's levels).
    fn select_levels(
        &mut self,
        camera: &Camera,
        head: &RigidTransform,
        given: Option<&[Level]>,
    ) -> Result<(usize, usize)> {
        if self.selector.is_none() {
            return Ok((0, 0));
        }
        if given.is_none() {
            self.observe_sections(camera)?;
        }
        let selector = self.selector.as_mut().expect("checked above");
        let choices = match (given, &self.budget) {
            (Some(levels), _) => selector.choose_levels(levels)?,
            (None, Some((budget, model))) => {
                // The frame's overhead is not any section's: leave it out of what they share.
                let share = (budget - model.rates().overhead).max(0.0);
                selector
                    .select_within_budget(
                        &self.observations,
                        camera,
                        head,
                        share,
                        model,
                        &self.section_work,
                    )?
                    .0
            }
            (None, None) => selector.select(&self.observations, camera, head)?,
        };
        let state = &mut self.state;
        state.choices.copy_from_slice(choices);
        state.selector_depths.clear();
        state.selector_depths.extend_from_slice(selector.depths());
        // The first frame picks the starting levels outright: there is nothing on screen to
        // blend from.
        let blend = if state.frame == 0 {
            0.0
        } else {
            selector.settings().blend_time
        };
        let time = state.time;
        let mut changes = 0;
        let mut visibility_changes = 0;
        let shares = selector.blend_shares();
        for (section, choice) in state.choices.iter().enumerate() {
            if state.levels.current()[section] != choice.level {
                // A switch the look ahead foresaw sooner than its lead blends over its share.
                let share = shares[section];
                state
                    .levels
                    .switch(section, choice.level, time, blend * share);
                changes += 1;
            }
            // Coming into view or leaving it fades over the blend too: a section drawn at once
            // where the conservative occlusion test or the frustum let it through would pop.
            if state
                .levels
                .set_visible(section, choice.visible, time, blend)
            {
                visibility_changes += 1;
            }
        }
        Ok((changes, visibility_changes))
    }

    /// Points every collision stage at its block's chains (rebuilds hierarchies on change).
    fn refresh_collision_chains(&mut self) -> Result<()> {
        let groom = &self.scene.groom;
        for level in Level::ALL {
            let block = &self.state.blocks[level];
            let work = &mut self.work[level];
            let (Some(solver), Some(simulation)) = (work.solver.as_mut(), work.simulation.as_ref())
            else {
                continue;
            };
            self.collision_chains.clear();
            for (model_chain, &chain) in block.chains.iter().enumerate() {
                if let Some(mut collision) = groom_chain(groom, chain) {
                    collision.chain = model_chain as u32;
                    self.collision_chains.push(collision);
                }
            }
            solver.set_chains(simulation, &self.collision_chains)?;
        }
        Ok(())
    }

    /// The time [s] the drawn skeletons are shown at: the end of the frame, also when a frame is
    /// begun and not yet stepped (the clock has not advanced yet).
    fn display_time(&self) -> f64 {
        match self.pending {
            Some(_) => self.state.time + f64::from(self.settings.dynamics.time_step),
            None => self.state.time,
        }
    }

    /// Segments drawn and pixels covered at each level by the sections shown this frame (strand
    /// groups count each of their strands drawn: a dissolving strand level draws only its
    /// coverage's share of them; a dissolving surface is drawn whole and screen-doored, and not
    /// at all once its coverage is 0, as a surface that gave way is in the second half of its
    /// blend).
    fn drawn_work(&self) -> ([usize; 3], [f64; 3]) {
        super::drawn::drawn_work(
            &self.state.levels,
            &self.section_work,
            &self.section_pixels,
            self.display_time(),
        )
    }

    /// Fills `active` with the skeletons to draw, on the groom's chain numbering: the chains of
    /// every visible section at its level (and, while it blends, at its previous level too: the new
    /// level's coverage rises from 0 to 1 over the first half of the blend while the old one's
    /// falls from 1 to 0 over the whole blend, a dissolve, [`SectionLevels::coverage`]; a section coming
    /// into view or leaving it dissolves in or out over the blend as a whole), with node frames
    /// computed from the simulated
    /// positions; everything else inactive.
    pub fn gather_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        active.clear();
        self.append_drawn(active)
    }

    /// [`gather_drawn`](Self::gather_drawn) appended after the chains already in `active` (a
    /// crowd draws its characters' grooms one after the other, on chain numbers offset by the
    /// chains before).
    pub fn append_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        let head = self.environment.head.transform_at(self.state.time);
        super::drawn::append_drawn(
            &self.scene.groom,
            &self.state,
            &head,
            self.display_time(),
            &mut self.frames_scratch,
            active,
        )
    }
}
