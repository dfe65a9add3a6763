//! [`Crowd`]: every character's pipeline advanced through one frame, with one tolerance or one
//! frame budget across all their sections, and one summed report.

use std::ops::Range;
use std::time::Instant;

use hair_core::lod::{BudgetOutcome, CostModel, SectionOptions};
use hair_core::{Camera, Level};

use super::model::CrowdModel;
use crate::pipeline::{FrameReport, Pipeline, PipelineSettings, Result};

/// A crowd in motion: one [`Pipeline`] per character, advanced together.
pub struct Crowd {
    pipelines: Vec<Pipeline>,
    names: Vec<String>,
    settings: PipelineSettings,
    /// The shared frame budget [s] and its calibrated cost model (`None`: each character's
    /// selector holds the pixel tolerance).
    budget: Option<(f64, CostModel)>,
    /// Every character's sections' options this frame, one after the other, and each
    /// character's range in them.
    options: Vec<SectionOptions>,
    ranges: Vec<Range<usize>>,
    levels: Vec<Level>,
    /// What the last budgeted choice came to (predicted cost [s] and error [pixels]).
    outcome: Option<BudgetOutcome>,
}

impl Crowd {
    /// Every character of `model` in a pipeline with `settings`, at rest (settled for the shot's
    /// settle time).
    /// Refuses, before anything is allocated, a crowd whose estimated memory is over what the
    /// machine has available ([`super::memory::check_fits`]).
    pub fn new(model: &CrowdModel, settings: PipelineSettings) -> Result<Crowd> {
        super::memory::check_fits(model, &settings, super::memory::available_bytes())?;
        let mut pipelines = Vec::with_capacity(model.members.len());
        for member in &model.members {
            pipelines.push(Pipeline::with_shared(
                member.scene.clone(),
                member.character.environment.clone(),
                settings,
                &member.deviations,
                &member.body,
            )?);
        }
        crate::pipeline::settle_together(&mut pipelines, model.shot.settle_seconds)?;
        Ok(Crowd {
            names: model
                .members
                .iter()
                .map(|m| m.character.name.clone())
                .collect(),
            pipelines,
            settings,
            budget: None,
            options: Vec::new(),
            ranges: Vec::new(),
            levels: Vec::new(),
            outcome: None,
        })
    }

    /// The characters' pipelines, in the shot's order.
    pub fn pipelines(&self) -> &[Pipeline] {
        &self.pipelines
    }

    /// The characters' pipelines, mutable (a renderer gathers their skeletons).
    pub fn pipelines_mut(&mut self) -> &mut [Pipeline] {
        &mut self.pipelines
    }

    /// The characters' names, in the shot's order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The settings every character runs with.
    pub fn settings(&self) -> &PipelineSettings {
        &self.settings
    }

    /// The pixel tolerance of the automatic levels [pixels] (`None` at a fixed level).
    pub fn pixel_tolerance(&self) -> Option<f32> {
        self.pipelines
            .first()
            .and_then(|p| p.selector())
            .map(|s| s.settings().pixel_tolerance)
    }

    /// Sets every character's pixel tolerance [pixels] from the next frame on.
    pub fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        for pipeline in &mut self.pipelines {
            pipeline.set_pixel_tolerance(pixel_tolerance)?;
        }
        Ok(())
    }

    /// Chooses every character's levels within one frame budget of `seconds` [s] from the next
    /// frame on, minimising the crowd's total estimated error, with costs from `model` (which
    /// [`observe_frame`](Self::observe_frame) calibrates on the crowd's summed reports); `None`
    /// goes back to the pixel tolerance. Errors at a fixed level and for a budget that is not a
    /// positive number of seconds.
    pub fn set_frame_budget(&mut self, budget: Option<(f64, CostModel)>) -> Result<()> {
        let automatic = matches!(self.settings.lod, crate::pipeline::LodMode::Auto(_));
        crate::pipeline::check_budget(budget.as_ref(), automatic)?;
        self.budget = budget;
        Ok(())
    }

    /// The shared frame budget [s] and cost model, when levels are chosen within one.
    pub fn frame_budget(&self) -> Option<&(f64, CostModel)> {
        self.budget.as_ref()
    }

    /// What the last frame's budgeted choice came to: its predicted cost [s] (without the
    /// frame's overhead) and total estimated error [pixels]; `None` without a budget.
    pub fn budget_outcome(&self) -> Option<BudgetOutcome> {
        self.budget.as_ref().and(self.outcome)
    }

    /// Calibrates the shared budget's cost model with a finished frame's summed `report`.
    pub fn observe_frame(&mut self, report: &FrameReport) {
        crate::pipeline::calibrate_budget(self.budget.as_mut(), report);
    }

    /// Advances every character one frame seen by `camera`: levels (each character's own
    /// selector at the pixel tolerance, or one greedy refinement over every section of the
    /// crowd within the budget), hand-over, dynamics with collision. Returns the characters'
    /// reports summed ([`sum_reports`]).
    pub fn advance(&mut self, camera: &Camera) -> Result<FrameReport> {
        let mut shared_lod = 0.0;
        match &self.budget {
            Some(budget) => {
                let model = &budget.1;
                self.options.clear();
                self.ranges.clear();
                for pipeline in &mut self.pipelines {
                    let start = self.options.len();
                    self.options
                        .extend_from_slice(pipeline.budget_options(camera, model)?);
                    self.ranges.push(start..self.options.len());
                }
                let started = Instant::now();
                self.outcome = Some(crate::pipeline::choose_within_budget(
                    &self.options,
                    budget,
                    &mut self.levels,
                ));
                shared_lod = started.elapsed().as_secs_f64();
                for (pipeline, range) in self.pipelines.iter_mut().zip(&self.ranges) {
                    pipeline.begin_frame_with_levels(camera, &self.levels[range.clone()])?;
                }
            }
            None => {
                for pipeline in &mut self.pipelines {
                    pipeline.begin_frame(camera)?;
                }
            }
        }
        // Every character's level blocks step side by side in one pass (each is independent of
        // the others, so the frame is the same whatever the order or the thread count).
        let started = Instant::now();
        let reports = crate::pipeline::step_together(&mut self.pipelines)?;
        let mut report = sum_reports(&reports);
        report.times.lod += shared_lod;
        crate::pipeline::charge_wall_time(&mut report, started.elapsed().as_secs_f64());
        Ok(report)
    }
}

/// The reports of the characters' frames as one: counts, work and stage times summed, the
/// largest stretch, the first report's frame and time (all characters share the clock).
pub fn sum_reports(reports: &[FrameReport]) -> FrameReport {
    let mut sum = FrameReport {
        frame: reports.first().map_or(0, |r| r.frame),
        time: reports.first().map_or(0.0, |r| r.time),
        ..FrameReport::default()
    };
    for report in reports {
        for level in 0..3 {
            sum.sections_at[level] += report.sections_at[level];
            sum.drawn_at[level] += report.drawn_at[level];
            sum.pixels_at[level] += report.pixels_at[level];
            sum.level_seconds[level] += report.level_seconds[level];
            sum.level_nodes[level] += report.level_nodes[level];
        }
        sum.visible_sections += report.visible_sections;
        sum.level_changes += report.level_changes;
        sum.visibility_changes += report.visibility_changes;
        sum.blending_sections += report.blending_sections;
        sum.simulated_nodes += report.simulated_nodes;
        sum.drawn_segments += report.drawn_segments;
        sum.contacts += report.contacts;
        sum.max_stretch = sum.max_stretch.max(report.max_stretch);
        sum.times.add(&report.times);
    }
    sum
}
