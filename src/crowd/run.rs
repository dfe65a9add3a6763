//! A crowd shot run in one mode through the frame loop ([`run_frames`]): the crowd built from
//! its [`CrowdModel`], drawn by a [`CrowdRenderer`], with or without a frame budget.

use hair_core::lod::BudgetSettings;

use super::frame::Crowd;
use super::model::CrowdModel;
use super::render::CrowdRenderer;
use crate::pipeline::{PipelineSettings, Result};
use crate::run::{FrameOutput, RunResult, View, run_frames};

/// Runs every frame of `model`'s shot with `settings` (and `budget`, at automatic levels),
/// drawing `views` with `renderer` when given; `on_frame` sees each frame.
pub fn run_crowd(
    model: &CrowdModel,
    settings: PipelineSettings,
    budget: Option<BudgetSettings>,
    renderer: Option<(&mut CrowdRenderer, &[View])>,
    on_frame: impl FnMut(FrameOutput<'_, Crowd>) -> Result<()>,
) -> Result<RunResult<Crowd>> {
    let crowd = Crowd::new(model, settings)?;
    let shot = &model.shot;
    run_frames(shot, crowd, 0..shot.frames, budget, renderer, on_frame)
}
