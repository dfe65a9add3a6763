//! The popping measures, all in one place: image differences between consecutive frames where
//! sections switched level and where none did, whole-image and beyond the camera's own motion
//! (this file), and what a frame's level decisions change on their own ([`lod_stage`]).

mod lod_stage;

pub use lod_stage::{
    PoppingComparison, PoppingFrame, SwitchPopping, advance_measured, compare_popping,
    measure_popping, switch_popping,
};

use serde::Serialize;

use crate::metrics::{luma_difference, mean_abs_difference};

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
