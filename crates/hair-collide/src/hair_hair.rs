//! Hair–hair repulsion (beyond the paper): segment volumes of different sections that overlap
//! push apart with a soft spring, so hair keeps its volume instead of passing through itself.
//!
//! For overlapping volumes `A`, `B` (signed separation `d < 0`, see
//! [`crate::SweptSphere::distance`]) the force on `A` is `m̄·(−d)/τ²·n`, with `n` the unit
//! direction from `B`'s core closest point to `A`'s (or between the volumes' box centres when the
//! cores cross), `m̄` the mean mass of the four nodes and `τ` the relaxation time; `B` gets the
//! opposite. Each is split half and half over the segment's two nodes, like the §5.4 response.
//! A spring scaled by the mass is soft by construction: alone it would close an overlap in about
//! `τ`, whatever the hair's density, and with `τ` much longer than a step (F_col is held over a
//! whole step) it cannot kick sections apart. Pairs of the same section are skipped: a section's own skeletons overlap by
//! construction (the cluster tubes of a section touch) and are held apart by their roots.
//!
//! Candidates come from the hair hierarchy against itself; each unordered pair is tested once, in
//! a deterministic order (the tree's), so forces do not depend on the thread count.

use glam::Vec3;

use crate::bvh::HairBvh;
use crate::error::{CollideError, Result};

/// Settings of the hair–hair repulsion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairHairSettings {
    /// Relaxation time `τ` \[s\], `> 0`: the spring's stiffness per unit mass is `1/τ²`. The
    /// default, 0.1 s, is six 60 Hz steps, so a pair's push grows smoothly; under gravity an
    /// overlap settles where `(−d)/τ² = g`, about 1 cm of mutual compression per pair.
    pub relaxation_time: f32,
}

impl Default for HairHairSettings {
    fn default() -> Self {
        HairHairSettings {
            relaxation_time: 0.1,
        }
    }
}

impl HairHairSettings {
    /// Checks the relaxation time.
    pub fn validate(&self) -> Result<()> {
        let tau = self.relaxation_time;
        if !(tau.is_finite() && tau > 0.0) {
            return Err(CollideError::InvalidParameter {
                name: "hair-hair relaxation_time",
                value: tau.to_string(),
                allowed: "a finite number > 0 s",
            });
        }
        Ok(())
    }
}

/// Adds the repulsion forces \[N\] between overlapping segment volumes of different sections to
/// `forces` (one per node of the hierarchy's own node numbering, i.e. `chain_offsets` of
/// [`HairBvh::chain_offsets`]); `chain_sections` gives each chain's section and `node_masses`
/// each node's mass \[kg\] (same numbering as `forces`). Returns the number of overlapping
/// pairs. Errors when the sizes do not match the hierarchy.
pub fn add_repulsion_forces(
    hair: &HairBvh,
    chain_sections: &[u32],
    node_masses: &[f32],
    settings: &HairHairSettings,
    forces: &mut [Vec3],
) -> Result<usize> {
    settings.validate()?;
    if chain_sections.len() != hair.chain_count() {
        return Err(CollideError::SizeMismatch {
            what: "chain_sections",
            actual: chain_sections.len(),
            expected: hair.chain_count(),
        });
    }
    let node_count = *hair.chain_offsets().last().unwrap_or(&0) as usize;
    for (what, actual) in [("forces", forces.len()), ("node_masses", node_masses.len())] {
        if actual != node_count {
            return Err(CollideError::SizeMismatch {
                what,
                actual,
                expected: node_count,
            });
        }
    }
    let rate = 1.0 / (settings.relaxation_time * settings.relaxation_time);
    let volumes = hair.volumes();
    let chains = hair.segment_chains();
    let tops = hair.segment_top_nodes();
    let mut overlaps = 0;
    let tree = hair.bvh();
    for (first, second) in tree.leaf_pairs(tree, |a, b| a.intersects(b)) {
        // Each unordered pair once; never a segment with itself.
        if first >= second {
            continue;
        }
        let (a, b) = (first as usize, second as usize);
        if chain_sections[chains[a] as usize] == chain_sections[chains[b] as usize] {
            continue;
        }
        let (va, vb) = (&volumes[a], &volumes[b]);
        let (on_a, on_b, core_distance) = va.core_closest_points(vb);
        let overlap = va.radius() + vb.radius() - core_distance;
        if overlap <= 0.0 {
            continue;
        }
        let mut direction = (on_a - on_b).normalize_or_zero();
        if direction == Vec3::ZERO {
            let centre = |v: &crate::SweptSphere| v.aabb(0.0).center();
            direction = (centre(va) - centre(vb)).normalize_or_zero();
        }
        if direction == Vec3::ZERO {
            continue;
        }
        overlaps += 1;
        let (ta, tb) = (tops[a] as usize, tops[b] as usize);
        let mean_mass =
            0.25 * (node_masses[ta] + node_masses[ta + 1] + node_masses[tb] + node_masses[tb + 1]);
        let half = direction * (0.5 * mean_mass * rate * overlap);
        forces[ta] += half;
        forces[ta + 1] += half;
        forces[tb] -= half;
        forces[tb + 1] -= half;
    }
    Ok(overlaps)
}
