//! The popping measure: the image change that a frame's level decisions make on their own, with
//! the camera and the skeletons held still, compared between blended transitions and instant
//! switching over the same frames.
//!
//! Each frame is drawn three times through the frame's camera: before the frame (the skeletons,
//! levels and blend coverages of the frame before), after its level-of-detail stage
//! ([`Pipeline::begin_frame`]: the frame's levels and coverages and the handed-over skeletons, not
//! yet stepped) and after its dynamics step (the frame as shown). The first difference is what the
//! level decisions change (the pop, if any); the second is what the hair's own motion changes. The
//! camera's motion is in neither.

use hair_core::lod::LodSettings;
use hair_core::{Camera, Scene};
use hair_render::ShadingMode;
use serde::Serialize;

use crate::metrics::{luma, luma_difference};
use crate::pipeline::{FrameReport, LodMode, Pipeline, PipelineRenderer, PipelineSettings, Result};
use crate::shot::Shot;

/// The image changes of one frame at its own camera, in mean absolute luma difference `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct PoppingFrame {
    /// Some section switched level, came into view or left it in the frame (a blend or a fade
    /// started, or an instant switch).
    pub switched: bool,
    /// What the level-of-detail stage changed: levels, blend coverages and handed-over skeletons,
    /// drawn on the skeletons of the frame before.
    pub lod_change: f64,
    /// What the dynamics step changed (the hair's own motion).
    pub motion_change: f64,
}

/// Advances `pipeline` one frame seen by `camera`, drawing it three times at `width`×`height`
/// (before the frame, after its level-of-detail stage, after its dynamics step); returns the
/// frame's report (rendering time: the last drawing's), its [`PoppingFrame`] and its image.
pub fn advance_measured(
    pipeline: &mut Pipeline,
    renderer: &mut PipelineRenderer,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Result<(FrameReport, PoppingFrame, image::RgbaImage)> {
    let shaded = ShadingMode::Shaded;
    let (before, _) = renderer.render(pipeline, camera, width, height, shaded)?;
    let changes = pipeline.begin_frame(camera)?;
    let (chosen, _) = renderer.render(pipeline, camera, width, height, shaded)?;
    let mut report = pipeline.finish_frame()?;
    let (after, seconds) = renderer.render(pipeline, camera, width, height, shaded)?;
    report.times.rendering = seconds;
    let (before, chosen, shown) = (luma(&before), luma(&chosen), luma(&after));
    let frame = PoppingFrame {
        switched: changes.any(),
        lod_change: luma_difference(&before, &chosen),
        motion_change: luma_difference(&chosen, &shown),
    };
    Ok((report, frame, after))
}

/// Popping of one run over a set of frames.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct SwitchPopping {
    /// Frames measured (where a switch started in either run compared).
    pub switch_frames: usize,
    /// Mean [`PoppingFrame::lod_change`] over those frames.
    pub lod_change: f64,
    /// Mean [`PoppingFrame::motion_change`] over the same frames.
    pub motion_change: f64,
    /// The popping ratio `lod_change / motion_change`: how large the level decisions' change is
    /// against the hair's own motion in the same frames (0 when there is no motion).
    pub ratio: f64,
    /// The largest [`PoppingFrame::lod_change`] of any frame of the run.
    pub peak_lod_change: f64,
    /// The sum of [`PoppingFrame::lod_change`] over every frame of the run but the first.
    pub total_lod_change: f64,
}

/// [`SwitchPopping`] of `frames` over the frames `t ≥ 1` where `at[t]` is true (frame 0 picks the
/// starting levels outright in every run and is left out).
pub fn switch_popping(frames: &[PoppingFrame], at: &[bool]) -> SwitchPopping {
    let measured: Vec<&PoppingFrame> = frames
        .iter()
        .zip(at)
        .skip(1)
        .filter(|(_, at)| **at)
        .map(|(frame, _)| frame)
        .collect();
    let count = measured.len();
    let mean = |value: fn(&PoppingFrame) -> f64| {
        if count == 0 {
            0.0
        } else {
            measured.iter().map(|f| value(f)).sum::<f64>() / count as f64
        }
    };
    let lod_change = mean(|f| f.lod_change);
    let motion_change = mean(|f| f.motion_change);
    SwitchPopping {
        switch_frames: count,
        lod_change,
        motion_change,
        ratio: if motion_change > 0.0 {
            lod_change / motion_change
        } else {
            0.0
        },
        peak_lod_change: frames
            .iter()
            .skip(1)
            .map(|f| f.lod_change)
            .fold(0.0, f64::max),
        total_lod_change: frames.iter().skip(1).map(|f| f.lod_change).sum(),
    }
}

