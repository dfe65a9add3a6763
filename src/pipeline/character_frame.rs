//! One character's part of a frame, stage by stage (DESIGN "One frame"): observe its sections,
//! select their levels (by the pixel tolerance, or given from a frame budget shared by the
//! world), hand over where a level changed, end the frame once its blocks are stepped, gather
//! what to draw. The world's pipeline ([`super::world_pipeline`]) runs these for every character
//! and steps all their blocks in one pass between.

use std::time::Instant;

use hair_core::lod::{CostModel, LodSelector, SectionChoice, SectionOptions};
use hair_core::{Camera, Level};
use hair_render::ActiveSkeletons;

use super::character::{CharacterRun, PendingFrame};
use super::error::{PipelineError, Result};
use super::report::{FrameReport, LodChanges, StageTimes};
use super::select::LevelSource;
use super::settings::LodMode;
use super::step::BlockStepped;

impl CharacterRun<'_> {
    /// Every section's options for a frame budget: the sections observed through `camera` and
    /// their estimated errors, costs (from `model`) and floors
    /// ([`LodSelector::budget_options`]). Errors at a fixed level.
    pub(crate) fn budget_options(
        &mut self,
        camera: &Camera,
        model: &CostModel,
    ) -> Result<&[SectionOptions]> {
        let started = Instant::now();
        let head = self.head_pose();
        self.follow_occluders();
        self.observe_sections(camera)?;
        let work = &mut *self.work;
        let Some(selector) = work.selector.as_mut() else {
            return Err(PipelineError::FixedLevels {
                what: "a frame budget",
            });
        };
        let options = selector.budget_options(
            &work.observations,
            camera,
            &head,
            model,
            &work.section_work,
        )?;
        work.options_made = Some((self.state.frame, started.elapsed().as_secs_f64()));
        Ok(options)
    }

    /// The level-of-detail stage of a frame seen by `camera`, with the levels chosen by the
    /// selector (`None`) or given from budget options made this frame (`Some`, one per section,
    /// each raised to its floor): chooses levels, starts and ends blends and hands state over
    /// where a section changed level, without stepping. A frame already begun is not begun
    /// again (its changes are returned).
    pub(crate) fn begin_frame(
        &mut self,
        camera: &Camera,
        given: Option<&[Level]>,
    ) -> Result<LodChanges> {
        if let Some(pending) = self.work.pending {
            return Ok(pending.changes);
        }
        camera.validate()?;
        let mut times = StageTimes::default();
        let started = Instant::now();
        let head = self.head_pose();
        let (levels, visibility) = match given {
            // Given levels were chosen by `budget_options`, which carried the occluders.
            Some(levels) => self.select_levels(LevelSource::Given(levels))?,
            None => {
                self.follow_occluders();
                self.observe_sections(camera)?;
                let observations = std::mem::take(&mut self.work.observations);
                let chosen = self.select_levels(LevelSource::Tolerance {
                    observations: &observations,
                    camera,
                    head: &head,
                });
                self.work.observations = observations;
                chosen?
            }
        };
        let changes = LodChanges { levels, visibility };
        let blends_ended = self.state.levels.blends_finished(self.state.time);
        if levels > 0 || blends_ended {
            self.hand_over(|model, state, work| {
                super::hand_over::apply_level_changes(model, state, work, &head)
            })?;
        }
        times.lod = started.elapsed().as_secs_f64();
        if given.is_some() {
            times.lod += self
                .work
                .options_made
                .take()
                .map_or(0.0, |(_, seconds)| seconds);
        }
        self.work.pending = Some(PendingFrame { changes, times });
        Ok(changes)
    }

    /// The end of a frame whose blocks were `stepped` (with the character's environment, from
    /// the state's time): the clock advanced by `settings.dynamics.time_step` and the frame's
    /// report, with the blocks' own dynamics and collision times (summed, not charged to the
    /// wall clock).
    pub(crate) fn end_frame(&mut self, stepped: &[BlockStepped]) -> Result<FrameReport> {
        let PendingFrame { changes, times } = self.work.pending.take().unwrap_or_default();
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
        let work = &mut *self.work;
        let Some(selector) = work.selector.as_ref() else {
            return Ok(());
        };
        super::observe::observe_sections(
            super::observe::Observed {
                groom: &self.model.scene.groom,
                environment: &self.model.environment,
                air_drag_rate: self.model.params.air_drag_rate,
                frame_time: self.settings.dynamics.time_step,
                state: self.state,
                lod: selector.settings(),
            },
            camera,
            &mut work.observations,
            &mut work.section_pixels,
        )
    }

    /// Chooses levels from `source` and starts the changes ([`super::select::select_levels`]);
    /// nothing at a fixed level.
    fn select_levels(&mut self, source: LevelSource<'_>) -> Result<(usize, usize)> {
        match self.work.selector.as_mut() {
            Some(selector) => super::select::select_levels(selector, self.state, source),
            None => Ok((0, 0)),
        }
    }

    /// The time [s] the drawn skeletons are shown at: the end of the frame, also when a frame is
    /// begun and not yet stepped (the clock has not advanced yet).
    fn display_time(&self) -> f64 {
        match self.work.pending {
            Some(_) => self.state.time + f64::from(self.settings.dynamics.time_step),
            None => self.state.time,
        }
    }

    /// Segments drawn and pixels covered at each level by the sections shown this frame
    /// ([`super::drawn::drawn_work`]).
    fn drawn_work(&self) -> ([usize; 3], [f64; 3]) {
        super::drawn::drawn_work(
            &self.state.levels,
            self.settings.drawn_as,
            &self.work.section_work,
            &self.work.section_pixels,
            self.display_time(),
        )
    }

    /// Appends the skeletons to draw after the chains already in `active`
    /// ([`super::drawn::append_drawn`]).
    pub(crate) fn append_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        let head = self.head_pose();
        let roots =
            super::body_motion::chain_roots(self.work.ride.as_ref(), &head, self.state.time);
        let gathered = super::drawn::Gathered {
            groom: &self.model.scene.groom,
            state: self.state,
            roots,
            display_time: self.display_time(),
            drawn_as: self.settings.drawn_as,
        };
        super::drawn::append_drawn(gathered, &mut self.work.draw_scratch, active)
    }

    /// Sets the selector's pixel tolerance [pixels] from the next frame on; nothing at a fixed
    /// level.
    pub(crate) fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        if let Some(selector) = self.work.selector.as_mut() {
            selector.set_pixel_tolerance(pixel_tolerance)?;
            self.state.pixel_tolerance = Some(pixel_tolerance);
        }
        Ok(())
    }

    /// Switches the character to `mode` (the settings still hold the mode it leaves): to a fixed
    /// level through the hand-over and blend of an automatic change, every section shown; to
    /// automatic levels with a selector that starts from the sections' levels.
    pub(crate) fn switch_lod_mode(&mut self, mode: LodMode) -> Result<()> {
        match mode {
            LodMode::Auto(lod) => {
                let scene = &self.model.scene;
                let mut selector =
                    LodSelector::new(&scene.groom, &scene.head.occluder_boxes(), lod)?;
                selector.set_frame_time(self.settings.dynamics.time_step)?;
                selector.restore_choices(&self.state.choices)?;
                // Depths from before a fixed spell are stale: the first choice does not look
                // ahead.
                self.state.selector_depths.clear();
                self.state.pixel_tolerance = Some(lod.pixel_tolerance);
                self.work.selector = Some(selector);
            }
            LodMode::Fixed(level) => {
                let blend = self
                    .work
                    .selector
                    .as_ref()
                    .map_or(0.0, |s| s.settings().blend_time);
                let time = self.state.time;
                for section in 0..self.model.scene.groom.section_count() {
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
                self.work.selector = None;
                self.state.pixel_tolerance = None;
                let head = self.head_pose();
                self.hand_over(|model, state, work| {
                    super::hand_over::apply_level_changes(model, state, work, &head)
                })?;
            }
        }
        Ok(())
    }
}
