//! One character's working memory ([`CharacterWork`]: its levels' solvers and collision stages,
//! its posed collision body, its level selector, per-frame buffers) and the view every stage
//! works through ([`CharacterRun`]: the character's model and state from the world beside its
//! working memory from the pipeline). Nothing here is state: a resumed run rebuilds it all from
//! the state ([`CharacterRun::restore`]).

use hair_collide::{BroadPhase, CollisionBody, RestField};
use hair_core::dynamics::Environment;
use hair_core::lod::{
    ErrorModel, LevelDeviation, LodSelector, SectionChoice, SectionObservation, SectionWork,
};
use hair_core::{Level, PerLevel};

use super::block::LevelBlock;
use super::body_motion::BodyRide;
use super::error::{PipelineError, Result};
use super::hand_over::HandOverModel;
use super::levels::SectionLevels;
use super::report::{LodChanges, StageTimes};
use super::settings::{LodMode, PipelineSettings};
use super::state::PipelineState;
use super::step::BlockStep;
use super::work::Workspace;
use super::world::{Character, CharacterModel};

/// What a character's working memory is given already built instead of building it (a crowd's
/// characters that wear one groom on one head build these once).
#[derive(Default, Clone, Copy)]
pub(crate) struct Shared<'a> {
    /// The sections' level deviations [m], one per section.
    pub(crate) deviations: Option<&'a [LevelDeviation]>,
    /// The head's collision body, built from this scene's head mesh.
    pub(crate) body: Option<&'a CollisionBody>,
}

/// What beginning a frame leaves for its end: the level changes and the stage times so far.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct PendingFrame {
    pub(crate) changes: LodChanges,
    pub(crate) times: StageTimes,
}

/// One character's working memory.
pub(crate) struct CharacterWork {
    /// Every level's solvers (each poses its own copy of the collision body).
    pub(crate) work: Workspace,
    /// The head's collision body (collision on), posed at the head at the state's time.
    pub(crate) body: Option<CollisionBody>,
    /// Where the groom rides a deforming head (the scene's body motion), if it deforms.
    pub(crate) ride: Option<BodyRide>,
    /// With a deforming head and collision: the collision body at the time the frame being
    /// stepped ends, which the levels' bodies become between the step and the projection, and
    /// the farthest its surface moved over the step [m].
    pub(crate) body_at_end: Option<(CollisionBody, f32)>,
    /// The time [s] `body_at_end` is at.
    pub(crate) body_at_end_time: f64,
    /// A deforming body's instant no longer needed, whose memory the next instant reuses
    /// ([`hair_collide::CollisionBody::deformed_reusing`]).
    pub(crate) spare_body: Option<CollisionBody>,
    /// The occluder boxes carried to the body now (scratch).
    pub(crate) occluders: Vec<(glam::Vec3, glam::Vec3)>,
    /// The level selector (automatic levels): its constants and scratch; its memory (choices,
    /// depths, tolerance) is the state's.
    pub(crate) selector: Option<LodSelector>,
    /// What each section simulates and draws at each level (for the cost model).
    pub(crate) section_work: Vec<SectionWork>,
    /// Screen area each section covers this frame [pixels] (its bounding disc).
    pub(crate) section_pixels: Vec<f64>,
    pub(crate) observations: Vec<SectionObservation>,
    /// The gather stage's scratch.
    pub(crate) draw_scratch: super::drawn::DrawScratch,
    /// A frame whose levels are chosen but whose dynamics step has not run.
    pub(crate) pending: Option<PendingFrame>,
    /// The frame whose budget options were made and the time it took [s], counted into that
    /// frame's level-of-detail stage.
    pub(crate) options_made: Option<(usize, f64)>,
}

/// A character's model and state (the world's) with its working memory (the pipeline's): what
/// each stage of a frame reads and writes.
pub(crate) struct CharacterRun<'a> {
    pub(crate) model: &'a CharacterModel,
    pub(crate) settings: &'a PipelineSettings,
    pub(crate) state: &'a mut PipelineState,
    pub(crate) work: &'a mut CharacterWork,
}

