//! The frame pipeline: one [`Pipeline`] holds a character's model (scene, environment,
//! settings), its state ([`PipelineState`]) and the working memory that steps it, and advances one
//! frame at a time through stage modules in order (DESIGN "One frame"):
//!
//! 1. control for time t (head pose, wind) and the camera;
//! 2. observe (`observe`): every section observed on its current level;
//! 3. select (`select`, `budget`): levels chosen by the pixel tolerance or a frame budget (§7),
//!    blends and fades started;
//! 4. hand over (`hand_over`): blocks rebuilt where a section changed level, state mapped over
//!    (§4.2), the working memory (`work`) rebuilt around them;
//! 5. step (`step`): every level block in one parallel pass, F_col from the head's collision
//!    body in head space (§5.4), one step of the integrator, the positional guarantee; a crowd's
//!    characters step together in the same pass (`together`), and the settling fall is the same
//!    step;
//! 6. gather (`drawn`): the skeletons to draw, for the renderer ([`Pipeline::gather_drawn`]).
//!
//! Fixed-level modes ([`LodMode::Fixed`]) run through the same code for comparison. Each stage's
//! wall-clock time is in the frame's [`FrameReport`]. Everything that evolves is a [`PipelineState`],
//! which a [`Checkpoint`] writes to a file and [`Pipeline::resume`] goes on from, bit for bit.

mod block;
mod budget;
mod checkpoint;
mod draw;
mod drawn;
mod error;
mod fingerprint;
mod hand_over;
mod levels;
mod observe;
#[allow(clippy::module_inception)]
mod pipeline;
mod report;
mod select;
mod settings;
mod state;
mod state_check;
mod step;
mod strands_out;
mod style;
mod together;
mod work;

pub use block::LevelBlock;
pub use budget::FrameBudget;
pub use checkpoint::{CHECKPOINT_FORMAT, CHECKPOINT_VERSION, Checkpoint};
pub use draw::PipelineRenderer;
pub use error::{PipelineError, Result};
pub use levels::SectionLevels;
pub use pipeline::Pipeline;
pub use report::{FrameReport, LodChanges, StageTimes};
pub use settings::{LodMode, PipelineSettings, RunMode};
pub use state::PipelineState;
pub use state_check::{MAX_NODE_SPEED, MAX_STATE_FRAMES};
pub use style::DrawStyle;

pub(crate) use budget::{calibrate as calibrate_budget, check_budget, choose_within_budget};
pub(crate) use step::charge_wall_time;
pub(crate) use together::{settle_together, step_together};
