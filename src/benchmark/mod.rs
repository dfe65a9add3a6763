//! The paper's benchmark (§8.2, Tables 1 and 2): the `paper-curly` groom (91 patches, 273
//! clusters, 455 strand groups, 37,765 strands) with the camera zooming out from the face, calm or
//! with wind, run in each mode (LODs, Strands, Clusters, Patches) over the same frames, timing
//! dynamics, collision and rendering.

use glam::Vec3;
use hair_core::dynamics::{Environment, WindField};
use hair_core::{Camera, Level, Scene};
use serde::Serialize;

mod budget;
mod popping;

pub use budget::{BudgetedRun, run_budgeted};
pub use popping::{
    ExcessPopping, Popping, PoppingMeter, excess_popping, luma, luma_difference,
    mean_abs_difference, ssim,
};

use crate::pipeline::{
    FrameReport, LodMode, Pipeline, PipelineRenderer, PipelineSettings, Result, StageTimes,
};

/// The paper's figures [s per frame], rows dynamics, collision, rendering; columns LODs, Strands,
/// Clusters, Patches. Table 1: camera zooming out.
pub const PAPER_TABLE_1: [[f64; 4]; 3] = [
    [0.183, 1.071, 0.099, 0.030],
    [0.077, 0.200, 0.122, 0.040],
    [0.385, 1.687, 0.656, 0.158],
];

/// Table 2: the same with wind blowing.
pub const PAPER_TABLE_2: [[f64; 4]; 3] = [
    [0.356, 1.134, 0.105, 0.032],
    [0.107, 0.168, 0.101, 0.034],
    [0.785, 1.734, 0.665, 0.158],
];

/// The four modes of the tables, in the paper's column order.
pub fn paper_modes(lod: hair_core::lod::LodSettings) -> [LodMode; 4] {
    [
        LodMode::Auto(lod),
        LodMode::Fixed(Level::StrandGroup),
        LodMode::Fixed(Level::Cluster),
        LodMode::Fixed(Level::Patch),
    ]
}

/// The benchmark's scene and camera path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PaperBenchmark {
    /// Frames per mode.
    pub frames: usize,
    /// Wind blowing (Table 2) or calm (Table 1).
    pub wind: bool,
    /// Image width [pixels].
    pub width: u32,
    /// Image height [pixels].
    pub height: u32,
    /// Camera distance from the head's centre at the first frame [m].
    pub near_distance: f32,
    /// Camera distance at the last frame [m].
    pub far_distance: f32,
}

impl Default for PaperBenchmark {
    /// 60 frames at 1280×720, calm, from 0.45 m to 12 m.
    fn default() -> Self {
        PaperBenchmark {
            frames: 60,
            wind: false,
            width: 1280,
            height: 720,
            near_distance: 0.45,
            far_distance: 12.0,
        }
    }
}

/// The point the camera looks at: the centre of the head [m].
pub const HEAD_CENTRE: Vec3 = Vec3::new(0.0, 0.0, 0.0);

impl PaperBenchmark {
    /// The camera of frame `frame`: distance geometric from near to far, in front of the face and a
    /// little to the side and above (so that the side and top hair show).
    pub fn camera(&self, frame: usize) -> Camera {
        let t = if self.frames > 1 {
            frame as f32 / (self.frames - 1) as f32
        } else {
            0.0
        };
        let distance = self.near_distance * (self.far_distance / self.near_distance).powf(t);
        Camera::orbit(HEAD_CENTRE, distance, 0.5, 0.15, 35f32.to_radians())
    }

    /// The control inputs: a still head, calm air or a gusting wind from the front left (mean
    /// 2.5 m/s, gusts of 1.5 m/s, seeded, so every mode sees the same wind).
    pub fn environment(&self) -> Environment {
        let wind = if self.wind {
            WindField::gusting(Vec3::new(1.5, 0.0, -2.0), 1.5, 1.0, 0.5, 7)
        } else {
            WindField::Calm
        };
        Environment {
            wind,
            ..Environment::default()
        }
    }

    /// The LOD settings matched to the benchmark's image size.
    pub fn lod_settings(&self) -> hair_core::lod::LodSettings {
        hair_core::lod::LodSettings {
            image_width: self.width,
            image_height: self.height,
            ..hair_core::lod::LodSettings::default()
        }
    }
}

/// One mode's run: every frame's report and the mean time per frame of each stage.
#[derive(Debug, Clone, Serialize)]
pub struct ModeRun {
    /// `LODs`, `Strands`, `Clusters` or `Patches`.
    pub mode: String,
    /// Every frame's report.
    pub frames: Vec<FrameReport>,
    /// Mean time per frame of each stage [s].
    pub mean: StageTimes,
    /// Median total time per frame [s].
    pub median_total: f64,
}

impl ModeRun {
    /// Summarises `frames` of mode `mode`.
    pub fn new(mode: &str, frames: Vec<FrameReport>) -> Self {
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
            mode: mode.to_string(),
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

/// How long the hair settles under gravity before the first frame [s] (see [`Pipeline::settle`]).
pub const SETTLE_TIME: f32 = 1.0;

/// Runs `settings` on `scene` over the benchmark's frames, rendering each frame with `renderer`
/// when given; `on_frame` sees each frame's report and image (for writing, popping measures or
/// progress).
pub fn run_mode(
    benchmark: &PaperBenchmark,
    scene: &Scene,
    settings: PipelineSettings,
    mut renderer: Option<&mut PipelineRenderer>,
    mut on_frame: impl FnMut(&FrameReport, Option<&image::RgbaImage>),
) -> Result<ModeRun> {
    let mut pipeline = Pipeline::new(scene.clone(), benchmark.environment(), settings)?;
    pipeline.settle(SETTLE_TIME)?;
    if let Some(renderer) = renderer.as_deref_mut() {
        renderer.bind(&pipeline)?;
    }
    let mut frames = Vec::with_capacity(benchmark.frames);
    for frame in 0..benchmark.frames {
        let camera = benchmark.camera(frame);
        let mut report = pipeline.advance(&camera)?;
        let image = match renderer.as_deref_mut() {
            Some(renderer) => Some(render_frame(
                benchmark,
                renderer,
                &mut pipeline,
                &camera,
                &mut report,
            )?),
            None => None,
        };
        on_frame(&report, image.as_ref());
        frames.push(report);
    }
    Ok(ModeRun::new(settings.lod.column_name(), frames))
}

/// Renders `pipeline`'s frame through `camera` at the benchmark's size, shaded, and records the
/// time it took in `report.times.rendering` [s].
pub(crate) fn render_frame(
    benchmark: &PaperBenchmark,
    renderer: &mut PipelineRenderer,
    pipeline: &mut Pipeline,
    camera: &Camera,
    report: &mut FrameReport,
) -> Result<image::RgbaImage> {
    let (image, seconds) = renderer.render(
        pipeline,
        camera,
        benchmark.width,
        benchmark.height,
        hair_render::ShadingMode::Shaded,
    )?;
    report.times.rendering = seconds;
    Ok(image)
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
        let calm = ModeRun::new("LODs", vec![frame(0, 1e-5), frame(1, 0.01)]);
        assert_eq!(calm.worst_stretch(), (0.01, 1));
        assert!(calm.stretch_warning().is_none());
        let torn = ModeRun::new(
            "Strands",
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
