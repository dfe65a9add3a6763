//! [`WorldPipeline`]: the working memory that advances a [`World`], and the one frame loop of
//! every run, a lone character's and a crowd's (DESIGN "One frame"):
//!
//! 1. observe and select: every character's sections observed and their levels chosen, each by
//!    its selector at the pixel tolerance, or all of them together by one greedy refinement
//!    within a frame budget ([`super::budget`]);
//! 2. hand over: each character's blocks rebuilt where its sections changed level;
//! 3. step: every level block of every character in one parallel pass ([`step_blocks`]), the
//!    settling fall the same step;
//! 4. end: each character's clock advanced and its report made; the reports summed.
//!
//! What is drawn is gathered afterwards ([`WorldPipeline::append_drawn`]).

use std::ops::Range;
use std::time::Instant;

use glam::Vec3;
use hair_core::dynamics::Environment;
use hair_core::lod::{BudgetOutcome, SectionOptions};
use hair_core::{Camera, Level};
use hair_render::ActiveSkeletons;

use super::body_motion::{ShiftedCharacter, strand_root_shifts};
use super::budget::FrameBudget;
use super::character::{CharacterRun, CharacterWork, Shared, build_character};
use super::checkpoint::Checkpoint;
use super::error::{PipelineError, Result};
use super::report::{FrameReport, LodChanges};
use super::settings::{LodMode, PipelineSettings};
use super::step::{charge_wall_time, on_pool, step_blocks};
use super::world::{CharacterModel, World};

/// The working memory that advances a world: each character's (solvers, collision stages, posed
/// bodies, selectors, buffers) and the frame budget's. Nothing of it is state.
pub(crate) struct WorldPipeline {
    characters: Vec<CharacterWork>,
    /// The frame budget that minimises error: the budget [s] and the calibrated cost model
    /// (`None`: levels from the pixel tolerance).
    budget: Option<FrameBudget>,
    /// Every character's sections' options this frame, one after the other, and each
    /// character's range in them (scratch).
    options: Vec<SectionOptions>,
    ranges: Vec<Range<usize>>,
    /// The levels the budget chose this frame (scratch).
    levels: Vec<Level>,
    /// What the last budgeted choice came to (predicted cost [s] and error [pixels]).
    outcome: Option<BudgetOutcome>,
}

impl WorldPipeline {
    /// A world of the characters of `models` run with `settings`, each at rest (automatic
    /// levels: strand groups; or the fixed level), with what each shares already built, and the
    /// pipeline that advances it.
    pub(crate) fn build<'a>(
        models: impl IntoIterator<Item = (CharacterModel, Shared<'a>)>,
        settings: PipelineSettings,
    ) -> Result<(World, WorldPipeline)> {
        let mut world = World {
            settings,
            characters: Vec::new(),
        };
        let mut characters = Vec::new();
        for (model, shared) in models {
            let (character, work) = build_character(model, &world.settings, shared)?;
            world.characters.push(character);
            characters.push(work);
        }
        let pipeline = WorldPipeline {
            characters,
            budget: None,
            options: Vec::new(),
            ranges: Vec::new(),
            levels: Vec::new(),
            outcome: None,
        };
        Ok((world, pipeline))
    }

    /// The stages' view of character `k` of `world`.
    pub(crate) fn run<'a>(&'a mut self, world: &'a mut World, k: usize) -> CharacterRun<'a> {
        let character = &mut world.characters[k];
        CharacterRun {
            model: &character.model,
            settings: &world.settings,
            state: &mut character.state,
            work: &mut self.characters[k],
        }
    }

    /// Every character's view, in the world's order.
    fn runs<'a>(&'a mut self, world: &'a mut World) -> impl Iterator<Item = CharacterRun<'a>> {
        let settings = &world.settings;
        world
            .characters
            .iter_mut()
            .zip(&mut self.characters)
            .map(move |(character, work)| CharacterRun {
                model: &character.model,
                settings,
                state: &mut character.state,
                work,
            })
    }

    /// Character `k`'s working memory.
    pub(crate) fn work(&self, k: usize) -> &CharacterWork {
        &self.characters[k]
    }

