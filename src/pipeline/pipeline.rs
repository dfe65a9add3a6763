//! [`Pipeline`]: one character's run, a [`World`] of one advanced by its [`WorldPipeline`], the
//! same frame loop as a crowd's (DESIGN "One frame"): control → level selection and transitions
//! → dynamics with collision → skeletons for the renderer, with the wall-clock time of each
//! stage.

use std::sync::Arc;

use hair_collide::CollisionBody;
use hair_core::dynamics::{ChainRoots, DynamicsModel, DynamicsParams, Environment, Simulation};
use hair_core::lod::{CostModel, LodSelector, SectionChoice};
use hair_core::{Camera, Level, RigidTransform, Scene};
use hair_render::ActiveSkeletons;

use super::block::LevelBlock;
use super::budget::FrameBudget;
use super::character::Shared;
use super::checkpoint::Checkpoint;
use super::error::Result;
use super::report::{FrameReport, LodChanges};
use super::settings::{LodMode, PipelineSettings};
use super::state::PipelineState;
use super::world::{Character, CharacterModel, World};
use super::world_pipeline::WorldPipeline;

/// A hair simulation with levels of detail: one character in a world of its own. It keeps three
/// things apart (like rapier's `PhysicsPipeline` and MuJoCo's `mjModel`/`mjData`):
/// - the model: the [`Scene`] (groom and head), the environment and the settings, fixed for the
///   run ([`World`], [`CharacterModel`]);
/// - the state: a [`PipelineState`], everything that evolves (skeletons at each level, levels,
///   blends, visibility, the selector's memory, time), which [`Pipeline::state`] returns and
///   [`Pipeline::resume`] starts from;
/// - working memory: each level's solver and collision stage (each posing its own copy of the
///   head's collision body, whose mesh and tree are shared), the level selector's constants,
///   per-frame buffers, held by the world's pipeline. Nothing of it is saved: a resumed run
///   rebuilds it from the state.
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
    /// The character: model and state.
    world: World,
    /// The working memory that advances it.
    stages: WorldPipeline,
}

