//! The step stage (DESIGN "One frame", step 3): every level block of every character advanced
//! one dynamics step with collision, side by side. Blocks share nothing they write (each level
//! poses its own copy of the collision bodies), so the frame is the same whatever the order or
//! the thread count. A frame ([`Pipeline::finish_frame`](super::Pipeline::finish_frame)), the
//! settling fall ([`Pipeline::settle`](super::Pipeline::settle)) and a crowd's frame all step
//! through [`step_blocks`].

use std::time::Instant;

use rayon::prelude::*;

use hair_collide::CollisionBody;
use hair_core::Level;
use hair_core::dynamics::Environment;

use super::block::LevelBlock;
use super::error::Result;
use super::report::FrameReport;
use super::work::LevelWork;

/// One block to step: its state, its solvers, the environment it moves in and the time its
/// state is at before the step [s].
pub(crate) struct BlockStep<'a> {
    pub(crate) level: Level,
    pub(crate) block: &'a mut LevelBlock,
    pub(crate) work: &'a mut LevelWork,
    pub(crate) environment: &'a Environment,
    pub(crate) time: f64,
    /// Hold a deforming head at rest through the step (the settling fall).
    pub(crate) hold_body: bool,
    /// A deforming head's collision body at the step's end, for the projection, and the farthest
    /// its surface moved over the step [m].
    pub(crate) body_at_end: Option<(&'a CollisionBody, f32)>,
}

/// What every block of a character steps with: the environment, the time the state is at
/// before the step [s], and for a deforming head whether it is held at rest and its collision
/// body at the step's end.
#[derive(Clone, Copy)]
pub(crate) struct StepInputs<'a> {
    pub(crate) environment: &'a Environment,
    pub(crate) time: f64,
    pub(crate) hold_body: bool,
    pub(crate) body_at_end: Option<(&'a CollisionBody, f32)>,
}

/// What stepping one block did: its level, the wall-clock time of its dynamics and collision
/// [s], the segments in contact, the largest stretch the projection left and the substeps its
/// dynamics took.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BlockStepped {
    pub(crate) level: Level,
    pub(crate) dynamics: f64,
    pub(crate) collision: f64,
    pub(crate) contacts: usize,
    pub(crate) max_stretch: f32,
    pub(crate) substeps: u32,
}

impl BlockStepped {
    /// The frame's dynamics and collision figures with this block's added.
    pub(crate) fn add_to(&self, report: &mut FrameReport) {
        report.times.dynamics += self.dynamics;
        report.times.collision += self.collision;
        report.contacts += self.contacts;
        report.max_stretch = report.max_stretch.max(self.max_stretch);
        report.max_substeps = report.max_substeps.max(self.substeps);
        report.level_seconds[self.level as usize] += self.dynamics + self.collision;
        report.level_dynamics[self.level as usize] += self.dynamics;
        report.level_collision[self.level as usize] += self.collision;
    }
}

/// The blocks of one character, each with its working memory, to be stepped with `inputs` (an
/// empty block is left out).
pub(crate) fn character_steps<'a>(
    blocks: impl Iterator<Item = (Level, &'a mut LevelBlock)>,
    work: impl Iterator<Item = (Level, &'a mut LevelWork)>,
    inputs: StepInputs<'a>,
) -> impl Iterator<Item = BlockStep<'a>> {
    blocks
        .zip(work)
        .filter(|(_, (_, work))| work.simulation.is_some())
        .map(move |((level, block), (_, work))| BlockStep {
            level,
            block,
            work,
            environment: inputs.environment,
            time: inputs.time,
            hold_body: inputs.hold_body,
            body_at_end: inputs.body_at_end,
        })
}

