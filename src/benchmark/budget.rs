//! The benchmark's LOD run in frame-budget mode: a [`BudgetController`](hair_core::lod::BudgetController)
//! steers the selector's pixel tolerance from each frame's measured cost (LOD, dynamics,
//! collision and rendering), in the frame loop ([`run_shot`]).

use hair_core::Scene;
use hair_core::lod::{BudgetReport, BudgetSettings, LodSettings};
use serde::Serialize;

use crate::pipeline::{FrameReport, LodMode, PipelineRenderer, PipelineSettings, Result};
use crate::run::{ModeRun, RunOptions, View, run_shot};
use crate::shot::Shot;

/// A budgeted run: the frames, how often the budget was met, and the tolerance of every frame.
#[derive(Debug, Clone, Serialize)]
pub struct BudgetedRun {
    /// The frames, as for any mode.
    pub run: ModeRun,
    /// Budget met how often, at what mean tolerance.
    pub budget: BudgetReport,
    /// The pixel tolerance each frame ran at [pixels].
    pub tolerances: Vec<f32>,
}

/// Runs `shot` with automatic levels from `lod` and the tolerance steered by a controller with
/// `budget`, rendering every frame shaded (the budget counts the rendering); `on_frame` sees each
/// frame's report, image and tolerance.
pub fn run_budgeted(
    shot: &Shot,
    scene: &Scene,
    lod: LodSettings,
    budget: BudgetSettings,
    renderer: &mut PipelineRenderer,
    mut on_frame: impl FnMut(&FrameReport, &image::RgbaImage, f32),
) -> Result<BudgetedRun> {
    let settings = PipelineSettings {
        lod: LodMode::Auto(lod),
        ..shot.settings
    };
    let options = RunOptions {
        budget: Some(budget),
        ..RunOptions::whole(shot, settings)
    };
    let views = [View::Shaded];
    let result = run_shot(shot, scene, options, Some((renderer, &views)), |frame| {
        on_frame(
            frame.report,
            &frame.images[0],
            frame.tolerance.unwrap_or(lod.pixel_tolerance),
        );
        Ok(())
    })?;
    let mut run = result.run;
    run.mode = crate::pipeline::RunMode::LodsFrameBudget;
    Ok(BudgetedRun {
        run,
        budget: result
            .budget
            .expect("a budget was given at automatic levels"),
        tolerances: result.tolerances,
    })
}