    /// Whether a frame is begun and not finished.
    pub(crate) fn frame_begun(&self) -> bool {
        self.characters.iter().any(|c| c.pending.is_some())
    }

    /// Errors while a frame is begun and not finished, naming what was refused (`action`).
    pub(crate) fn refuse_while_begun(&self, action: &'static str) -> Result<()> {
        if self.frame_begun() {
            return Err(PipelineError::FrameBegun { action });
        }
        Ok(())
    }

    /// The level-of-detail stage of a frame seen by `camera` for every character (steps 1 and 2
    /// above): levels chosen, blends started and ended, state handed over, nothing stepped;
    /// returns the changes summed. A frame already begun is not begun again.
    pub(crate) fn begin_frame(&mut self, world: &mut World, camera: &Camera) -> Result<LodChanges> {
        on_pool(|| self.begin_frame_on_pool(world, camera))
    }

    /// [`begin_frame`](Self::begin_frame), on a thread of the pool.
    fn begin_frame_on_pool(&mut self, world: &mut World, camera: &Camera) -> Result<LodChanges> {
        if self.frame_begun() {
            return Ok(self.pending_changes());
        }
        camera.validate()?;
        let automatic = matches!(world.settings.lod, LodMode::Auto(_));
        let mut sum = LodChanges::default();
        let Some(budget) = self.budget.take().filter(|_| automatic) else {
            for mut run in self.runs(world) {
                sum.add(run.begin_frame(camera, None)?);
            }
            return Ok(sum);
        };
        let chosen = self.begin_within_budget(world, camera, &budget);
        self.budget = Some(budget);
        chosen
    }

    /// Steps 1 and 2 with every character's levels chosen within `budget`: each character's
    /// options gathered, one refinement over them all, each character begun with its levels.
    fn begin_within_budget(
        &mut self,
        world: &mut World,
        camera: &Camera,
        budget: &FrameBudget,
    ) -> Result<LodChanges> {
        let mut options = std::mem::take(&mut self.options);
        let mut ranges = std::mem::take(&mut self.ranges);
        options.clear();
        ranges.clear();
        let mut gathered = Ok(());
        for mut run in self.runs(world) {
            let start = options.len();
            match run.budget_options(camera, &budget.1) {
                Ok(own) => options.extend_from_slice(own),
                Err(error) => {
                    gathered = Err(error);
                    break;
                }
            }
            ranges.push(start..options.len());
        }
        (self.options, self.ranges) = (options, ranges);
        gathered?;
        let started = Instant::now();
        self.outcome = Some(super::budget::choose_within_budget(
            &self.options,
            budget,
            &mut self.levels,
        ));
        let chosen = started.elapsed().as_secs_f64();
        let mut sum = LodChanges::default();
        let (levels, ranges) = (
            std::mem::take(&mut self.levels),
            std::mem::take(&mut self.ranges),
        );
        let mut begun = Ok(());
        for (k, range) in ranges.iter().enumerate() {
            match self
                .run(world, k)
                .begin_frame(camera, Some(&levels[range.clone()]))
            {
                Ok(changes) => sum.add(changes),
                Err(error) => {
                    begun = Err(error);
                    break;
                }
            }
        }
        (self.levels, self.ranges) = (levels, ranges);
        begun?;
        // The refinement is the frame's: its time is charged to the first character's stage.
        if let Some(pending) = self.characters.first_mut().and_then(|c| c.pending.as_mut()) {
            pending.times.lod += chosen;
        }
        Ok(sum)
    }

    /// The changes of the frame begun, summed over the characters.
    fn pending_changes(&self) -> LodChanges {
        let mut sum = LodChanges::default();
        for pending in self.characters.iter().filter_map(|c| c.pending) {
            sum.add(pending.changes);
        }
        sum
    }

    /// The rest of a frame begun with [`begin_frame`](Self::begin_frame) (steps 3 and 4): every
    /// level block of every character stepped in one pass, each clock advanced, the reports
    /// summed, with dynamics and collision charged to the wall-clock time the stepping took.
    /// Without a begun frame it steps with the levels as they are.
    pub(crate) fn finish_frame(&mut self, world: &mut World) -> Result<FrameReport> {
        on_pool(|| self.finish_frame_on_pool(world))
    }

