//! Per-strand shape beyond the root offset: how far along its skeleton a strand runs, how much
//! it gathers towards it on the way to the tip, and its residual profile (uploaded once, with the
//! strands).

use glam::Vec3;
use hair_core::NO_PROFILE;

use crate::error::{Result, invalid};

/// Optional per-strand shape data, in the order of the [`crate::StrandSet`] it goes with. Empty
/// slices mean every strand at 1 (full length, parallel to its skeleton).
///
/// A strand with length `l` and tip scale `s` at root offset `o` is drawn from `u = 0` to
/// `u = l` (rounded to the chain's tessellation) along `C(u) + σ(u)·(o.x·N(u) + o.y·B(u))`,
/// `σ(u) = 1 + (s − 1)·u`, where `C`, `N`, `B` are the B-splines of its chain's nodes, normals
/// and binormals, plus its residual profile `r(u / l)` in the orthonormal frame `(N̂, B̂, T̂)` where it has one
/// (`hair_core::representation::drawn` gives the whole definition).
#[derive(Debug, Clone, Copy, Default)]
pub struct StrandShapes<'a> {
    /// Length of each strand as a fraction of its chain's, in `(0, 1]`.
    pub strand_lengths: &'a [f32],
    /// Scale of each strand's offset at the tip, in `0..=1`.
    pub strand_tip_scales: &'a [f32],
    /// Residual profile of each strand, in profiles (`PROFILE_SAMPLES` entries each) into
    /// `profiles`, or `hair_core::NO_PROFILE` (see [`hair_core::StrandSet::profile_of`]).
    pub strand_profiles: &'a [u32],
    /// The residual profiles [m], [`hair_core::PROFILE_SAMPLES`] entries each (see
    /// [`hair_core::StrandSet::profiles`]).
    pub profiles: &'a [Vec3],
}

impl StrandShapes<'_> {
    /// Checks that each array is empty or has `strands` values in range.
    pub fn validate(&self, strands: usize) -> Result<()> {
        for (name, values, low_open) in [
            ("length", self.strand_lengths, true),
            ("tip scale", self.strand_tip_scales, false),
        ] {
            if !values.is_empty() && values.len() != strands {
                return Err(invalid(format!(
                    "{} strand {name}s for {strands} strands (give one per strand, or none)",
                    values.len()
                )));
            }
            let in_range = |v: f32| v <= 1.0 && if low_open { v > 0.0 } else { v >= 0.0 };
            if let Some(strand) = values.iter().position(|&v| !in_range(v)) {
                let range = if low_open { "(0, 1]" } else { "0..=1" };
                return Err(invalid(format!(
                    "strand {strand} has {name} {}, expected a value in {range}",
                    values[strand]
                )));
            }
        }
        hair_core::groom::check_profiles(self.strand_profiles, self.profiles, strands)
            .map_err(|error| invalid(error.to_string()))?;
        Ok(())
    }

    /// Residual profile of strand `strand` (`NO_PROFILE` when none is given).
    pub fn profile(&self, strand: usize) -> u32 {
        self.strand_profiles
            .get(strand)
            .copied()
            .unwrap_or(NO_PROFILE)
    }

    /// Length of strand `strand` (1 when none is given).
    pub fn length(&self, strand: usize) -> f32 {
        self.strand_lengths.get(strand).copied().unwrap_or(1.0)
    }

    /// Tip scale of strand `strand` (1 when none is given).
    pub fn tip_scale(&self, strand: usize) -> f32 {
        self.strand_tip_scales.get(strand).copied().unwrap_or(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hair_core::PROFILE_SAMPLES;

    #[test]
    fn shapes_are_validated() {
        assert!(StrandShapes::default().validate(3).is_ok());
        let good = StrandShapes {
            strand_lengths: &[1.0, 0.5],
            strand_tip_scales: &[0.0, 1.0],
            ..StrandShapes::default()
        };
        assert!(good.validate(2).is_ok());
        assert!(good.validate(3).unwrap_err().to_string().contains("length"));
        let zero_length = StrandShapes {
            strand_lengths: &[0.0],
            ..StrandShapes::default()
        };
        assert!(zero_length.validate(1).is_err());
        let big_tip = StrandShapes {
            strand_tip_scales: &[1.5],
            ..StrandShapes::default()
        };
        assert!(big_tip.validate(1).unwrap_err().to_string().contains("tip"));
        let entries = vec![Vec3::ZERO; PROFILE_SAMPLES];
        let profiled = StrandShapes {
            strand_profiles: &[0, NO_PROFILE],
            profiles: &entries,
            ..StrandShapes::default()
        };
        assert!(profiled.validate(2).is_ok());
        assert_eq!(profiled.profile(1), NO_PROFILE);
        let past_the_end = StrandShapes {
            strand_profiles: &[1],
            profiles: &entries,
            ..StrandShapes::default()
        };
        assert!(
            past_the_end
                .validate(1)
                .unwrap_err()
                .to_string()
                .contains("profile index: 1 of strand 0")
        );
        let ragged = StrandShapes {
            profiles: &entries[1..],
            ..StrandShapes::default()
        };
        assert!(
            ragged
                .validate(0)
                .unwrap_err()
                .to_string()
                .contains("multiple")
        );
        let mut bad = entries.clone();
        bad[3].y = f32::NAN;
        let nan = StrandShapes {
            profiles: &bad,
            ..StrandShapes::default()
        };
        let error = nan.validate(0).unwrap_err().to_string();
        assert!(error.contains("entry") && error.contains("3: "), "{error}");
    }
}