/// Popping with blended transitions and with instant switching, over the same frames: those where
/// a switch started in either run.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct PoppingComparison {
    /// With the blend of the LOD settings.
    pub blended: SwitchPopping,
    /// With instant switching (`blend_time` 0).
    pub instant: SwitchPopping,
    /// Whether both runs switched in exactly the same frames (the levels are chosen from the
    /// current level's skeletons, which blending does not touch, so they should).
    pub same_switch_frames: bool,
}

/// [`PoppingComparison`] of two runs' frames (same length; extra frames of either are ignored).
pub fn compare_popping(blended: &[PoppingFrame], instant: &[PoppingFrame]) -> PoppingComparison {
    let frames = blended.len().min(instant.len());
    let (blended, instant) = (&blended[..frames], &instant[..frames]);
    let at: Vec<bool> = blended
        .iter()
        .zip(instant)
        .map(|(b, i)| b.switched || i.switched)
        .collect();
    PoppingComparison {
        blended: switch_popping(blended, &at),
        instant: switch_popping(instant, &at),
        same_switch_frames: blended
            .iter()
            .zip(instant)
            .skip(1)
            .all(|(b, i)| b.switched == i.switched),
    }
}

/// Runs `shot` at automatic levels (`lod`, with its blend) and again with instant switching, each frame
/// drawn three times (see [`advance_measured`]), and compares their popping; `on_frame` is called
/// after every frame of either run (progress).
pub fn measure_popping(
    shot: &Shot,
    scene: &Scene,
    lod: LodSettings,
    renderer: &mut PipelineRenderer,
    mut on_frame: impl FnMut(),
) -> Result<PoppingComparison> {
    let mut runs = [Vec::new(), Vec::new()];
    let instant = LodSettings {
        blend_time: 0.0,
        ..lod
    };
    for (frames, lod) in runs.iter_mut().zip([lod, instant]) {
        let settings = PipelineSettings {
            lod: LodMode::Auto(lod),
            ..shot.settings
        };
        let mut pipeline = shot.pipeline(scene, settings, None)?;
        renderer.bind(&pipeline)?;
        for frame in 0..shot.frames {
            let camera = shot.camera(frame);
            let (_, measured, _) =
                advance_measured(&mut pipeline, renderer, &camera, shot.width, shot.height)?;
            frames.push(measured);
            on_frame();
        }
    }
    Ok(compare_popping(&runs[0], &runs[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(switched: bool, lod_change: f64, motion_change: f64) -> PoppingFrame {
        PoppingFrame {
            switched,
            lod_change,
            motion_change,
        }
    }

    #[test]
    fn both_runs_are_measured_over_the_same_frames_and_frame_zero_is_left_out() {
        // Frame 0 (the starting levels) would dominate if counted; frame 2 switches in the
        // instant run only and frame 3 in the blended one only: both count for both runs.
        let blended = [
            frame(true, 9.0, 1.0),
            frame(false, 0.5, 1.0),
            frame(false, 0.25, 1.0),
            frame(true, 0.25, 1.0),
        ];
        let instant = [
            frame(true, 9.0, 1.0),
            frame(false, 0.0, 1.0),
            frame(true, 2.0, 1.0),
            frame(false, 0.0, 2.0),
        ];
        let comparison = compare_popping(&blended, &instant);
        assert!(!comparison.same_switch_frames);
        assert_eq!(comparison.blended.switch_frames, 2);
        assert_eq!(comparison.instant.switch_frames, 2);
        assert_eq!(comparison.blended.lod_change, 0.25);
        assert_eq!(comparison.instant.lod_change, 1.0);
        assert_eq!(comparison.instant.motion_change, 1.5);
        assert_eq!(comparison.instant.ratio, 1.0 / 1.5);
        assert_eq!(comparison.blended.peak_lod_change, 0.5);
        assert_eq!(comparison.blended.total_lod_change, 1.0);
        assert_eq!(comparison.instant.total_lod_change, 2.0);
    }

    #[test]
    fn no_switch_and_no_motion_give_zeros_not_nans() {
        let still = [frame(false, 0.0, 0.0); 3];
        let popping = switch_popping(&still, &[false; 3]);
        assert_eq!(popping, SwitchPopping::default());
        let popping = switch_popping(&still, &[true; 3]);
        assert_eq!((popping.switch_frames, popping.ratio), (2, 0.0));
    }
}
