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
//! wall-clock time is in the frame's [`FrameReport`]. [`measure_popping`] measures the image
//! change that level decisions make on their own, with blended transitions and without.

mod block;
mod draw;
mod error;
#[allow(clippy::module_inception)]
mod pipeline;
mod popping;
mod report;
mod settings;
mod transitions;

pub use block::LevelBlock;
pub use draw::PipelineRenderer;
pub use error::{PipelineError, Result};
pub use pipeline::Pipeline;
pub use popping::{
    PoppingComparison, PoppingFrame, SwitchPopping, advance_measured, compare_popping,
    measure_popping, switch_popping,
};
pub use report::{FrameReport, LodChanges, StageTimes};
pub use settings::{LodMode, PipelineSettings};
pub use transitions::SectionLevels;
