//! A crowd: several characters in one frame, each with its own groom, place, head motion and
//! wind, simulated, collided and drawn together, with level selection across all of them under
//! one tolerance or one frame budget.
//!
//! A crowd is a [`World`](crate::pipeline::World) of many characters (each its groom on its own
//! head, the head placed in the world through its motion,
//! [`HeadMotion::placed`](hair_core::dynamics::HeadMotion::placed)) advanced through the same
//! frame loop as a lone [`Pipeline`](crate::pipeline::Pipeline), so dynamics, collision and
//! hand-over are exactly one character's, and every character's level blocks step in one
//! parallel pass. What the crowd adds:
//! - **one budget**: with a frame budget, every character's sections offer their options and
//!   one greedy refinement
//!   ([`refine_within_budget`](hair_core::lod::refine_within_budget)) chooses all their levels,
//!   so detail goes to whichever character's sections buy the most error per second, near or
//!   far;
//! - **one frame**: the characters' reports are summed into one [`FrameReport`], so the frame
//!   loop, the budget controller, the cost model and the benchmark tables treat a crowd as one
//!   scene;
//! - **one picture**: [`CrowdRenderer`] draws every character's groom and head in one pass.
//!
//! Characters with the same groom parameters share one built groom (one `Arc<Scene>`, in their
//! models too) and one deviation measurement ([`CrowdModel`]). A crowd whose estimated memory
//! is over what the machine has available is refused before its world is built
//! ([`memory`]).
//!
//! ```no_run
//! use hairlod::crowd::{Crowd, CrowdModel};
//! use hairlod::scene_file::SceneFile;
//!
//! let shot = SceneFile::read("scenes/crowd.toml".as_ref())?.resolve()?;
//! let model = CrowdModel::build(&shot)?;
//! let mut crowd = Crowd::new(&model, shot.settings)?;
//! let report = crowd.advance(&shot.camera(0))?;
//! println!("{} sections at each level", report.sections_at.iter().sum::<usize>());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod frame;
mod heads;
pub mod memory;
mod model;
mod render;
mod run;

pub use frame::Crowd;
pub use model::{CrowdMember, CrowdModel};
pub use render::{CrowdRenderer, concatenated_geometry};
pub use run::run_crowd;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_checkpoint;