/// A character of `model` run with `settings`, every section at rest at the finest level (strand
/// groups, automatic levels) or at the fixed level, with its working memory.
pub(crate) fn build_character(
    model: CharacterModel,
    settings: &PipelineSettings,
    shared: Shared<'_>,
) -> Result<(Character, CharacterWork)> {
    settings.dynamics.validate()?;
    model.params.validate()?;
    let groom = &model.scene.groom;
    let sections = groom.section_count();
    let occluders = model.scene.head.occluder_boxes();
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
    let triangles = model.scene.head.mesh.triangles.len();
    let body = match (settings.collision, shared.body) {
        (false, _) => None,
        (true, Some(body)) if body.triangle_count() != triangles => {
            return Err(PipelineError::SharedBodyMismatch {
                body: body.triangle_count(),
                head: triangles,
            });
        }
        (true, Some(body)) => Some(body.clone()),
        (true, None) => Some(CollisionBody::from_mesh(&model.scene.head.mesh)?),
    };
    let mut ride = BodyRide::of(&model.scene, body.as_ref())?;
    // A deforming body is built again every frame. Its field contacts read the rest mesh's
    // field moved with it (`RestField`, built once); the other broad phases take the
    // hierarchies, since a field of one instant would be built again every frame.
    let broad_phase = match (&mut ride, &body) {
        (Some(ride), Some(body)) if settings.broad_phase == BroadPhase::FieldContacts => {
            let rest = RestField::of(body);
            ride.rest_occluders = Some(rest.boxes(&occluders));
            ride.rest_field = Some(rest);
            BroadPhase::FieldContacts
        }
        (Some(_), _) => BroadPhase::Hierarchies,
        (None, _) => settings.broad_phase,
    };
    if broad_phase != BroadPhase::Hierarchies
        && ride.is_none()
        && let Some(body) = &body
    {
        // Built with the character (once per mesh, shared by its copies), not in the first
        // frame's collision time.
        body.distance_field();
    }
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
    let mut work = CharacterWork {
        work: Workspace::new(body.as_ref(), broad_phase, ride.as_ref())?,
        body,
        ride,
        body_at_end: None,
        body_at_end_time: f64::NAN,
        spare_body: None,
        occluders: Vec::new(),
        selector,
        section_work: super::drawn::section_work(groom),
        section_pixels: vec![0.0; sections],
        observations: vec![SectionObservation::default(); sections],
        draw_scratch: super::drawn::DrawScratch::default(),
        pending: None,
        options_made: None,
    };
    let mut character = Character { model, state };
    let mut run = CharacterRun {
        model: &character.model,
        settings,
        state: &mut character.state,
        work: &mut work,
    };
    let head = run.head_pose();
    run.hand_over(|model, state, work| super::hand_over::start_at_rest(model, state, work, &head))?;
    run.pose_body()?;
    Ok((character, work))
}

/// `state` with the collision stages' velocity memory from `work`, for a checkpoint; refused
/// while a frame is begun and not finished.
pub(crate) fn saved_state(state: &PipelineState, work: &CharacterWork) -> Result<PipelineState> {
    if work.pending.is_some() {
        return Err(PipelineError::FrameBegun {
            action: "take the state between frames",
        });
    }
    let mut state = state.clone();
    for (level, block) in state.blocks.iter_mut() {
        if let Some(solver) = &work.work.levels[level].solver {
            block.collision_memory = solver.velocity_memory();
        }
    }
    Ok(state)
}