/// Runs `work` on a thread of rayon's pool and returns what it returns. A frame's stages each
/// split their work with rayon; called from a thread outside the pool (the program's own), every
/// split would hand its work to the pool and sleep until it is done, and the pool's threads
/// would fall asleep between stages, so a frame of a dozen stages paid a dozen wake-ups of both
/// sides. Run from inside the pool, a stage's split is a task the calling thread takes part in.
/// Measured on the 2 cores with the talking head's 20k-triangle body (`cargo run --release
/// --example deforming_body_cost 240`, `docs/bodies.md`): collision fell from 1.54–1.72 to
/// 1.44–1.56 ms a frame and dynamics from 0.94–0.98 to 0.88–0.92 ms; at one thread collision
/// fell from 2.79–2.95 to 2.31–2.35 ms.
pub(crate) fn on_pool<R: Send>(work: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| work())
}

/// Steps every block of `steps` side by side; returns what each did, in `steps`' order, or the
/// first error in that order (the same whatever the thread count).
pub(crate) fn step_blocks(steps: Vec<BlockStep<'_>>) -> Result<Vec<BlockStepped>> {
    let stepped: Vec<Result<BlockStepped>> = steps.into_par_iter().map(step_block).collect();
    stepped.into_iter().collect()
}

/// One block's dynamics step with collision: F_col from the bodies (§5.4), the integrator's
/// step, the positional guarantee; the integrator alone with collision off.
fn step_block(step: BlockStep<'_>) -> Result<BlockStepped> {
    let BlockStep {
        level,
        block,
        work,
        environment,
        time,
        hold_body,
        body_at_end,
    } = step;
    let mut stepped = BlockStepped {
        level,
        dynamics: 0.0,
        collision: 0.0,
        contacts: 0,
        max_stretch: 0.0,
        substeps: 0,
    };
    let Some(simulation) = work.simulation.as_mut() else {
        return Ok(stepped);
    };
    block.state.time = time;
    // Held at rest: the carrier (which would move the roots with the body's time) steps aside.
    let held = if hold_body {
        simulation.take_root_carrier()
    } else {
        None
    };
    match &mut work.solver {
        Some(solver) => {
            let started = Instant::now();
            let contacts =
                solver.before_step(&mut work.bodies, simulation, &mut block.state, environment)?;
            stepped.contacts = contacts.contact_segments;
            stepped.collision += started.elapsed().as_secs_f64();
            let started = Instant::now();
            stepped.substeps = simulation.step(&mut block.state, environment)?.substeps;
            stepped.dynamics += started.elapsed().as_secs_f64();
            let started = Instant::now();
            if let Some((end, moved)) = body_at_end {
                // The deforming head where the step ends: what the projection holds the nodes
                // out of, and the next step's contacts start from.
                for body in work.bodies.iter_mut() {
                    *body = end.clone();
                }
                solver.shrink_clearances(moved);
            }
            let projection =
                solver.after_step(&mut work.bodies, simulation, &mut block.state, environment)?;
            stepped.max_stretch = projection.max_stretch;
            stepped.collision += started.elapsed().as_secs_f64();
        }
        None => {
            let started = Instant::now();
            stepped.substeps = simulation.step(&mut block.state, environment)?.substeps;
            stepped.dynamics += started.elapsed().as_secs_f64();
        }
    }
    if held.is_some() {
        simulation.set_root_carrier(held)?;
    }
    Ok(stepped)
}

/// Blocks stepped side by side measure, each, the time its own dynamics and collision took;
/// summed, those exceed the time the step took. Scales the report's dynamics, collision and
/// per-level times so that dynamics and collision add up to `wall` [s], the time the stepping
/// took, shared between them (and between the levels) as the blocks' own times share it.
pub(crate) fn charge_wall_time(report: &mut FrameReport, wall: f64) {
    let busy = report.times.dynamics + report.times.collision;
    if !(busy > 0.0 && wall.is_finite()) {
        return;
    }
    let scale = wall / busy;
    report.times.dynamics *= scale;
    report.times.collision *= scale;
    for seconds in report
        .level_seconds
        .iter_mut()
        .chain(&mut report.level_dynamics)
        .chain(&mut report.level_collision)
    {
        *seconds *= scale;
    }
}
