//! The paper tables' runs (§8.2) as a typed list: [`PaperRun`] names each of the five (LODs,
//! Strands, Clusters, Patches, LODs switching instantly), [`PaperOptions`] the settings they share,
//! and [`run_paper_tables`] runs them interleaved frame by frame on one renderer and returns what the
//! tables print ([`PaperRuns`]): each run's frames, its mean SSIM and pixel error against the
//! Strands frames, and the popping measures. [`run_budgeted_against`] adds a frame-budget run.

use glam::Vec3;
use hair_core::Scene;
use hair_core::lod::{BudgetMethod, BudgetSettings, ErrorModel, LodSettings};
use hair_core::{HairError, Level};
use image::GrayImage;
use serde::Serialize;

use super::{BudgetedRun, run_budgeted};
use crate::accuracy::{
    geometric_error_of_visible, head_sight, sample_skeletons, strand_skeletons, visible_samples,
};
use crate::metrics::{luma, ssim};
use crate::pipeline::{LodMode, PipelineError, PipelineRenderer, PipelineSettings};
use crate::popping::{ExcessPopping, Popping, PoppingMeter, excess_popping};
use crate::run::{FrameLoop, ModeRun, RunOptions, View};
use crate::shot::Shot;

/// One of the paper tables' five runs, in the order they are interleaved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PaperRun {
    /// Automatic levels with the shot's (or the options') blend between levels.
    Lods,
    /// Every section as five strand groups: the reference the others are compared with.
    Strands,
    /// Every section as three clusters.
    Clusters,
    /// Every section as one patch.
    Patches,
    /// Automatic levels switching instantly (`blend_time` 0, the paper's transitions).
    LodsInstantSwitching,
}

impl PaperRun {
    /// The five runs, in the order they run each frame.
    pub const ALL: [PaperRun; 5] = [
        PaperRun::Lods,
        PaperRun::Strands,
        PaperRun::Clusters,
        PaperRun::Patches,
        PaperRun::LodsInstantSwitching,
    ];

    /// The run's name in tables and reports (`LODs`, `Strands`, `Clusters`, `Patches`, `LODs,
    /// instant switching`).
    pub fn label(self) -> &'static str {
        self.run_mode().name()
    }

    /// The run's mode in its reports.
    pub fn run_mode(self) -> crate::pipeline::RunMode {
        match self {
            PaperRun::LodsInstantSwitching => crate::pipeline::RunMode::LodsInstantSwitching,
            run => run.mode(LodSettings::default()).run_mode(),
        }
    }

    /// The levels the run draws, the automatic ones chosen with `lod`.
    pub fn mode(self, lod: LodSettings) -> LodMode {
        match self {
            PaperRun::Lods => LodMode::Auto(lod),
            PaperRun::Strands => LodMode::Fixed(Level::StrandGroup),
            PaperRun::Clusters => LodMode::Fixed(Level::Cluster),
            PaperRun::Patches => LodMode::Fixed(Level::Patch),
            PaperRun::LodsInstantSwitching => LodMode::Auto(LodSettings {
                blend_time: 0.0,
                ..lod
            }),
        }
    }
}

/// What the paper tables' LODs change from the shot, and the frame-budget runs to add.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PaperOptions {
    /// Frame budget [ms] for budgeted LODs runs (`None`: the shot's budget, if any).
    pub budget_ms: Option<f64>,
    /// How the budget is met, one budgeted run each (empty: the budget's own method).
    pub budget_methods: Vec<BudgetMethod>,
    /// Error model of the LODs (`None`: the shot's).
    pub error_model: Option<ErrorModel>,
    /// Blend duration of the LODs [s] (`None`: the shot's).
    pub blend_time: Option<f32>,
    /// Look ahead of the LODs' choice, a fraction of the blend time (`None`: the shot's).
    pub blend_lead: Option<f32>,
    /// Strands the LODs draw per pixel of a strand group's screen width (`None`: the shot's; 0
    /// draws every strand).
    pub strands_per_pixel: Option<f32>,
    /// Whether the LODs' thinned strands are widened to stand for those left out (`None`: the
    /// shot's).
    pub raise_thinned_widths: Option<bool>,
}

