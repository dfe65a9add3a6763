//! Automatic levels of detail (§4.2, §7): which level every section takes each frame, and how
//! skeleton state passes between levels.
//!
//! - [`LodSettings`]: the pixel tolerance the distance limits derive from, motion thresholds,
//!   hysteresis, per-section rules, blend time;
//! - [`criteria`]: the paper's tests as pure functions (occlusion rays against a box inside the
//!   head, projected skeleton length, motion measure, a level with hysteresis);
//! - [`LodSelector`]: the per-frame choice for every section ([`SectionChoice`]) from what it sees of
//!   each ([`SectionObservation`]);
//! - [`hand_over`]: a section's skeleton state from one level to another (split and merge);
//! - [`BudgetController`]: the frame-budget mode, the pixel tolerance steered to meet a time
//!   budget per frame.

mod budget;
pub mod criteria;
mod selector;
mod settings;
mod transfer;

#[cfg(test)]
mod tests;

pub use budget::{BudgetController, BudgetReport, BudgetSettings};
pub use criteria::{
    distance_limits, head_point_acceleration, head_point_acceleration_from_poses, is_occluded,
    level_with_hysteresis, motion_measure, projected_length, segment_hits_box,
};
pub use selector::{LodSelector, Reason, SectionChoice, SectionObservation};
pub use settings::LodSettings;
pub use transfer::{SectionStateRef, hand_over};
