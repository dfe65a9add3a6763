//! The strands carried by strand-group skeletons: root offsets in the group's frame and shades.

use glam::Vec2;
use std::ops::Range;

/// All strands of a groom, flat: strand group `g` (numbered `0..5·sections`, section-major) owns
/// strands `group_offsets[g]..group_offsets[g + 1]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StrandSet {
    /// Strand ranges per strand group: `group_count + 1` entries starting at 0.
    pub group_offsets: Vec<u32>,
    /// Root offset of each strand from its group's skeleton, in the node frame's
    /// (normal, binormal) plane [m]. Control point `k` of the strand is
    /// `node_k + x · normal_k + y · binormal_k`.
    pub root_offsets: Vec<Vec2>,
    /// Shade of each strand within the hair colour range, `0..1`.
    pub shades: Vec<f32>,
}

impl StrandSet {
    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.root_offsets.len()
    }

    /// Number of strand groups.
    pub fn group_count(&self) -> usize {
        self.group_offsets.len().saturating_sub(1)
    }

    /// The strands of strand group `group`.
    pub fn strands(&self, group: usize) -> Range<usize> {
        self.group_offsets[group] as usize..self.group_offsets[group + 1] as usize
    }
}
