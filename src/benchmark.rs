//! The paper's benchmark (§8.2, Tables 1 and 2): the `paper-curly` groom (91 patches, 273
//! clusters, 455 strand groups, 37,765 strands) with the camera zooming out from the face, calm or
//! with wind, run in each mode (LODs, Strands, Clusters, Patches) over the same frames, timing
//! dynamics, collision and rendering.

use glam::Vec3;
use hair_core::dynamics::{Environment, WindField};
use hair_core::{Camera, Level, Scene};
use serde::Serialize;

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
            Some(renderer) => {
                let (image, seconds) = renderer.render(
                    &mut pipeline,
                    &camera,
                    benchmark.width,
                    benchmark.height,
                    hair_render::ShadingMode::Shaded,
                )?;
                report.times.rendering = seconds;
                Some(image)
            }
            None => None,
        };
        on_frame(&report, image.as_ref());
        frames.push(report);
    }
    Ok(ModeRun::new(settings.lod.column_name(), frames))
}

/// Mean absolute difference of two images of the same size, over the RGB channels, in `[0, 1]`.
pub fn mean_abs_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    if a.dimensions() != b.dimensions() {
        return 1.0;
    }
    let mut sum = 0u64;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for c in 0..3 {
            sum += u64::from(p.0[c].abs_diff(q.0[c]));
        }
    }
    sum as f64 / (255.0 * 3.0 * f64::from(a.width()) * f64::from(a.height())).max(1.0)
}

/// The popping measure of a run: mean absolute difference between consecutive frames where some
/// section changed level, where none did, and their ratio.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Popping {
    /// Mean difference over frames where a section changed level.
    pub changing: f64,
    /// Mean difference over frames where no section changed level.
    pub steady: f64,
    /// `changing / steady`.
    pub ratio: f64,
    /// Frames with a change.
    pub changing_frames: usize,
    /// Frames without.
    pub steady_frames: usize,
}

/// Accumulates [`Popping`] frame by frame.
#[derive(Debug, Default)]
pub struct PoppingMeter {
    previous: Option<image::RgbaImage>,
    changing: (f64, usize),
    steady: (f64, usize),
}

impl PoppingMeter {
    /// Adds the next frame and whether some section changed level (or blended) in it.
    pub fn add(&mut self, image: &image::RgbaImage, changed: bool) {
        if let Some(previous) = &self.previous {
            let difference = mean_abs_difference(previous, image);
            let bucket = if changed {
                &mut self.changing
            } else {
                &mut self.steady
            };
            bucket.0 += difference;
            bucket.1 += 1;
        }
        self.previous = Some(image.clone());
    }

    /// The measure so far.
    pub fn popping(&self) -> Popping {
        let mean = |(sum, count): (f64, usize)| if count > 0 { sum / count as f64 } else { 0.0 };
        let changing = mean(self.changing);
        let steady = mean(self.steady);
        Popping {
            changing,
            steady,
            ratio: if steady > 0.0 { changing / steady } else { 0.0 },
            changing_frames: self.changing.1,
            steady_frames: self.steady.1,
        }
    }
}

/// Mean structural similarity (SSIM, on luma) of two images of the same size, in `[−1, 1]` (1:
/// identical), from the `image-compare` crate.
pub fn ssim(a: &image::GrayImage, b: &image::GrayImage) -> f64 {
    if a.dimensions() != b.dimensions() {
        return 0.0;
    }
    image_compare::gray_similarity_structure(&image_compare::Algorithm::MSSIMSimple, a, b)
        .map(|similarity| similarity.score)
        .unwrap_or(0.0)
}

/// The luma of an RGBA image (what [`ssim`] compares).
pub fn luma(image: &image::RgbaImage) -> image::GrayImage {
    image::DynamicImage::ImageRgba8(image.clone()).to_luma8()
}

/// Mean absolute difference of two luma images of the same size, in `[0, 1]`.
fn luma_difference(a: &image::GrayImage, b: &image::GrayImage) -> f64 {
    if a.dimensions() != b.dimensions() {
        return 1.0;
    }
    let sum: u64 = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| u64::from(p.0[0].abs_diff(q.0[0])))
        .sum();
    sum as f64 / (255.0 * f64::from(a.width()) * f64::from(a.height())).max(1.0)
}

/// Popping beyond what the camera's own motion explains: per frame `t ≥ 1`, the mean absolute
/// luma difference between consecutive frames of a LOD run minus the same between consecutive
/// frames of the Strands run over the same camera path, averaged over the frames where some
/// section switched level (`at_switches`) and over the others (`elsewhere`).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct ExcessPopping {
    /// Mean excess difference over frames where a switch started, in `[−1, 1]`.
    pub at_switches: f64,
    /// Mean excess difference over the other frames.
    pub elsewhere: f64,
    /// Frames with a switch.
    pub switch_frames: usize,
}

/// [`ExcessPopping`] of the LOD frames `lod` against the Strands frames `strands` (luma, same
/// frames), with `switched[t]` true where a section switched level in frame `t`.
pub fn excess_popping(
    lod: &[image::GrayImage],
    strands: &[image::GrayImage],
    switched: &[bool],
) -> ExcessPopping {
    let frames = lod.len().min(strands.len()).min(switched.len());
    let (mut at, mut at_count, mut other, mut other_count) = (0.0, 0usize, 0.0, 0usize);
    for t in 1..frames {
        let excess =
            luma_difference(&lod[t], &lod[t - 1]) - luma_difference(&strands[t], &strands[t - 1]);
        if switched[t] {
            at += excess;
            at_count += 1;
        } else {
            other += excess;
            other_count += 1;
        }
    }
    ExcessPopping {
        at_switches: if at_count > 0 {
            at / at_count as f64
        } else {
            0.0
        },
        elsewhere: if other_count > 0 {
            other / other_count as f64
        } else {
            0.0
        },
        switch_frames: at_count,
    }
}
