//! The frame loop: the one loop every command, benchmark and example drives a [`Pipeline`] with.
//! For each frame of a range of a [`Shot`]: the camera, the frame budget's tolerance (when the
//! shot has a budget), [`Pipeline::advance`] (levels, hand-over, dynamics with collision), the
//! views rendered (the head mesh at its simulated pose), and the caller's hook (write images,
//! measure, show progress). A run can start from a [`Checkpoint`] and resume bit for bit.
//! [`FrameLoop`] is that loop one frame at a time ([`run_shot`] and [`run_frames`] drive it to
//! the end), so that several runs can be stepped side by side.

use std::ops::Range;

use hair_core::Scene;
use hair_core::lod::{
    BudgetController, BudgetMethod, BudgetReport, BudgetSettings, CostModel, CostRates,
};
use hair_render::ShadingMode;
use serde::Serialize;

use crate::pipeline::{
    Checkpoint, DrawnSource, FrameReport, Pipeline, PipelineError, PipelineRenderer,
    PipelineSettings, Result, RunMode, StageTimes,
};
use crate::shot::Shot;

/// One picture of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum View {
    /// Shaded (Kajiya-Kay hair, Lambert head).
    Shaded,
    /// Colour-coded by level: strands yellow, clusters red, patches blue (the paper's Fig. 6).
    LevelColors,
    /// Shaded | colour-coded, side by side (twice as wide).
    SideBySide,
}

impl View {
    /// The views a shot's outputs ask for, in a fixed order (shaded first).
    pub fn of_outputs(outputs: &crate::shot::Outputs) -> Vec<View> {
        let mut views = Vec::new();
        if outputs.shaded {
            views.push(View::Shaded);
        }
        if outputs.color_coded {
            views.push(View::LevelColors);
        }
        if outputs.side_by_side {
            views.push(View::SideBySide);
        }
        views
    }

    /// A short name, also the folder of the view's frames when a run writes several.
    pub fn name(self) -> &'static str {
        match self {
            View::Shaded => "shaded",
            View::LevelColors => "levels",
            View::SideBySide => "side_by_side",
        }
    }
}

/// What a run does besides the shot: the pipeline settings (a benchmark runs several modes of
/// one shot), the frames, where it starts and the frame budget.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The pipeline settings.
    pub settings: PipelineSettings,
    /// The frames to make, within the shot's `0..frames`.
    pub frames: Range<usize>,
    /// Start from this checkpoint (whose frame must be `frames.start`) instead of settling.
    pub resume: Option<Checkpoint>,
    /// Steer the pixel tolerance to this frame budget (automatic levels only).
    pub budget: Option<BudgetSettings>,
}

impl RunOptions {
    /// The whole shot with `settings`, from the start, with the shot's budget when `settings`
    /// are the shot's own.
    pub fn whole(shot: &Shot, settings: PipelineSettings) -> Self {
        RunOptions {
            budget: if settings == shot.settings {
                shot.budget
            } else {
                None
            },
            settings,
            frames: 0..shot.frames,
            resume: None,
        }
    }
}

/// What the frame loop drives: one character's [`Pipeline`], or a [`Crowd`](crate::crowd::Crowd)
/// of them, each drawn by its own kind of renderer.
pub trait Runnable {
    /// What draws it.
    type Renderer;

    /// The pixel tolerance of its automatic levels [pixels] (`None` at a fixed level).
    fn pixel_tolerance(&self) -> Option<f32>;

    /// Sets the pixel tolerance of its automatic levels [pixels] from the next frame on.
    fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()>;

    /// Chooses levels within a frame budget [s] with costs from a calibrated model
    /// ([`Pipeline::set_frame_budget`]).
    fn set_frame_budget(&mut self, budget: Option<(f64, CostModel)>) -> Result<()>;

    /// Advances one frame seen by `camera`: levels, hand-over, dynamics with collision.
    fn advance(&mut self, camera: &hair_core::Camera) -> Result<FrameReport>;

    /// Calibrates the frame budget's cost model with a finished frame's report.
    fn observe_frame(&mut self, report: &FrameReport);