    /// [`finish_frame`](Self::finish_frame), on a thread of the pool.
    fn finish_frame_on_pool(&mut self, world: &mut World) -> Result<FrameReport> {
        let mut body_update = 0.0;
        for mut run in self.runs(world) {
            let started = Instant::now();
            let time = run.state.time;
            run.prepare_body_at_end(time)?;
            body_update += started.elapsed().as_secs_f64();
        }
        let started = Instant::now();
        let mut steps = Vec::new();
        let mut counts = Vec::with_capacity(self.characters.len());
        for run in self.runs(world) {
            let time = run.state.time;
            let before = steps.len();
            steps.extend(run.into_block_steps(None, time));
            counts.push(steps.len() - before);
        }
        let stepped = step_blocks(steps)?;
        let mut report = FrameReport::default();
        let mut first = 0;
        for (k, (mut run, count)) in self.runs(world).zip(counts).enumerate() {
            let own = run.end_frame(&stepped[first..first + count])?;
            if k == 0 {
                (report.frame, report.time) = (own.frame, own.time);
            }
            report.add(&own);
            first += count;
        }
        charge_wall_time(&mut report, started.elapsed().as_secs_f64());
        // The deforming bodies' update is collision work, done once for every level.
        report.body_update = body_update;
        report.times.collision += body_update;
        Ok(report)
    }

    /// A frame seen by `camera`: [`begin_frame`](Self::begin_frame) then
    /// [`finish_frame`](Self::finish_frame).
    pub(crate) fn advance(&mut self, world: &mut World, camera: &Camera) -> Result<FrameReport> {
        on_pool(|| {
            self.begin_frame_on_pool(world, camera)?;
            self.finish_frame_on_pool(world)
        })
    }

    /// Lets every character's hair settle for `seconds` [s] with its head held still at its
    /// pose now, without choosing levels or advancing the clocks: the same step as a frame's,
    /// every block of every character in one pass.
    pub(crate) fn settle(&mut self, world: &mut World, seconds: f32) -> Result<()> {
        on_pool(|| self.settle_on_pool(world, seconds))
    }

    /// [`settle`](Self::settle), on a thread of the pool.
    fn settle_on_pool(&mut self, world: &mut World, seconds: f32) -> Result<()> {
        let mut still: Vec<(Environment, usize)> = Vec::with_capacity(self.characters.len());
        for run in self.runs(world) {
            still.push((run.settle_environment(), run.settle_steps(seconds)));
        }
        let longest = still.iter().map(|(_, steps)| *steps).max().unwrap_or(0);
        for step in 0..longest {
            let mut steps = Vec::new();
            for (run, (environment, count)) in self.runs(world).zip(&still) {
                if step < *count {
                    steps.extend(run.into_block_steps(Some(environment), 0.0));
                }
            }
            step_blocks(steps)?;
        }
        for mut run in self.runs(world) {
            run.settled();
        }
        Ok(())
    }

    /// Appends every character's skeletons to draw to `active`, one after the other, on chain
    /// numbers offset by the chains before.
    pub(crate) fn append_drawn(
        &mut self,
        world: &mut World,
        active: &mut ActiveSkeletons,
    ) -> Result<()> {
        for mut run in self.runs(world) {
            run.append_drawn(active)?;
        }
        Ok(())
    }

    /// Each strand's shift [m, world] onto where its character's body carries its root, for the
    /// skeletons `active` holds as [`append_drawn`](Self::append_drawn) laid them out: every
    /// character's strands one after the other (zeros for a rigid head's), in the order their
    /// grooms are uploaded ([`hair_render::Renderer::set_strand_root_shifts`]). `shifts` is
    /// left empty where no head deforms.
    pub(crate) fn strand_root_shifts(
        &self,
        world: &World,
        active: &ActiveSkeletons,
        shifts: &mut Vec<Vec3>,
    ) {
        let characters = world
            .characters
            .iter()
            .zip(&self.characters)
            .map(|(c, work)| ShiftedCharacter {
                groom: &c.model.scene.groom,
                ride: work.ride.as_ref(),
                head: c.head_pose(),
                time: c.time(),
            });
        strand_root_shifts(characters, active, shifts);
    }

