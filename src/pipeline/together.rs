//! Characters stepped together (a crowd's world): every level block of every character in one
//! parallel pass ([`step_blocks`]), for a frame and for the settling fall, so small blocks of
//! many characters fill the threads as one large block would.

use hair_core::dynamics::Environment;

use super::error::Result;
use super::pipeline::Pipeline;
use super::report::FrameReport;
use super::step::step_blocks;

/// Ends the frame of every pipeline (each begun or not): their level blocks stepped in one pass
/// and each one's report, in order, with the blocks' own dynamics and collision times (summed
/// over the characters they exceed the wall clock: charge them with
/// [`charge_wall_time`](super::step::charge_wall_time)). Errors with the first failing block in
/// the pipelines' order.
pub(crate) fn step_together(pipelines: &mut [Pipeline]) -> Result<Vec<FrameReport>> {
    let mut steps = Vec::new();
    let mut counts = Vec::with_capacity(pipelines.len());
    for pipeline in pipelines.iter_mut() {
        let time = pipeline.time();
        let before = steps.len();
        steps.extend(pipeline.block_steps(None, time));
        counts.push(steps.len() - before);
    }
    let stepped = step_blocks(steps)?;
    let mut reports = Vec::with_capacity(pipelines.len());
    let mut first = 0;
    for (pipeline, count) in pipelines.iter_mut().zip(counts) {
        reports.push(pipeline.end_frame(&stepped[first..first + count])?);
        first += count;
    }
    Ok(reports)
}

/// [`Pipeline::settle`] for every pipeline, their blocks stepped together: each one's hair
/// falls for `seconds` [s] with its head held still, without advancing its clock.
pub(crate) fn settle_together(pipelines: &mut [Pipeline], seconds: f32) -> Result<()> {
    let still: Vec<Environment> = pipelines.iter().map(Pipeline::settle_environment).collect();
    let counts: Vec<usize> = pipelines.iter().map(|p| p.settle_steps(seconds)).collect();
    let longest = counts.iter().copied().max().unwrap_or(0);
    for step in 0..longest {
        let mut steps = Vec::new();
        for ((pipeline, environment), &count) in pipelines.iter_mut().zip(&still).zip(&counts) {
            if step < count {
                steps.extend(pipeline.block_steps(Some(environment), 0.0));
            }
        }
        step_blocks(steps)?;
    }
    for pipeline in pipelines {
        pipeline.settled();
    }
    Ok(())
}
