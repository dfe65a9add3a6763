//! [`PipelineState`]: everything of a run that evolves (each level's skeleton state, each
//! section's level, blend and visibility, the selector's memory, time and frame), apart from the
//! scene (the model) and the solvers' scratch. It is serializable: a run can be checkpointed and
//! resumed bit for bit ([`super::Checkpoint`]).

use hair_core::lod::SectionChoice;
use hair_core::{Level, PerLevel};
use serde::{Deserialize, Serialize};

use super::block::LevelBlock;
use super::levels::SectionLevels;

/// Everything of a [`Pipeline`](super::Pipeline) run that evolves from frame to frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PipelineState {
    /// Frames advanced so far.
    pub frame: usize,
    /// Simulated time [s].
    pub time: f64,
    /// Every section's level, blend and visibility fade.
    pub levels: SectionLevels,
    /// The last choice of every section (level, visibility, reason): the selector's hysteresis
    /// memory.
    pub choices: Vec<SectionChoice>,
    /// The selector's pixel tolerance [pixels] (a frame-budget controller moves it); `None` at a
    /// fixed level.
    pub pixel_tolerance: Option<f32>,
    /// Each section's depth [m] at the selector's last choice, what its look ahead compares the
    /// next frame with ([`LodSelector::depths`](hair_core::lod::LodSelector::depths)); empty at a
    /// fixed level or before the first choice (and in checkpoints written before it was kept:
    /// the first frame after resuming then does not look ahead).
    #[serde(default)]
    pub selector_depths: Vec<f32>,
    /// The skeletons simulated at each level.
    pub blocks: PerLevel<LevelBlock>,
}

impl PipelineState {
    /// Sections at each level now: patches, clusters, strand groups.
    pub fn sections_at(&self) -> [usize; 3] {
        Level::ALL.map(|level| {
            self.levels
                .current()
                .iter()
                .filter(|&&l| l == level)
                .count()
        })
    }

    /// Skeleton nodes simulated, over all levels.
    pub fn simulated_nodes(&self) -> usize {
        self.blocks.values().map(LevelBlock::node_count).sum()
    }
}
