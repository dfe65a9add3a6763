//! [`Crowd`]: a world of many characters advanced through the one frame loop
//! ([`WorldPipeline`]), with one tolerance or one frame budget across all their sections, and
//! one summed report.

use hair_collide::CollisionBody;
use hair_core::Camera;
use hair_core::lod::{BudgetOutcome, CostModel};
use hair_render::ActiveSkeletons;

use super::model::CrowdModel;
use crate::pipeline::{
    Checkpoint, FrameReport, PipelineSettings, Result, Shared, World, WorldPipeline,
};

/// A crowd in motion: every character in one world, advanced together.
pub struct Crowd {
    world: World,
    stages: WorldPipeline,
    names: Vec<String>,
}

impl Crowd {
    /// Every character of `model` with `settings`, at rest (settled for the shot's settle time).
    /// Refuses, before anything is allocated, a crowd whose estimated memory is over what the
    /// machine has available ([`super::memory::check_fits`]).
    pub fn new(model: &CrowdModel, settings: PipelineSettings) -> Result<Crowd> {
        let mut crowd = Crowd::at_rest(model, settings)?;
        crowd
            .stages
            .settle(&mut crowd.world, model.shot.settle_seconds)?;
        Ok(crowd)
    }

    /// A crowd of `model` with `settings` that goes on from `checkpoint` (written by
    /// [`Crowd::checkpoint`]), stepping exactly as the run that wrote it would have. Refuses a
    /// checkpoint of another crowd (its fingerprint: characters, grooms, places, motions,
    /// settings) or one whose states do not fit the grooms.
    pub fn resume(
        model: &CrowdModel,
        settings: PipelineSettings,
        checkpoint: Checkpoint,
    ) -> Result<Crowd> {
        let mut crowd = Crowd::at_rest(model, settings)?;
        crowd.stages.restore(&mut crowd.world, checkpoint)?;
        Ok(crowd)
    }

    /// Every character of the crowd's state now, for a checkpoint; between frames.
    pub fn checkpoint(&self) -> Result<Checkpoint> {
        self.stages.checkpoint(&self.world)
    }

    /// The frames advanced so far.
    pub fn frame(&self) -> usize {
        self.world
            .characters()
            .first()
            .map_or(0, |c| c.state().frame)
    }

    /// Every character of `model` at rest, not settled.
    fn at_rest(model: &CrowdModel, settings: PipelineSettings) -> Result<Crowd> {
        super::memory::check_fits(model, &settings, super::memory::available_bytes())?;
        let characters = model.members.iter().map(|member| {
            let character = member.model();
            let shared = Shared {
                deviations: Some(&member.deviations),
                body: Some(&member.body),
            };
            (character, shared)
        });
        let (world, stages) = WorldPipeline::build(characters, settings)?;
        Ok(Crowd {
            names: model
                .members
                .iter()
                .map(|m| m.character.name.clone())
                .collect(),
            world,
            stages,
        })
    }

    /// The world: every character's model and state, in the shot's order.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The characters' names, in the shot's order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The settings every character runs with.
    pub fn settings(&self) -> &PipelineSettings {
        self.world.settings()
    }

    /// Character `k`'s collision body (`None` with collision off), posed at its head: a copy
    /// that shares the mesh and tree with the other characters' of the same head.
    pub fn collision_body(&self, k: usize) -> Option<&CollisionBody> {
        self.stages.work(k).body.as_ref()
    }

    /// The pixel tolerance of the automatic levels [pixels] (`None` at a fixed level).
    pub fn pixel_tolerance(&self) -> Option<f32> {
        self.stages.pixel_tolerance()
    }

    /// Sets every character's pixel tolerance [pixels] from the next frame on.
    pub fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        self.stages
            .set_pixel_tolerance(&mut self.world, pixel_tolerance)
    }

    /// Chooses every character's levels within one frame budget of `seconds` [s] from the next
    /// frame on, minimising the crowd's total estimated error, with costs from `model` (which
    /// [`observe_frame`](Self::observe_frame) calibrates on the crowd's summed reports); `None`
    /// goes back to the pixel tolerance. Errors at a fixed level and for a budget that is not a
    /// positive number of seconds.
    pub fn set_frame_budget(&mut self, budget: Option<(f64, CostModel)>) -> Result<()> {
        self.stages.set_frame_budget(&self.world, budget)
    }

    /// The shared frame budget [s] and cost model, when levels are chosen within one.
    pub fn frame_budget(&self) -> Option<&(f64, CostModel)> {
        self.stages.frame_budget()
    }

    /// What the last frame's budgeted choice came to: its predicted cost [s] (without the
    /// frame's overhead) and total estimated error [pixels]; `None` without a budget.
    pub fn budget_outcome(&self) -> Option<BudgetOutcome> {
        self.stages.budget_outcome()
    }

    /// Calibrates the shared budget's cost model with a finished frame's summed `report`.
    pub fn observe_frame(&mut self, report: &FrameReport) {
        self.stages.observe_frame(report);
    }

    /// Advances every character one frame seen by `camera`: levels (each character's own
    /// selector at the pixel tolerance, or one greedy refinement over every section of the
    /// crowd within the budget), hand-over, dynamics with collision, every character's blocks
    /// in one pass. Returns the characters' reports summed ([`FrameReport::add`]).
    pub fn advance(&mut self, camera: &Camera) -> Result<FrameReport> {
        self.stages.advance(&mut self.world, camera)
    }

    /// Appends every character's skeletons to draw to `active`, one groom after the other, on
    /// chain numbers offset by the chains before.
    pub fn append_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        self.stages.append_drawn(&mut self.world, active)
    }

    /// Fills `shifts` (cleared first) with each strand's shift [m, world] onto where its
    /// character's deforming body carries its root, for the skeletons `active` holds (as
    /// [`append_drawn`](Self::append_drawn) laid them out), every character's strands one after
    /// the other (zeros for a rigid head's); left empty where no head deforms. See
    /// [`Pipeline::strand_root_shifts`](crate::pipeline::Pipeline::strand_root_shifts).
    pub fn strand_root_shifts(&self, active: &ActiveSkeletons, shifts: &mut Vec<glam::Vec3>) {
        self.stages.strand_root_shifts(&self.world, active, shifts);
    }
}