    /// Chooses every character's levels within one frame budget [s] from the next frame on,
    /// with costs from its model; `None` goes back to the pixel tolerance. Errors at a fixed
    /// level and for a budget that is not a positive number of seconds.
    pub(crate) fn set_frame_budget(
        &mut self,
        world: &World,
        budget: Option<FrameBudget>,
    ) -> Result<()> {
        let automatic = matches!(world.settings.lod, LodMode::Auto(_));
        super::budget::check_budget(budget.as_ref(), automatic)?;
        self.budget = budget;
        Ok(())
    }

    /// The frame budget [s] and cost model, when levels are chosen within one.
    pub(crate) fn frame_budget(&self) -> Option<&FrameBudget> {
        self.budget.as_ref()
    }

    /// What the last budgeted choice came to; `None` without a budget.
    pub(crate) fn budget_outcome(&self) -> Option<BudgetOutcome> {
        self.budget.as_ref().and(self.outcome)
    }

    /// Calibrates the budget's cost model with a finished frame's summed `report`.
    pub(crate) fn observe_frame(&mut self, report: &FrameReport) {
        super::budget::calibrate(self.budget.as_mut(), report);
    }

    /// A checkpoint of every character of `world` now: each one's state with its collision
    /// stages' velocity memory, under the world's fingerprint
    /// ([`World::fingerprint`]); refused while a frame is begun.
    pub(crate) fn checkpoint(&self, world: &World) -> Result<Checkpoint> {
        let mut states = Vec::with_capacity(world.characters.len());
        for (character, work) in world.characters.iter().zip(&self.characters) {
            states.push(super::character::saved_state(&character.state, work)?);
        }
        let fingerprint = world.fingerprint();
        let mut states = states.into_iter();
        let first = states.next().ok_or(PipelineError::NoCharacters)?;
        Ok(Checkpoint::of_characters(
            fingerprint,
            first,
            states.collect(),
        ))
    }

    /// Replaces every character's state with the checkpoint's (each checked against its groom
    /// and the settings) and rebuilds the working memory around them. Refuses a checkpoint of
    /// another world (its fingerprint: scene, grooms, environments, settings, characters).
    pub(crate) fn restore(&mut self, world: &mut World, checkpoint: Checkpoint) -> Result<()> {
        let ours = world.fingerprint();
        let count = 1 + checkpoint.others.len();
        if checkpoint.scene_fingerprint != ours || count != world.characters.len() {
            return Err(PipelineError::ForeignCheckpoint {
                theirs: checkpoint.scene_fingerprint,
                ours,
            });
        }
        let states = std::iter::once(checkpoint.state).chain(checkpoint.others);
        for (mut run, state) in self.runs(world).zip(states) {
            run.restore(state)?;
        }
        Ok(())
    }

    /// The pixel tolerance of the automatic levels [pixels] (`None` at a fixed level).
    pub(crate) fn pixel_tolerance(&self) -> Option<f32> {
        self.characters
            .first()
            .and_then(|c| c.selector.as_ref())
            .map(|s| s.settings().pixel_tolerance)
    }

    /// Sets every character's pixel tolerance [pixels] from the next frame on.
    pub(crate) fn set_pixel_tolerance(&mut self, world: &mut World, tolerance: f32) -> Result<()> {
        for mut run in self.runs(world) {
            run.set_pixel_tolerance(tolerance)?;
        }
        Ok(())
    }

    /// Switches every character between automatic levels and a fixed level from the next frame
    /// on ([`CharacterRun::switch_lod_mode`]); refused while a frame is begun.
    pub(crate) fn set_lod_mode(&mut self, world: &mut World, mode: LodMode) -> Result<()> {
        self.refuse_while_begun("change the level mode between frames")?;
        if mode == world.settings.lod {
            return Ok(());
        }
        for mut run in self.runs(world) {
            run.switch_lod_mode(mode)?;
        }
        world.settings.lod = mode;
        Ok(())
    }
}