    /// Draws the current frame in `view` through `camera` at `width`×`height` [pixels]; returns
    /// the image and the time it took [s].
    fn render_view(
        &mut self,
        renderer: &mut Self::Renderer,
        camera: &hair_core::Camera,
        size: (u32, u32),
        view: View,
    ) -> Result<(image::RgbaImage, f64)>;

    /// What `renderer`'s last frame drew (strands and segments, after thinning).
    fn drawn_by(renderer: &Self::Renderer) -> hair_render::DrawnCounts;

    /// The run's mode (`LODs`, `Strands`, `Clusters`, `Patches`).
    fn run_mode(&self) -> RunMode;
}

impl Runnable for Pipeline {
    type Renderer = PipelineRenderer;

    fn pixel_tolerance(&self) -> Option<f32> {
        self.selector().map(|s| s.settings().pixel_tolerance)
    }

    fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        Pipeline::set_pixel_tolerance(self, pixel_tolerance)
    }

    fn set_frame_budget(&mut self, budget: Option<(f64, CostModel)>) -> Result<()> {
        Pipeline::set_frame_budget(self, budget)
    }

    fn advance(&mut self, camera: &hair_core::Camera) -> Result<FrameReport> {
        Pipeline::advance(self, camera)
    }

    fn observe_frame(&mut self, report: &FrameReport) {
        Pipeline::observe_frame(self, report);
    }

    fn render_view(
        &mut self,
        renderer: &mut PipelineRenderer,
        camera: &hair_core::Camera,
        size: (u32, u32),
        view: View,
    ) -> Result<(image::RgbaImage, f64)> {
        render_view_of(renderer, self, camera, size, view)
    }

    fn drawn_by(renderer: &PipelineRenderer) -> hair_render::DrawnCounts {
        renderer.last_drawn()
    }

    fn run_mode(&self) -> RunMode {
        self.settings().lod.run_mode()
    }
}

/// A renderer the frame loop draws its views with: one character's
/// ([`PipelineRenderer`]) or a crowd's ([`CrowdRenderer`](crate::crowd::CrowdRenderer)), drawing
/// any [`DrawnSource`] (a run in memory, or frames read back from a cache).
pub trait FrameRenderer {
    /// Draws `source`'s frame through `camera` into a `width`×`height` image, shaded or
    /// colour-coded by level; returns the image and the time it took [s].
    fn render_source(
        &mut self,
        source: &mut impl DrawnSource,
        camera: &hair_core::Camera,
        size: (u32, u32),
        mode: ShadingMode,
    ) -> Result<(image::RgbaImage, f64)>;

    /// Draws shaded and colour-coded side by side (`2·width`×`height`); returns the image and
    /// the time it took [s].
    fn render_source_side_by_side(
        &mut self,
        source: &mut impl DrawnSource,
        camera: &hair_core::Camera,
        size: (u32, u32),
    ) -> Result<(image::RgbaImage, f64)>;

    /// What the last frame drew (strands and segments, after thinning).
    fn last_drawn(&self) -> hair_render::DrawnCounts;
}

impl FrameRenderer for PipelineRenderer {
    fn render_source(
        &mut self,
        source: &mut impl DrawnSource,
        camera: &hair_core::Camera,
        (width, height): (u32, u32),
        mode: ShadingMode,
    ) -> Result<(image::RgbaImage, f64)> {
        self.render(source, camera, width, height, mode)
    }

    fn render_source_side_by_side(
        &mut self,
        source: &mut impl DrawnSource,
        camera: &hair_core::Camera,
        (width, height): (u32, u32),
    ) -> Result<(image::RgbaImage, f64)> {
        self.render_side_by_side(source, camera, width, height)
    }

    fn last_drawn(&self) -> hair_render::DrawnCounts {
        self.renderer().last_drawn()
    }
}

/// Draws `source` in `view` with `renderer` (see [`Runnable::render_view`]).
pub fn render_view_of<R: FrameRenderer>(
    renderer: &mut R,
    source: &mut impl DrawnSource,
    camera: &hair_core::Camera,
    size: (u32, u32),
    view: View,
) -> Result<(image::RgbaImage, f64)> {
    match view {
        View::Shaded => renderer.render_source(source, camera, size, ShadingMode::Shaded),
        View::LevelColors => renderer.render_source(source, camera, size, ShadingMode::LevelColors),
        View::SideBySide => renderer.render_source_side_by_side(source, camera, size),
    }
}