impl PaperOptions {
    /// The LODs' settings on `shot` at `pixel_tolerance` [pixels], with these overrides; checked.
    pub fn lod(&self, shot: &Shot, pixel_tolerance: f32) -> Result<LodSettings, HairError> {
        let base = shot.lod_settings();
        let lod = LodSettings {
            pixel_tolerance,
            error_model: self.error_model.unwrap_or(base.error_model),
            blend_time: self.blend_time.unwrap_or(base.blend_time),
            blend_lead: self.blend_lead.unwrap_or(base.blend_lead),
            strands_per_pixel: self.strands_per_pixel.unwrap_or(base.strands_per_pixel),
            raise_thinned_widths: self
                .raise_thinned_widths
                .unwrap_or(base.raise_thinned_widths),
            ..base
        };
        lod.validate()?;
        Ok(lod)
    }

    /// The frame-budget runs to make with the LODs' settings `lod`: one per method of
    /// [`PaperOptions::budget_methods`] at [`PaperOptions::budget_ms`] (or the shot's budget),
    /// holding a lowering of the tolerance for the blend time; none without a budget.
    pub fn budgets(
        &self,
        shot: &Shot,
        lod: &LodSettings,
    ) -> Result<Vec<BudgetSettings>, HairError> {
        let budget = match self.budget_ms {
            Some(ms) => {
                // Hold a lowering of the tolerance for the blend time: its cost shows only after it.
                let frame_time = shot.settings.dynamics.time_step;
                let settings = BudgetSettings {
                    hold_frames: (lod.blend_time / frame_time).round() as usize,
                    ..BudgetSettings::new(ms / 1e3)
                };
                settings.validate()?;
                Some(settings)
            }
            None => shot.budget,
        };
        let Some(budget) = budget else {
            return Ok(Vec::new());
        };
        let methods = if self.budget_methods.is_empty() {
            vec![budget.method]
        } else {
            self.budget_methods.clone()
        };
        Ok(methods
            .into_iter()
            .map(|method| BudgetSettings { method, ..budget })
            .collect())
    }
}

