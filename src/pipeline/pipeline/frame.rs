//! A pipeline's frame, stage by stage (DESIGN "One frame"): observe the sections, select their
//! levels (by the pixel tolerance or a frame budget), hand over where a level changed, step every
//! block with collision ([`crate::pipeline::step`]), gather what to draw.

use std::time::Instant;

use hair_core::lod::{CostModel, SectionOptions};
use hair_core::{Camera, Level};
use hair_render::ActiveSkeletons;

use super::{PendingFrame, Pipeline};
use crate::pipeline::error::{PipelineError, Result};
use crate::pipeline::report::{FrameReport, LodChanges, StageTimes};
use crate::pipeline::select::LevelSource;
use crate::pipeline::step::BlockStepped;

impl Pipeline {
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
        if let Some(pending) = self.pending {
            return Ok(pending.changes);
        }
        let budget = match (&self.selector, self.budget.take()) {
            (Some(_), Some(budget)) => budget,
            (_, budget) => {
                self.budget = budget;
                return self.begin_frame_from(camera, None);
            }
        };
        // A character alone under a budget is a crowd of one: the same options, refinement and
        // given levels as a crowd's frame ([`crate::crowd::Crowd::advance`]).
        let mut levels = std::mem::take(&mut self.budget_levels);
        let chosen = self.budget_options(camera, &budget.1).map(|options| {
            let started = Instant::now();
            crate::pipeline::budget::choose_within_budget(options, &budget, &mut levels);
            started.elapsed().as_secs_f64()
        });
        self.budget = Some(budget);
        let changes = chosen.and_then(|seconds| {
            if let Some((_, made)) = &mut self.options_made {
                *made += seconds;
            }
            self.begin_frame_from(camera, Some(&levels))
        });
        self.budget_levels = levels;
        changes
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
            return Err(PipelineError::FrameBegun {
                action: "make the budget options before it",
            });
        }
        camera.validate()?;
        let started = Instant::now();
        let head = self.environment.head.transform_at(self.state.time);
        self.observe_sections(camera)?;
        let Some(selector) = self.selector.as_mut() else {
            return Err(PipelineError::FixedLevels {
                what: "a shared frame budget",
            });
        };
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
                return Err(PipelineError::NoBudgetOptions);
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
        let (levels, visibility) = match given {
            Some(levels) => self.select_levels(LevelSource::Given(levels))?,
            None => {
                self.observe_sections(camera)?;
                let observations = std::mem::take(&mut self.observations);
                let chosen = self.select_levels(LevelSource::Tolerance {
                    observations: &observations,
                    camera,
                    head: &head,
                });
                self.observations = observations;
                chosen?
            }
        };
        let changes = LodChanges { levels, visibility };
        let blends_ended = self.state.levels.blends_finished(self.state.time);
        if levels > 0 || blends_ended {
            self.hand_over(|model, state, work| {
                crate::pipeline::hand_over::apply_level_changes(model, state, work, &head)
            })?;
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
        let started = Instant::now();
        let time = self.state.time;
        let stepped = crate::pipeline::step::step_blocks(self.block_steps(None, time))?;
        let wall = started.elapsed().as_secs_f64();
        let mut report = self.end_frame(&stepped)?;
        crate::pipeline::step::charge_wall_time(&mut report, wall);
        Ok(report)
    }

    /// The end of a frame whose blocks were `stepped` ([`block_steps`](Self::block_steps) with
    /// the run's environment, from the state's time): the clock advanced by
    /// `settings.dynamics.time_step` and the frame's report, with the blocks' own dynamics and
    /// collision times (summed, not charged to the wall clock).
    pub(crate) fn end_frame(&mut self, stepped: &[BlockStepped]) -> Result<FrameReport> {
        let PendingFrame { changes, times } = self.pending.take().unwrap_or_default();
        self.state.time += f64::from(self.settings.dynamics.time_step);
        self.pose_body()?;
        let (drawn_at, pixels_at) = self.drawn_work();
        let mut report = FrameReport {
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
            level_nodes: Level::ALL.map(|level| self.state.blocks[level].node_count()),
            times,
            ..FrameReport::default()
        };
        for block in stepped {
            block.add_to(&mut report);
        }
        self.state.frame += 1;
        Ok(report)
    }

    /// Observes every section on its current level (its observation and covered pixels this
    /// frame, for the selector and the cost model); nothing at a fixed level.
    fn observe_sections(&mut self, camera: &Camera) -> Result<()> {
        let Some(selector) = self.selector.as_ref() else {
            return Ok(());
        };
        crate::pipeline::observe::observe_sections(
            crate::pipeline::observe::Observed {
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

    /// Chooses levels from `source` and starts the changes ([`crate::pipeline::select::select_levels`]);
    /// nothing at a fixed level.
    fn select_levels(&mut self, source: LevelSource<'_>) -> Result<(usize, usize)> {
        match self.selector.as_mut() {
            Some(selector) => {
                crate::pipeline::select::select_levels(selector, &mut self.state, source)
            }
            None => Ok((0, 0)),
        }
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
        crate::pipeline::drawn::drawn_work(
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
        crate::pipeline::drawn::append_drawn(
            &self.scene.groom,
            &self.state,
            &head,
            self.display_time(),
            &mut self.frames_scratch,
            active,
        )
    }
}