impl CharacterRun<'_> {
    /// The head's pose at the state's time.
    pub(crate) fn head_pose(&self) -> hair_core::RigidTransform {
        self.model.environment.head.transform_at(self.state.time)
    }

    /// Poses the collision body at the head at the state's time; a deforming head's is built
    /// again at that time, for the levels' collision stages too.
    pub(crate) fn pose_body(&mut self) -> Result<()> {
        let head = self.head_pose();
        if let (Some(ride), Some(_)) = (&self.work.ride, &self.work.body) {
            // The body where the last step ended is the body now (built for the projection).
            let body = match &self.work.body_at_end {
                Some((end, _)) if self.work.body_at_end_time == self.state.time => end.clone(),
                _ => {
                    ride.collision_body(
                        self.state.time,
                        self.settings.dynamics.time_step,
                        None,
                        None,
                    )?
                    .0
                }
            };
            for (_, level) in self.work.work.levels.iter_mut() {
                for copy in level.bodies.iter_mut() {
                    *copy = body.clone();
                }
            }
            // The body before is no longer needed: its memory makes the next instant.
            self.work.spare_body = self.work.body.replace(body);
        }
        if let Some(body) = &mut self.work.body {
            body.set_pose(head.rotation, head.translation)?;
        }
        Ok(())
    }

    /// With a deforming head read through its rest field, the selector's occluder boxes carried
    /// to the body at the state's time (`CollisionBody::carried_occluders`: the rest boxes moved
    /// by the deformation's rigid fit and shrunk by how far the surface near each strays from
    /// it, so that they stay inside the deformed body). Otherwise the boxes stay the rest
    /// body's.
    pub(crate) fn follow_occluders(&mut self) {
        let work = &mut *self.work;
        let (Some(ride), Some(body), Some(selector)) = (&work.ride, &work.body, &mut work.selector)
        else {
            return;
        };
        let Some(rest) = &ride.rest_occluders else {
            return;
        };
        if body.carried_occluders(rest, &mut work.occluders) {
            selector.set_occluders(&work.occluders);
        }
    }

    /// With a deforming head and collision, builds the collision body at the end of the step
    /// from `time` [s] ([`CharacterWork::body_at_end`]).
    pub(crate) fn prepare_body_at_end(&mut self, time: f64) -> Result<()> {
        let previous = self.work.body_at_end.take();
        self.work.body_at_end = match (&self.work.ride, &self.work.body) {
            (Some(ride), Some(body)) => {
                let step = self.settings.dynamics.time_step;
                let previous = previous.as_ref().map_or(body, |(previous, _)| previous);
                self.work.body_at_end_time = time + f64::from(step);
                let spare = self.work.spare_body.take();
                Some(ride.collision_body(time + f64::from(step), step, Some(previous), spare)?)
            }
            _ => None,
        };
        Ok(())
    }

    /// Runs a hand-over stage function on the model, the state and the working memory.
    pub(crate) fn hand_over<T>(
        &mut self,
        stage: impl FnOnce(HandOverModel<'_>, &mut PipelineState, &mut Workspace) -> Result<T>,
    ) -> Result<T> {
        let model = HandOverModel {
            groom: &self.model.scene.groom,
            params: self.model.params,
            settings: self.settings,
            ride: self.work.ride.as_ref(),
        };
        stage(model, self.state, &mut self.work.work)
    }

    /// Replaces the state with `state` (checked against the groom and the settings) and
    /// rebuilds every solver around it.
    pub(crate) fn restore(&mut self, state: PipelineState) -> Result<()> {
        state.check(&self.model.scene.groom, self.settings.dynamics.time_step)?;
        match (&mut self.work.selector, state.pixel_tolerance) {
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
        *self.state = state;
        self.hand_over(|model, state, work| super::hand_over::rebuild_all(model, state, work))?;
        self.pose_body()
    }

    /// The settling fall's still environment: the head held at its pose now, the rest as the
    /// run's.
    pub(crate) fn settle_environment(&self) -> Environment {
        Environment {
            head: hair_core::dynamics::HeadMotion::Still(self.head_pose()),
            ..self.model.environment.clone()
        }
    }

    /// The steps of a settling fall of `seconds` [s].
    pub(crate) fn settle_steps(&self, seconds: f32) -> usize {
        (seconds / self.settings.dynamics.time_step).ceil().max(0.0) as usize
    }

    /// Puts the blocks' clocks back on the run's after the settling fall.
    pub(crate) fn settled(&mut self) {
        for (_, block) in self.state.blocks.iter_mut() {
            block.state.time = self.state.time;
        }
    }
}

impl<'a> CharacterRun<'a> {
    /// Every level block with its working memory, to step in `environment` (the character's
    /// when `None`) from `time` [s] ([`super::step::step_blocks`]). A given environment is the
    /// settling fall's: a deforming head is held at rest through it.
    pub(crate) fn into_block_steps(
        self,
        environment: Option<&'a Environment>,
        time: f64,
    ) -> impl Iterator<Item = BlockStep<'a>> + 'a {
        let CharacterRun {
            model, state, work, ..
        } = self;
        let hold_body = environment.is_some();
        let environment = environment.unwrap_or(&model.environment);
        let body_at_end = if hold_body {
            None
        } else {
            work.body_at_end
                .as_ref()
                .map(|(body, moved)| (body, *moved))
        };
        super::step::character_steps(
            state.blocks.iter_mut(),
            work.work.levels.iter_mut(),
            super::step::StepInputs {
                environment,
                time,
                hold_body,
                body_at_end,
            },
        )
    }
}
