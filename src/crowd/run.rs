//! A crowd shot run in one mode through the frame loop ([`run_frames`]): the crowd built from
//! its [`CrowdModel`] (or resumed from a checkpoint), drawn by a [`CrowdRenderer`], with or
//! without a frame budget.

use super::frame::Crowd;
use super::model::CrowdModel;
use super::render::CrowdRenderer;
use crate::pipeline::Result;
use crate::run::{FrameOutput, RunOptions, RunResult, View, check_frames, run_frames};

/// Runs `options.frames` of `model`'s shot with `options.settings` (and `options.budget`, at
/// automatic levels), from the start or from `options.resume` (a crowd checkpoint whose frame is
/// where the frames start), drawing `views` with `renderer` when given; `on_frame` sees each
/// frame.
pub fn run_crowd(
    model: &CrowdModel,
    options: RunOptions,
    renderer: Option<(&mut CrowdRenderer, &[View])>,
    on_frame: impl FnMut(FrameOutput<'_, Crowd>) -> Result<()>,
) -> Result<RunResult<Crowd>> {
    let RunOptions {
        settings,
        frames,
        resume,
        budget,
    } = options;
    let shot = &model.shot;
    check_frames(shot, &frames, resume.as_ref())?;
    let crowd = match resume {
        Some(checkpoint) => Crowd::resume(model, settings, checkpoint)?,
        None => Crowd::new(model, settings)?,
    };
    run_frames(shot, crowd, frames, budget, renderer, on_frame)
}
