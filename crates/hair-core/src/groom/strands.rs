//! The strands carried by strand-group skeletons: root offsets in the group's frame, shades,
//! lengths, tip scales and residual profiles.

use glam::{Vec2, Vec3};
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
    /// Length of each strand as a fraction of its skeleton's, `(0, 1]`: the strand runs from the
    /// root to curve parameter `u = length` (empty: every strand runs the whole skeleton).
    pub lengths: Vec<f32>,
    /// Scale of each strand's offset from its skeleton at the tip, `0..=1`: the offset shrinks
    /// linearly in the curve parameter from 1 at the root to this at `u = 1`, so strands gather
    /// towards their skeleton (clump) on the way to the tip (empty: every strand at 1, parallel).
    pub tip_scales: Vec<f32>,
    /// Residual profile of each strand: an index into [`StrandSet::profiles`] in units of
    /// [`PROFILE_SAMPLES`] entries, or [`NO_PROFILE`] (empty: no strand has one). Several strands
    /// may share a profile (a guide's children follow its shape).
    pub profile_of: Vec<u32>,
    /// Residual profiles, [`PROFILE_SAMPLES`] entries each: entry `j` is the strand's offset [m]
    /// from its model (skeleton curve plus the tapered root offset) at fraction
    /// `v = j / (PROFILE_SAMPLES − 1)` of its run, in the orthonormal frame `(N̂, B̂, T̂)` of its
    /// skeleton's curve at `u = v · length`
    /// ([`ChainPoint::residual_basis`](crate::representation::drawn::ChainPoint::residual_basis));
    /// linear between entries. This is how a loaded groom's strands keep their own shapes: they are bound as
    /// offsets in the skeleton's node frames, so they move with it.
    pub profiles: Vec<Vec3>,
}

/// Entries per residual profile ([`StrandSet::profiles`]).
pub const PROFILE_SAMPLES: usize = 64;

/// [`StrandSet::profile_of`] of a strand without a residual profile.
pub const NO_PROFILE: u32 = u32::MAX;

impl StrandSet {
    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.root_offsets.len()
    }

    /// Number of strand groups.
    pub fn group_count(&self) -> usize {
        self.group_offsets.len().saturating_sub(1)
    }

    /// Length of strand `strand` as a fraction of its skeleton's (1 when none is given).
    pub fn length(&self, strand: usize) -> f32 {
        self.lengths.get(strand).copied().unwrap_or(1.0)
    }

    /// Tip scale of strand `strand`'s offset (1 when none is given).
    pub fn tip_scale(&self, strand: usize) -> f32 {
        self.tip_scales.get(strand).copied().unwrap_or(1.0)
    }

    /// The residual profile of strand `strand` ([`PROFILE_SAMPLES`] entries), if it has one.
    pub fn profile(&self, strand: usize) -> Option<&[Vec3]> {
        let index = *self.profile_of.get(strand)?;
        if index == NO_PROFILE {
            return None;
        }
        let start = index as usize * PROFILE_SAMPLES;
        self.profiles.get(start..start + PROFILE_SAMPLES)
    }

    /// The strands of strand group `group`.
    pub fn strands(&self, group: usize) -> Range<usize> {
        self.group_offsets[group] as usize..self.group_offsets[group + 1] as usize
    }
}