/// A failed paper-table run: which run, and at which frame.
#[derive(Debug, thiserror::Error)]
pub enum PaperRunError {
    /// A run could not start.
    #[error("the {} run failed to start", run.label())]
    Start {
        /// The run.
        run: PaperRun,
        /// Why.
        #[source]
        source: PipelineError,
    },
    /// A run failed making a frame.
    #[error("the {} run failed at frame {frame}", run.label())]
    Frame {
        /// The run.
        run: PaperRun,
        /// The frame.
        frame: usize,
        /// Why.
        #[source]
        source: PipelineError,
    },
    /// A run ended before the shot's last frame.
    #[error("the {} run ended before frame {frame}", run.label())]
    Ended {
        /// The run.
        run: PaperRun,
        /// The frame it did not make.
        frame: usize,
    },
    /// Measuring a frame against the Strands frame failed.
    #[error(transparent)]
    Measure(#[from] PipelineError),
}

/// A value per compared run: the LODs (both), Clusters and Patches against Strands.
#[derive(Debug, Serialize, Clone, Copy, PartialEq, Default)]
pub struct AgainstStrands {
    /// The LODs.
    pub lods: f64,
    /// The LODs switching instantly (`blend_time` 0, the paper's transitions).
    pub lods_instant_switching: f64,
    /// Clusters.
    pub clusters: f64,
    /// Patches.
    pub patches: f64,
}

/// What the paper tables' five runs made.
#[derive(Debug, Clone)]
pub struct PaperRuns {
    /// LODs, Strands, Clusters, Patches, in the paper's column order.
    pub modes: Vec<ModeRun>,
    /// The LODs again switching instantly, named `LODs, instant switching`.
    pub instant: ModeRun,
    /// Mean SSIM of each run's frames against the Strands frames, frame by frame.
    pub mean_ssim: AgainstStrands,
    /// Mean pixel error of each run's hair samples (8 per strand-group skeleton it stands for)
    /// against the Strands run's visible ones, frame by frame [pixels].
    pub mean_pixels: AgainstStrands,
    /// Popping of the LODs (blended), between consecutive frames.
    pub popping_blended: Popping,
    /// Popping of the LODs switching instantly.
    pub popping_instant: Popping,
    /// The blended LODs' popping beyond the camera's motion.
    pub excess_blended: ExcessPopping,
    /// The instant LODs' popping beyond the camera's motion.
    pub excess_instant: ExcessPopping,
    /// The Strands frames' luma, for comparing further runs (budgeted ones) with.
    pub strand_frames: Vec<GrayImage>,
}

/// Hair samples of a frame and which of them the viewer sees.
type Reference = (Vec<Vec3>, Vec<bool>);

/// Runs `shot`'s frames in the five [`PaperRun`]s, the LODs from `lod`, interleaved frame by
/// frame (each makes frame k before any makes k + 1, so that every run sees the same machine
/// load: on a shared machine, runs one after another can differ by 10–20 % for load alone).
/// The runs share `scene` and `renderer`; each frame's work is its own (bit for bit what the run
/// alone makes, `tests/frame_loop.rs`). `on_step` sees each run's frame as it is made.
pub fn run_paper_tables(
    shot: &Shot,
    scene: &Scene,
    lod: LodSettings,
    renderer: &mut PipelineRenderer,
    mut on_step: impl FnMut(PaperRun, usize),
) -> Result<PaperRuns, PaperRunError> {
    let mut loops = Vec::with_capacity(PaperRun::ALL.len());
    for run in PaperRun::ALL {
        let settings = PipelineSettings {
            lod: run.mode(lod),
            ..shot.settings
        };
        let options = RunOptions::whole(shot, settings);
        let frame_loop = FrameLoop::start(shot, scene, options, Some(&mut *renderer))
            .map_err(|source| PaperRunError::Start { run, source })?;
        loops.push((run, frame_loop));
    }
    let mut meters: Vec<PoppingMeter> = loops.iter().map(|_| PoppingMeter::default()).collect();
    let (mut ssim_sums, mut pixel_sums) = ([0.0f64; 5], [0.0f64; 5]);
    // Luma and hair samples of the LODs and Strands frames (the LODs' are compared when the
    // Strands frame is made), and the instant LODs' luma with where they switched.
    let (mut lod_frames, mut strand_frames, mut instant_frames) =
        (Vec::new(), Vec::new(), Vec::new());
    let mut instant_switched = Vec::new();
    let mut lod_samples: Vec<Vec<Vec3>> = Vec::new();
    let mut strand_samples: Vec<Reference> = Vec::new();
    let (width, height) = (shot.width, shot.height);
    let views = [View::Shaded];
    for frame in 0..shot.frames {
        for (index, (run, frame_loop)) in loops.iter_mut().enumerate() {
            let run = *run;
            let output = frame_loop
                .step(Some((&mut *renderer, &views)))
                .map_err(|source| PaperRunError::Frame { run, frame, source })?
                .ok_or(PaperRunError::Ended { run, frame })?;
            let report = output.report;
            // Every run's hair samples against the Strands run's (the pixel error).
            let groom = &output.pipeline.scene().groom;
            let samples = sample_skeletons(groom, &strand_skeletons(output.pipeline)?, 8);
            let error = |(reference, visible): &Reference, samples: &[Vec3]| {
                geometric_error_of_visible(
                    output.camera,
                    width,
                    height,
                    reference,
                    samples,
                    visible,
                )
                .mean_pixels
            };
            match run {
                PaperRun::Lods => lod_samples.push(samples),
                PaperRun::Strands => {
                    let sight = head_sight(output.pipeline)?;
                    let visible = visible_samples(output.camera, &sight, &samples);
                    let reference = (samples, visible);
                    pixel_sums[0] += error(&reference, &lod_samples[frame]);
                    strand_samples.push(reference);
                }
                _ => pixel_sums[index] += error(&strand_samples[frame], &samples),
            }
            if let Some(image) = output.images.first() {
                meters[index].add(image, report.level_changes > 0);
                match run {
                    PaperRun::Lods => lod_frames.push(luma(image)),
                    PaperRun::Strands => {
                        let gray = luma(image);
                        ssim_sums[0] += ssim(&lod_frames[frame], &gray);
                        strand_frames.push(gray);
                    }
                    PaperRun::Clusters | PaperRun::Patches => {
                        ssim_sums[index] += ssim(&strand_frames[frame], &luma(image));
                    }
                    PaperRun::LodsInstantSwitching => {
                        let gray = luma(image);
                        ssim_sums[index] += ssim(&strand_frames[frame], &gray);
                        instant_frames.push(gray);
                        instant_switched.push(report.level_changes > 0);
                    }
                }
            }
            on_step(run, frame);
        }
    }
    let mut modes = Vec::with_capacity(4);
    let mut instant = None;
    for (run, frame_loop) in loops {
        let made = frame_loop.finish().run;
        match run {
            PaperRun::LodsInstantSwitching => {
                instant = Some(ModeRun {
                    mode: run.run_mode(),
                    ..made
                });
            }
            _ => modes.push(made),
        }
    }
    let blended_switched: Vec<bool> = modes[0]
        .frames
        .iter()
        .map(|f| f.level_changes > 0)
        .collect();
    let frames = shot.frames as f64;
    let mean = |sums: [f64; 5]| AgainstStrands {
        lods: sums[0] / frames,
        lods_instant_switching: sums[4] / frames,
        clusters: sums[2] / frames,
        patches: sums[3] / frames,
    };
    Ok(PaperRuns {
        excess_blended: excess_popping(&lod_frames, &strand_frames, &blended_switched),
        excess_instant: excess_popping(&instant_frames, &strand_frames, &instant_switched),
        popping_blended: meters[0].popping(),
        popping_instant: meters[4].popping(),
        modes,
        instant: instant.expect("the instant-switching run is one of the five"),
        mean_ssim: mean(ssim_sums),
        mean_pixels: mean(pixel_sums),
        strand_frames,
    })
}

/// A frame-budget run and the error it paid.
#[derive(Debug, Clone, Serialize)]
pub struct BudgetedAgainstStrands {
    /// The run.
    #[serde(flatten)]
    pub run: BudgetedRun,
    /// Mean SSIM of its frames against the Strands frames.
    pub mean_ssim_against_strands: f64,
}

/// Runs the LODs (`lod`) under the frame budget `budget` ([`run_budgeted`]) and compares each
/// frame with the Strands frame of the same number in `strand_frames` (luma); `on_frame` sees
/// each frame's pixel tolerance [pixels].
pub fn run_budgeted_against(
    shot: &Shot,
    scene: &Scene,
    lod: LodSettings,
    budget: BudgetSettings,
    renderer: &mut PipelineRenderer,
    strand_frames: &[GrayImage],
    mut on_frame: impl FnMut(f32),
) -> Result<BudgetedAgainstStrands, PipelineError> {
    let mut ssim_sum = 0.0;
    let run = run_budgeted(
        shot,
        scene,
        lod,
        budget,
        renderer,
        |report, image, tolerance| {
            if let Some(strands) = strand_frames.get(report.frame) {
                ssim_sum += ssim(strands, &luma(image));
            }
            on_frame(tolerance);
        },
    )?;
    Ok(BudgetedAgainstStrands {
        run,
        mean_ssim_against_strands: ssim_sum / shot.frames.max(1) as f64,
    })
}
