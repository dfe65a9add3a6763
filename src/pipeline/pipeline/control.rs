//! A pipeline's controls between frames: the frame budget or pixel tolerance the levels are
//! chosen by, automatic or fixed levels, and the environment (an interactive viewer's switches).

use hair_core::dynamics::Environment;
use hair_core::lod::{CostModel, LodSelector, SectionChoice};

use super::Pipeline;
use crate::pipeline::error::{PipelineError, Result};
use crate::pipeline::report::FrameReport;
use crate::pipeline::settings::LodMode;

impl Pipeline {
    /// Chooses levels within a frame budget of `seconds` [s] from the next frame on, minimising
    /// the total estimated error (the same choice as a crowd's over all its characters, and as
    /// [`LodSelector::select_within_budget`]) with costs from
    /// `model`, which [`observe_frame`](Self::observe_frame) calibrates; `None` goes back to the
    /// pixel tolerance. Errors at a fixed level (there is nothing to choose) and for a budget
    /// that is not a positive number of seconds.
    pub fn set_frame_budget(&mut self, budget: Option<(f64, CostModel)>) -> Result<()> {
        crate::pipeline::budget::check_budget(budget.as_ref(), self.selector.is_some())?;
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
        crate::pipeline::budget::calibrate(self.budget.as_mut(), report);
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
            return Err(PipelineError::FrameBegun {
                action: "change the level mode between frames",
            });
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
                self.hand_over(|model, state, work| {
                    crate::pipeline::hand_over::apply_level_changes(model, state, work, &head)
                })?;
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
            return Err(PipelineError::FrameBegun {
                action: "change the environment between frames",
            });
        }
        self.environment = environment;
        Ok(())
    }
}
