//! The frame pipeline. A [`World`] holds the characters, each one's model (scene, environment,
//! material) and state ([`PipelineState`]), and the settings they run with; the world's pipeline
//! (`world_pipeline`) holds only working memory (each character's solvers, collision stages,
//! selector and buffers, `character`) and advances every character one frame at a time through
//! stage modules in order (DESIGN "One frame"):
//!
//! 1. control for time t (head pose, wind) and the camera;
//! 2. observe (`observe`): every section observed on its current level;
//! 3. select (`select`, `budget`): levels chosen by the pixel tolerance or by one frame budget
//!    over every character's sections (§7), blends and fades started;
//! 4. hand over (`hand_over`): blocks rebuilt where a section changed level, state mapped over
//!    (§4.2), the working memory (`work`) rebuilt around them;
//! 5. step (`step`): every level block of every character in one parallel pass, F_col from the
//!    head's collision body in head space (§5.4), one step of the integrator, the positional
//!    guarantee; the settling fall is the same step;
//! 6. gather (`drawn`): the skeletons to draw, for the renderer ([`Pipeline::gather_drawn`]).
//!
//! A [`Pipeline`] is a world of one character with its pipeline; a
//! [`Crowd`](crate::crowd::Crowd) is a world of many, through the same loop.
//! Fixed-level modes ([`LodMode::Fixed`]) run through the same code for comparison. Each stage's
//! wall-clock time is in the frame's [`FrameReport`]. Everything that evolves is a [`PipelineState`],
//! which a [`Checkpoint`] writes to a file and [`Pipeline::resume`] goes on from, bit for bit.

mod block;
mod body_motion;
pub(crate) use body_motion::{BodyRide, ShiftedCharacter, body_meshes, strand_root_shifts};
mod budget;
mod character;
mod character_frame;
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
mod work;
mod world;
mod world_pipeline;

pub use block::LevelBlock;
pub use budget::FrameBudget;
pub use checkpoint::{CHECKPOINT_FORMAT, CHECKPOINT_VERSION, Checkpoint};
pub use draw::{DrawnSource, PipelineRenderer};
pub use error::{PipelineError, Result};
pub use levels::SectionLevels;
pub use pipeline::Pipeline;
pub use report::{FrameReport, LodChanges, StageTimes};
pub use settings::{DrawnAs, LodMode, PipelineSettings, RunMode};
pub use state::PipelineState;
pub use state_check::{MAX_NODE_SPEED, MAX_STATE_FRAMES};
pub use style::DrawStyle;
pub use world::{Character, CharacterModel, World};

pub(crate) use character::Shared;
pub(crate) use fingerprint::Fnv1a;
#[cfg(test)]
pub(crate) use step::charge_wall_time;
pub(crate) use world_pipeline::WorldPipeline;
