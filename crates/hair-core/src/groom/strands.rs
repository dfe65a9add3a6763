//! The strands carried by strand-group skeletons: root offsets in the group's frame, shades,
//! lengths, tip scales and residual profiles.

use glam::{Vec2, Vec3};
use std::ops::Range;

use crate::error::{HairError, Result};

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

/// Checks residual profiles for `strands` strands (one definition for the CPU polylines and the
/// renderer's upload): `profile_of` empty or one entry per strand, each [`NO_PROFILE`] or the
/// index of a whole profile in `profiles` (a multiple of [`PROFILE_SAMPLES`] entries, all
/// finite). Errors name the strand or the entry.
pub fn check_profiles(profile_of: &[u32], profiles: &[Vec3], strands: usize) -> Result<()> {
    if profiles.len() % PROFILE_SAMPLES != 0 {
        return Err(HairError::invalid(
            "residual profile entries",
            profiles.len(),
            "a multiple of PROFILE_SAMPLES (64)",
        ));
    }
    if let Some(entry) = profiles.iter().position(|r| !r.is_finite()) {
        return Err(HairError::invalid(
            "residual profile entry",
            format!("{entry}: {}", profiles[entry]),
            "finite",
        ));
    }
    if profile_of.is_empty() {
        return Ok(());
    }
    if profile_of.len() != strands {
        return Err(HairError::SizeMismatch {
            what: "strand profile indices",
            actual: profile_of.len(),
            expected: strands,
        });
    }
    let count = profiles.len() / PROFILE_SAMPLES;
    if let Some(strand) = profile_of
        .iter()
        .position(|&p| p != NO_PROFILE && p as usize >= count)
    {
        return Err(HairError::invalid(
            "strand profile index",
            format!("{} of strand {strand}", profile_of[strand]),
            "NO_PROFILE or below the number of profiles",
        ));
    }
    Ok(())
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

    /// Checks the residual profiles ([`check_profiles`] on this set's). Errors name the strand
    /// or the entry.
    pub fn check_profiles(&self) -> Result<()> {
        check_profiles(&self.profile_of, &self.profiles, self.strand_count())
    }

    /// The strands of strand group `group`.
    pub fn strands(&self, group: usize) -> Range<usize> {
        self.group_offsets[group] as usize..self.group_offsets[group + 1] as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_strands() -> StrandSet {
        StrandSet {
            group_offsets: vec![0, 2],
            root_offsets: vec![Vec2::ZERO; 2],
            shades: vec![0.5; 2],
            profile_of: vec![0, NO_PROFILE],
            profiles: vec![Vec3::ZERO; PROFILE_SAMPLES],
            ..StrandSet::default()
        }
    }

    #[test]
    fn profiles_are_checked_and_bad_ones_named() {
        assert!(two_strands().check_profiles().is_ok());
        assert!(StrandSet::default().check_profiles().is_ok());
        type Spoil = fn(&mut StrandSet);
        let cases: [(Spoil, &str); 4] = [
            (|s| s.profile_of.push(0), "strand profile indices"),
            (|s| s.profiles.truncate(PROFILE_SAMPLES - 1), "multiple of"),
            (|s| s.profiles[3].y = f32::NAN, "entry"),
            (|s| s.profile_of[1] = 1, "of strand 1"),
        ];
        for (spoil, expected) in cases {
            let mut strands = two_strands();
            spoil(&mut strands);
            let error = strands.check_profiles().unwrap_err().to_string();
            assert!(error.contains(expected), "{error} lacks {expected}");
        }
    }
}
