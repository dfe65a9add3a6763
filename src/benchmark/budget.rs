//! The benchmark's LOD run in frame-budget mode: a [`BudgetController`] steers the selector's
//! pixel tolerance from each frame's measured cost (LOD, dynamics, collision and rendering).

use hair_core::Scene;
use hair_core::lod::{BudgetController, BudgetReport, BudgetSettings, LodSettings};
use serde::Serialize;

use super::{ModeRun, PaperBenchmark, SETTLE_TIME, render_frame};
use crate::pipeline::{FrameReport, LodMode, Pipeline, PipelineRenderer, PipelineSettings, Result};

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

/// Runs the benchmark's LOD mode with `lod` as the starting settings and the tolerance steered
/// by a controller with `budget`, rendering every frame (the budget counts the rendering);
/// `on_frame` sees each frame's report, image and tolerance.
pub fn run_budgeted(
    benchmark: &PaperBenchmark,
    scene: &Scene,
    lod: LodSettings,
    budget: BudgetSettings,
    renderer: &mut PipelineRenderer,
    mut on_frame: impl FnMut(&FrameReport, &image::RgbaImage, f32),
) -> Result<BudgetedRun> {
    let mut controller = BudgetController::new(budget, lod.pixel_tolerance)?;
    let settings = PipelineSettings {
        lod: LodMode::Auto(LodSettings {
            pixel_tolerance: controller.tolerance(),
            ..lod
        }),
        ..PipelineSettings::default()
    };
    let mut pipeline = Pipeline::new(scene.clone(), benchmark.environment(), settings)?;
    pipeline.settle(SETTLE_TIME)?;
    renderer.bind(&pipeline)?;
    let mut frames = Vec::with_capacity(benchmark.frames);
    let mut tolerances = Vec::with_capacity(benchmark.frames);
    for frame in 0..benchmark.frames {
        let camera = benchmark.camera(frame);
        let tolerance = controller.tolerance();
        if let Some(selector) = pipeline.selector_mut() {
            selector.set_pixel_tolerance(tolerance)?;
        }
        let mut report = pipeline.advance(&camera)?;
        let image = render_frame(benchmark, renderer, &mut pipeline, &camera, &mut report)?;
        controller.update(report.times.total())?;
        on_frame(&report, &image, tolerance);
        tolerances.push(tolerance);
        frames.push(report);
    }
    Ok(BudgetedRun {
        run: ModeRun::new("LODs, frame budget", frames),
        budget: controller.report(),
        tolerances,
    })
}
