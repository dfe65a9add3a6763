//! Automatic levels of detail (§4.2, §7): which level every section takes each frame, and how
//! skeleton state passes between levels.
//!
//! - [`LodSettings`]: the pixel tolerance the distance limits derive from, motion thresholds,
//!   hysteresis, per-section rules, blend time and how far ahead the choice looks;
//! - [`level_deviations`]: how far each section's patch and clusters are from its strands [m],
//!   the estimate behind error-driven selection;
//! - [`criteria`]: the paper's tests as pure functions (occlusion rays against a box inside the
//!   head, projected skeleton length, motion measure, a level with hysteresis, the change of a
//!   section's errors over a look ahead);
//! - [`LodSelector`]: the per-frame choice for every section ([`SectionChoice`]) from what it sees of
//!   each ([`SectionObservation`]);
//! - [`hand_over`]: a section's skeleton state from one level to another (split and merge);
//! - [`StrandFollow`]: strand-group skeletons rebuilt on a coarser level's, to draw its strands;
//! - [`refine_within_budget`] with a [`CostModel`]: the frame budget that minimises the total
//!   estimated error (greedy refinement by error saved per unit cost, costs calibrated at run
//!   time);
//! - [`BudgetController`]: the other frame-budget mode, the pixel tolerance steered to meet a
//!   time budget per frame.

mod budget;
mod cost_model;
pub mod criteria;
mod deviation;
mod greedy;
mod observation;
mod occluders;
mod section_choice;
mod selector;
mod settings;
mod strand_follow;
mod transfer;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_hand_over;
#[cfg(test)]
mod tests_lead;
#[cfg(test)]
mod tests_strand_follow;

pub use budget::{BudgetController, BudgetMethod, BudgetReport, BudgetSettings};
pub use cost_model::{CostModel, CostRates, RenderSample, SectionWork};
pub use criteria::{
    distance_limits, error_ahead, foreseen_share, head_point_acceleration,
    head_point_acceleration_from_poses, is_occluded, is_section_occluded, level_with_hysteresis,
    motion_measure, projected_length, segment_hits_box,
};
pub use deviation::{
    DEVIATION_PERCENTILE, DRAWN_TUBE_RADIUS, LevelDeviation, PointGrid, level_deviations,
    level_deviations_at,
};
pub use greedy::{BudgetOutcome, SectionOptions, refine_within_budget};
pub use observation::{SIGHT_SAMPLES, SectionObservation};
pub use occluders::carried_boxes;
pub use section_choice::{Reason, SectionChoice, covered_pixels};
pub use selector::LodSelector;
pub use settings::{ErrorModel, LodSettings, OcclusionTest};
pub use strand_follow::{FollowScratch, StrandFollow};
pub use transfer::{SectionStateRef, hand_over};
#[cfg(test)]
mod tests_deviation;
