//! The frame pipeline: one [`Pipeline`] owns the scene, the skeleton states of the levels in use,
//! their solvers and the level selector, and advances one frame at a time (DESIGN "One frame"):
//!
//! 1. control for time t (head pose, wind) and the camera;
//! 2. level of detail: every section observed on its current level, levels chosen (§7), state
//!    handed over where a section changed level (§4.2), blends started and ended;
//! 3. dynamics with collision, per level block: F_col from the head (§5.4), one step of the
//!    integrator, the positional guarantee;
//! 4. the skeletons to draw, gathered for the renderer ([`Pipeline::gather_drawn`]).
//!
//! Fixed-level modes ([`LodMode::Fixed`]) run through the same code for comparison. Each stage's
//! wall-clock time is in the frame's [`FrameReport`]. Everything that evolves is a [`PipelineState`],
//! which a [`Checkpoint`] writes to a file and [`Pipeline::resume`] goes on from, bit for bit.

mod block;
mod checkpoint;
mod draw;
mod drawn;
mod error;
mod fingerprint;
mod levels;
mod observe;
#[allow(clippy::module_inception)]
mod pipeline;
mod report;
mod settings;
mod state;
mod state_check;
mod strands_out;
mod style;

pub use block::LevelBlock;
pub use checkpoint::{CHECKPOINT_FORMAT, CHECKPOINT_VERSION, Checkpoint};
pub use draw::PipelineRenderer;
pub use error::{PipelineError, Result};
pub use levels::SectionLevels;
pub use pipeline::Pipeline;
pub use report::{FrameReport, LodChanges, StageTimes};
pub use settings::{LodMode, PipelineSettings};
pub use state::PipelineState;
pub use state_check::{MAX_NODE_SPEED, MAX_STATE_FRAMES};
pub use style::DrawStyle;
