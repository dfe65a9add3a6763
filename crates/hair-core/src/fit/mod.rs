//! The paper's hierarchy fitted to any groom's curves (§3): strands ([`Curves`](crate::curves::Curves),
//! from any file reader of the `hair-formats` crate) grouped into sections of 5 strand groups,
//! 3 clusters and 1 patch, each element with a skeleton that stands for its strands, and every level's error against them.
//!
//! Pure functions, deterministic whatever the thread count:
//! - [`resample_curve`], [`curve_length`], [`total_turning`], [`node_count_for`]: curves by arc
//!   length and the smoothness rule for node counts ([`Smoothness`]);
//! - [`fit_hierarchy`]: curves and [`FitSettings`] in, a [`FittedHierarchy`] with its
//!   [`FitReport`] out.
//!
//! The fit measures itself ("fitting is measurable", DESIGN.md): each strand is compared, at
//! equal fractions of its length, with the skeleton of its patch, cluster and strand group, drawn
//! as that skeleton plus the strand's root offset in the node frames (the model's strands), and
//! also with a free offset per node and with no offset ([`LevelErrors`]).

mod build;
mod element;
mod hierarchy;
mod kmeans;
mod partition;
mod pca;
mod profiles;
mod report;
mod resample;
mod settings;
mod structure;

#[cfg(test)]
mod tests;

pub use build::fit_hierarchy;
pub use hierarchy::{CLUSTER_OF_GROUP, FittedHierarchy, FittedSection};
pub use profiles::bind_profiles;
pub use report::{ErrorStats, FitReport, LevelErrors};
pub use resample::{curve_length, node_count_for, resample_curve, resample_into, total_turning};
pub use settings::{
    FitSettings, GroupSplit, NodeCountScope, Representative, SectionCount, Smoothness,
};
pub use structure::StructureError;