impl Pipeline {
    /// A pipeline for `scene` driven by `environment` (head motion, wind, gravity), every section
    /// at rest at the finest level, strand groups (automatic mode: [`settle`](Self::settle) lets
    /// the hair fall into place at full detail, and the first frame hands each section down to
    /// the level it is given), or at the fixed level.
    /// The scene may be an `Arc<Scene>` shared with other pipelines.
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
        let model = CharacterModel {
            scene: scene.into(),
            environment,
            params,
        };
        let (world, stages) = WorldPipeline::build([(model, Shared::default())], settings)?;
        Ok(Pipeline { world, stages })
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
        pipeline.stages.restore(&mut pipeline.world, checkpoint)?;
        Ok(pipeline)
    }

    /// The world: this pipeline's one character, its model and state, and the settings.
    pub fn world(&self) -> &World {
        &self.world
    }

    pub(crate) fn character(&self) -> &Character {
        &self.world.characters[0]
    }

    /// Where the groom rides a deforming head (`None` for a rigid one).
    pub(crate) fn ride(&self) -> Option<&super::body_motion::BodyRide> {
        self.stages.work(0).ride.as_ref()
    }

    /// The head's collision body (`None` with collision off), posed at this pipeline's head.
    pub fn collision_body(&self) -> Option<&CollisionBody> {
        self.stages.work(0).body.as_ref()
    }

    /// The fingerprint of this run's model: the groom (parameters and skeleton rest data:
    /// lengths, rest and natural angles, roots), the head mesh, the environment and the
    /// settings, hashed (FNV-1a, 64 bits) to 16 hex digits.
    /// A checkpoint resumes only where the fingerprint is the same.
    pub fn fingerprint(&self) -> String {
        self.world.fingerprint()
    }

    /// Everything of the run that evolves, for a checkpoint ([`Checkpoint::new`] with
    /// [`Pipeline::fingerprint`]); between frames (a frame begun with
    /// [`begin_frame`](Self::begin_frame) and not finished is refused).
    pub fn state(&self) -> Result<PipelineState> {
        let character = self.character();
        super::character::saved_state(&character.state, self.stages.work(0))
    }

    /// A checkpoint of the run now.
    pub fn checkpoint(&self) -> Result<Checkpoint> {
        self.stages.checkpoint(&self.world)
    }

    /// Lets the hair settle from its rest shape under gravity (and the environment at time 0)
    /// for `seconds` [s] at the current levels, without choosing levels or advancing the clock:
    /// a groom's rest shape is not an equilibrium under gravity, and a run should not start with
    /// hair falling into place (which the motion criterion would rightly read as motion).
    pub fn settle(&mut self, seconds: f32) -> Result<()> {
        self.stages.settle(&mut self.world, seconds)
    }

    /// Advances one frame of `settings.dynamics.time_step` seconds seen by `camera`: chooses
    /// levels, hands state over where a section changed level, steps every block with collision.
    /// The same as [`Pipeline::begin_frame`] then [`Pipeline::finish_frame`].
    pub fn advance(&mut self, camera: &Camera) -> Result<FrameReport> {
        self.stages.advance(&mut self.world, camera)
    }

    /// The level-of-detail stage of a frame seen by `camera`: chooses levels (by the pixel
    /// tolerance or within the frame budget), starts and ends blends and hands state over where
    /// a section changed level, without stepping the dynamics; returns how many sections changed
    /// level or visibility. Drawing now ([`Pipeline::gather_drawn`]) shows the frame's levels and
    /// blend coverages on the skeletons of the frame before, so the image change that the level
    /// decisions alone make can be measured (the popping measure). A frame already begun is not
    /// begun again (its changes are returned).
    pub fn begin_frame(&mut self, camera: &Camera) -> Result<LodChanges> {
        self.stages.begin_frame(&mut self.world, camera)
    }

    /// The rest of a frame begun with [`Pipeline::begin_frame`]: one dynamics step with collision
    /// per block, the clock advanced by `settings.dynamics.time_step`. Without a begun frame it
    /// steps with the levels as they are (no selection).
    pub fn finish_frame(&mut self) -> Result<FrameReport> {
        self.stages.finish_frame(&mut self.world)
    }

    /// Fills `active` with the skeletons to draw, on the groom's chain numbering: the chains of
    /// every visible section at its level (and, while it blends, at its previous level too: the
    /// new level's coverage rises from 0 to 1 over the first half of the blend while the old
    /// one's falls from 1 to 0 over the whole blend, a dissolve,
    /// [`SectionLevels::coverage`](super::SectionLevels::coverage); a section coming into view or
    /// leaving it dissolves in or out over the blend as a whole), with node frames computed from
    /// the simulated positions; everything else inactive.
    pub fn gather_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        active.clear();
        self.append_drawn(active)
    }

    /// [`gather_drawn`](Self::gather_drawn) appended after the chains already in `active`.
    pub fn append_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        self.stages.append_drawn(&mut self.world, active)
    }

    /// Fills `shifts` (cleared first) with each strand's shift [m, world] from where the
    /// renderer draws its root on the skeletons `active` holds (as
    /// [`gather_drawn`](Self::gather_drawn) filled it) to where the deforming body carries it
    /// now, in the groom's strand order, for
    /// [`Renderer::set_strand_root_shifts`](hair_render::Renderer::set_strand_root_shifts):
    /// the skin stretches, and the skeletons' rest offsets do not follow each root's triangle.
    /// Zero for strands not drawn; `shifts` left empty for a rigid head.
    pub fn strand_root_shifts(&self, active: &ActiveSkeletons, shifts: &mut Vec<glam::Vec3>) {
        self.stages.strand_root_shifts(&self.world, active, shifts);
    }

    /// Chooses levels within a frame budget of `seconds` [s] from the next frame on, minimising
    /// the total estimated error (the same choice as a crowd's over all its characters, and as
    /// [`LodSelector::select_within_budget`]) with costs from `model`, which
    /// [`observe_frame`](Self::observe_frame) calibrates; `None` goes back to the pixel
    /// tolerance. Errors at a fixed level (there is nothing to choose) and for a budget that is
    /// not a positive number of seconds.
    pub fn set_frame_budget(&mut self, budget: Option<(f64, CostModel)>) -> Result<()> {
        self.stages.set_frame_budget(&self.world, budget)
    }

    /// The frame budget [s] and cost model, when levels are chosen within a budget.
    pub fn frame_budget(&self) -> Option<&FrameBudget> {
        self.stages.frame_budget()
    }

    /// Calibrates the frame budget's cost model with a finished frame's `report` (its rendering
    /// time filled in when the frame was drawn). Does nothing without a budget.
    pub fn observe_frame(&mut self, report: &FrameReport) {
        self.stages.observe_frame(report);
    }

    /// Sets the selector's pixel tolerance [pixels] from the next frame on (a frame-budget
    /// controller steers it); nothing at a fixed level.
    pub fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        self.stages
            .set_pixel_tolerance(&mut self.world, pixel_tolerance)
    }

    /// Switches between automatic levels and a fixed level from the next frame on (an
    /// interactive viewer's "force a level"). To a fixed level, every section is switched through
    /// the same hand-over (§4.2) and blend as an automatic change (blending over the current
    /// selector's blend time) and shown whether in view or not, as a fixed-level run does; back to
    /// automatic levels, a selector with `lod` settings starts from the levels the sections are at
    /// and chooses at the next frame. The run's fingerprint follows the settings. Refused while a
    /// frame is begun and not finished.
    pub fn set_lod_mode(&mut self, mode: LodMode) -> Result<()> {
        self.stages.set_lod_mode(&mut self.world, mode)
    }

    /// Replaces the environment (head motion, wind, gravity) from the next frame on (an
    /// interactive viewer's wind and head-motion switches). The head's pose jumps to the new
    /// motion's pose at the current time. The run's fingerprint follows the environment.
    /// Refused while a frame is begun and not finished.
    pub fn set_environment(&mut self, environment: Environment) -> Result<()> {
        self.stages
            .refuse_while_begun("change the environment between frames")?;
        self.world.characters[0].model.environment = environment;
        Ok(())
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.character().model.scene
    }

    /// The settings.
    pub fn settings(&self) -> &PipelineSettings {
        &self.world.settings
    }

    /// The environment (head motion, wind, gravity).
    pub fn environment(&self) -> &Environment {
        &self.character().model.environment
    }

    /// The level selector (`None` with a fixed level).
    pub fn selector(&self) -> Option<&LodSelector> {
        self.stages.work(0).selector.as_ref()
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        self.character().state.time
    }

    /// Frames advanced so far.
    pub fn frame(&self) -> usize {
        self.character().state.frame
    }

    /// The current level of every section.
    pub fn section_levels(&self) -> &[Level] {
        self.character().section_levels()
    }

    /// The last choice of every section (level, visibility, reason).
    pub fn choices(&self) -> &[SectionChoice] {
        self.character().choices()
    }

    /// The block of `level`: the sections simulated at it and their state.
    pub fn block(&self, level: Level) -> &LevelBlock {
        self.character().block(level)
    }

    /// The dynamics model `level`'s block is stepped with (none while the block is empty): its
    /// chains are the block's, in the block's order, and its nodes index the block's state.
    pub fn level_model(&self, level: Level) -> Option<&DynamicsModel> {
        self.stages.work(0).work.levels[level]
            .simulation
            .as_ref()
            .map(Simulation::model)
    }

    /// The head's pose at the time the skeletons are at (the end of the last frame stepped).
    pub fn head_pose(&self) -> RigidTransform {
        self.character().head_pose()
    }

    /// Where every skeleton chain of the groom has its root at the time the skeletons are at:
    /// on the head, carried by the deforming body first where the head deforms.
    pub fn chain_roots(&self) -> ChainRoots<'_> {
        super::body_motion::chain_roots(self.ride(), &self.head_pose(), self.time())
    }
}