/// What the loop shows the caller after each frame.
pub struct FrameOutput<'a, R = Pipeline> {
    /// The frame's report (stage times, levels, model size).
    pub report: &'a FrameReport,
    /// The frame's camera.
    pub camera: &'a hair_core::Camera,
    /// One image per view asked for, in that order (empty without a renderer).
    pub images: &'a [image::RgbaImage],
    /// The pipeline (or crowd) after the frame (for measurements).
    pub pipeline: &'a R,
    /// The pixel tolerance the frame ran at [pixels] (`None` at a fixed level).
    pub tolerance: Option<f32>,
}

/// What a run leaves: its frames, the pipeline (or crowd) at the end (to checkpoint) and the
/// budget's record.
pub struct RunResult<R = Pipeline> {
    /// Every frame's report, summarised.
    pub run: ModeRun,
    /// The pipeline (or crowd) after the last frame.
    pub pipeline: R,
    /// The frame budget's record, when the run had one.
    pub budget: Option<BudgetReport>,
    /// The pixel tolerance each frame ran at [pixels] (empty at a fixed level).
    pub tolerances: Vec<f32>,
}

/// Runs `options.frames` of `shot` on `scene` (built from it): the one frame loop. With a
/// renderer, each frame is drawn in each of `views`; the first view's time is the frame's
/// rendering time (and counts towards the budget). `on_frame` sees each frame; an error from it
/// stops the run.
pub fn run_shot(
    shot: &Shot,
    scene: &Scene,
    options: RunOptions,
    mut renderer: Option<(&mut PipelineRenderer, &[View])>,
    on_frame: impl FnMut(FrameOutput<'_>) -> Result<()>,
) -> Result<RunResult> {
    let frame_loop = FrameLoop::start(
        shot,
        scene,
        options,
        renderer.as_mut().map(|(r, _)| &mut **r),
    )?;
    frame_loop.run_to_end(renderer, on_frame)
}

/// Checks that `frames` lie within `shot` and start where the run can start: frame 0, or the
/// checkpoint's frame.
pub(crate) fn check_frames(
    shot: &Shot,
    frames: &Range<usize>,
    resume: Option<&Checkpoint>,
) -> Result<()> {
    if frames.start > frames.end || frames.end > shot.frames {
        return Err(PipelineError::FramesOutsideShot {
            start: frames.start,
            end: frames.end,
            frames: shot.frames,
        });
    }
    let start = resume.map_or(0, |c| c.state.frame);
    if start != frames.start {
        return Err(PipelineError::StartFrame {
            start: frames.start,
            checkpoint: resume.map(|_| start),
        });
    }
    Ok(())
}

/// The frame loop itself, on a pipeline or crowd already built: for each frame of `frames`, the
/// camera, the frame budget's tolerance (or the greedy choice within `budget`),
/// [`Runnable::advance`], the views rendered, the budget's calibration and `on_frame`
/// ([`FrameLoop`] one frame at a time).
pub fn run_frames<R: Runnable>(
    shot: &Shot,
    target: R,
    frames: Range<usize>,
    budget: Option<BudgetSettings>,
    renderer: Option<(&mut R::Renderer, &[View])>,
    on_frame: impl FnMut(FrameOutput<'_, R>) -> Result<()>,
) -> Result<RunResult<R>> {
    FrameLoop::new(shot, target, frames, budget)?.run_to_end(renderer, on_frame)
}

/// The frame loop one frame at a time, so that a caller can drive several runs side by side
/// (`bench paper` interleaves its modes frame by frame, so that each sees the same machine
/// load). [`run_frames`] drives one to its end.
pub struct FrameLoop<'s, R: Runnable = Pipeline> {
    shot: &'s Shot,
    target: R,
    frames: Range<usize>,
    controller: Option<BudgetController>,
    reports: Vec<FrameReport>,
    tolerances: Vec<f32>,
    images: Vec<image::RgbaImage>,
    /// The last frame's camera.
    camera: Option<hair_core::Camera>,
}

impl<'s> FrameLoop<'s, Pipeline> {
    /// Checks `options` against `shot`, builds the pipeline on `scene` (from the checkpoint, when
    /// given) and binds it to `renderer`: [`run_shot`] one frame at a time. Runs driven side by
    /// side on one renderer must share `scene` (the renderer holds the last bound groom).
    pub fn start(
        shot: &'s Shot,
        scene: &Scene,
        options: RunOptions,
        renderer: Option<&mut PipelineRenderer>,
    ) -> Result<Self> {
        let RunOptions {
            settings,
            frames,
            resume,
            budget,
        } = options;
        check_frames(shot, &frames, resume.as_ref())?;
        let pipeline = shot.pipeline(scene, settings, resume)?;
        if let Some(renderer) = renderer {
            renderer.bind(&pipeline)?;
        }
        FrameLoop::new(shot, pipeline, frames, budget)
    }
}

impl<'s, R: Runnable> FrameLoop<'s, R> {
    /// A loop over `frames` of `shot` on `target` (a pipeline or crowd already built), steered
    /// to `budget` when given (automatic levels only).
    pub fn new(
        shot: &'s Shot,
        mut target: R,
        frames: Range<usize>,
        budget: Option<BudgetSettings>,
    ) -> Result<Self> {
        let controller = match (budget, target.pixel_tolerance()) {
            (Some(budget), Some(tolerance)) => Some(BudgetController::new(budget, tolerance)?),
            _ => None,
        };
        // The greedy method chooses levels within the budget (aiming at its margin) from costs
        // the pipeline calibrates frame by frame; the controller then only keeps the tally.
        if let Some(settings) = controller.as_ref().map(|c| *c.settings())
            && settings.method == BudgetMethod::Greedy
        {
            let model = CostModel::new(CostRates::default())?;
            target.set_frame_budget(Some((settings.margin * settings.budget, model)))?;
        }
        Ok(FrameLoop {
            shot,
            target,
            reports: Vec::with_capacity(frames.len()),
            frames,
            controller,
            tolerances: Vec::new(),
            images: Vec::new(),
            camera: None,
        })
    }

    /// Makes the next frame: the camera, the budget's tolerance, [`Runnable::advance`], each of
    /// the views drawn with `renderer` (the first view's time is the frame's rendering time) and
    /// the budget's calibration. Returns what the frame left, or `None` after the last frame.
    pub fn step(
        &mut self,
        renderer: Option<(&mut R::Renderer, &[View])>,
    ) -> Result<Option<FrameOutput<'_, R>>> {
        let Some(frame) = self.frames.next() else {
            return Ok(None);
        };
        let camera = self.shot.camera(frame);
        if let Some(controller) = &self.controller {
            self.target.set_pixel_tolerance(controller.tolerance())?;
        }
        let tolerance = self.target.pixel_tolerance();
        let mut report = self.target.advance(&camera)?;
        self.images.clear();
        if let Some((renderer, views)) = renderer {
            for (k, view) in views.iter().enumerate() {
                let (image, seconds) = self.target.render_view(
                    renderer,
                    &camera,
                    (self.shot.width, self.shot.height),
                    *view,
                )?;
                if k == 0 {
                    report.times.rendering = seconds;
                    let drawn = R::drawn_by(renderer);
                    report.rendered_strands = drawn.strands;
                    report.rendered_strand_segments = drawn.strand_segments;
                }
                self.images.push(image);
            }
        }
        if let Some(controller) = &mut self.controller {
            controller.update(report.times.total())?;
        }
        self.target.observe_frame(&report);
        self.tolerances.extend(tolerance);
        self.reports.push(report);
        let report = self
            .reports
            .last()
            .expect("the frame's report was just pushed");
        Ok(Some(FrameOutput {
            report,
            camera: self.camera.insert(camera),
            images: &self.images,
            pipeline: &self.target,
            tolerance,
        }))
    }

    /// The pipeline (or crowd) as the last frame left it, to draw that frame in ways the views
    /// do not (`bench costs` draws each frame in several render variants).
    pub fn target_mut(&mut self) -> &mut R {
        &mut self.target
    }

    /// Makes every frame left, showing each to `on_frame` (an error from it stops the run), and
    /// finishes.
    pub fn run_to_end(
        mut self,
        mut renderer: Option<(&mut R::Renderer, &[View])>,
        mut on_frame: impl FnMut(FrameOutput<'_, R>) -> Result<()>,
    ) -> Result<RunResult<R>> {
        while let Some(output) =
            self.step(renderer.as_mut().map(|(r, views)| (&mut **r, *views)))?
        {
            on_frame(output)?;
        }
        Ok(self.finish())
    }

    /// The frames made so far, summarised, with the pipeline (or crowd) as it stands.
    pub fn finish(self) -> RunResult<R> {
        RunResult {
            run: ModeRun::new(self.target.run_mode(), self.reports),
            budget: self.controller.map(|c| c.report()),
            tolerances: self.tolerances,
            pipeline: self.target,
        }
    }
}

/// One mode's run: every frame's report and the mean time per frame of each stage.
#[derive(Debug, Clone, Serialize)]
pub struct ModeRun {
    /// `LODs`, `Strands`, `Clusters` or `Patches` (or a study's variant of automatic levels).
    pub mode: RunMode,
    /// Every frame's report.
    pub frames: Vec<FrameReport>,
    /// Mean time per frame of each stage [s].
    pub mean: StageTimes,
    /// Median total time per frame [s].
    pub median_total: f64,
}

impl ModeRun {
    /// Summarises `frames` of mode `mode`.
    pub fn new(mode: RunMode, frames: Vec<FrameReport>) -> Self {
        let mut mean = StageTimes::default();
        for frame in &frames {
            mean.add(&frame.times);
        }
        let n = frames.len().max(1) as f64;
        mean.lod /= n;
        mean.dynamics /= n;
        mean.collision /= n;
        mean.rendering /= n;
        let mut totals: Vec<f64> = frames.iter().map(|f| f.times.total()).collect();
        totals.sort_by(f64::total_cmp);
        let median_total = totals.get(totals.len() / 2).copied().unwrap_or(0.0);
        ModeRun {
            mode,
            frames,
            mean,
            median_total,
        }
    }

    /// The largest segment stretch the collision projection left in any frame, and that frame
    /// (`(0.0, 0)` without collision or frames).
    pub fn worst_stretch(&self) -> (f32, usize) {
        self.frames
            .iter()
            .map(|f| (f.max_stretch, f.frame))
            .fold(
                (0.0, 0),
                |worst, next| if next.0 > worst.0 { next } else { worst },
            )
    }

    /// A warning naming the mode, the stretch and the frame when the collision projection
    /// stretched a segment beyond [`hair_collide::STRETCH_WARNING`]; `None` otherwise.
    pub fn stretch_warning(&self) -> Option<String> {
        let (stretch, frame) = self.worst_stretch();
        (stretch > hair_collide::STRETCH_WARNING).then(|| {
            format!(
                "warning: {}: the collision projection stretched a segment by {:.1} % (frame \
                 {frame}): the time step is too coarse for the hair's motion near the head; \
                 use more substeps",
                self.mode,
                100.0 * stretch
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(frame: usize, max_stretch: f32) -> FrameReport {
        FrameReport {
            frame,
            max_stretch,
            ..FrameReport::default()
        }
    }

    #[test]
    fn stretch_beyond_the_warning_names_the_mode_and_frame() {
        let calm = ModeRun::new(RunMode::Lods, vec![frame(0, 1e-5), frame(1, 0.01)]);
        assert_eq!(calm.worst_stretch(), (0.01, 1));
        assert!(calm.stretch_warning().is_none());
        let torn = ModeRun::new(
            RunMode::Strands,
            vec![frame(0, 0.01), frame(1, 0.22), frame(2, 0.1)],
        );
        let warning = torn.stretch_warning().expect("22 % is past the warning");
        assert!(
            warning.contains("Strands")
                && warning.contains("22.0 %")
                && warning.contains("frame 1")
        );
    }
}
