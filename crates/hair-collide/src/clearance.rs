//! Clearances: per node and body, a lower bound on the distance to the body's surface that lets
//! the positional projection skip the closest-point search while a node stays near where it was
//! measured; and carrying them over when the active chains change.

use std::collections::HashMap;

use glam::Vec3;

use crate::layout::{ChainShape, CollisionChain};
use crate::surface::SurfacePoint;

/// A lower bound on a node's distance to a body, valid at a position in head space: while the
/// node stays within `clearance` of `local_position` it cannot have crossed the surface (the
/// distance to a surface is 1-Lipschitz, and head space moves with the bodies). The default
/// (zero clearance) certifies nothing. `triangle` is the body's triangle found closest when it
/// was measured: the next search starts from it. `inside` is what a search found where the node
/// was inside (the position searched, world, and the closest surface point): the projection of
/// that very position takes it instead of searching again.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Clearance {
    pub local_position: Vec3,
    pub clearance: f32,
    pub triangle: u32,
    pub inside: Option<(Vec3, SurfacePoint)>,
}

/// Rounding allowance \[m\] of the clearance test (the head transform's f32 rounding at 1 m).
pub(crate) const CLEARANCE_ROUNDING: f32 = 1.0e-6;

/// Which of a section's chains this is: its section, level and rank among the section's chains
/// of that level, in order. The same chain keeps its key when the dynamics model is rebuilt
/// around it (a section elsewhere changed level), while its model index changes.
fn chain_keys(chains: &[CollisionChain]) -> Vec<(u32, u8, u32)> {
    let mut seen: HashMap<(u32, u8), u32> = HashMap::new();
    chains
        .iter()
        .map(|chain| {
            let level = match chain.shape {
                ChainShape::Patch { .. } => 0,
                ChainShape::Cluster { .. } => 1,
                ChainShape::StrandGroup { .. } => 2,
            };
            let rank = seen.entry((chain.section, level)).or_insert(0);
            let key = (chain.section, level, *rank);
            *rank += 1;
            key
        })
        .collect()
}

/// The clearances of a new layout `(chains, chain_offsets)` (`bodies` per node, node-major):
/// those of the chains that were already active (same key, same node count) are carried over
/// from `old`, the others start at zero. A clearance is a statement about a region of space, so
/// even a mismatched carry-over stays correct; it only saves the closest-point searches that a
/// level change elsewhere would otherwise cost every node of the block.
pub(crate) fn carry_clearances(
    (old_chains, old_offsets, old): (&[CollisionChain], &[u32], &[Clearance]),
    (chains, chain_offsets): (&[CollisionChain], &[u32]),
    bodies: usize,
) -> Vec<Clearance> {
    let node_count = chain_offsets.last().copied().unwrap_or(0) as usize;
    let mut carried = vec![Clearance::default(); node_count * bodies];
    let old_index: HashMap<(u32, u8, u32), usize> = chain_keys(old_chains)
        .into_iter()
        .enumerate()
        .map(|(index, key)| (key, index))
        .collect();
    for (index, key) in chain_keys(chains).into_iter().enumerate() {
        let Some(&old_chain) = old_index.get(&key) else {
            continue;
        };
        let (Some(from), Some(to)) = (
            old_offsets.get(old_chain..old_chain + 2),
            chain_offsets.get(index..index + 2),
        ) else {
            continue;
        };
        let (from, to) = (
            from[0] as usize * bodies..from[1] as usize * bodies,
            to[0] as usize * bodies..to[1] as usize * bodies,
        );
        if from.len() == to.len() && from.end <= old.len() {
            carried[to].copy_from_slice(&old[from]);
        }
    }
    carried
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(chain: u32, section: u32, shape: ChainShape) -> CollisionChain {
        CollisionChain {
            chain,
            section,
            shape,
        }
    }

    fn at(x: f32) -> Clearance {
        Clearance {
            local_position: Vec3::new(x, 0.0, 0.0),
            clearance: 0.01,
            triangle: 0,
            inside: None,
        }
    }

    /// Section 1's two clusters stay (renumbered in the model), section 2 arrives as a patch,
    /// section 0's strand group leaves: the clusters keep their clearances, the patch starts at
    /// zero; two bodies per node.
    #[test]
    fn chains_that_stay_keep_their_clearances() {
        let cluster = ChainShape::Cluster {
            root_radius: 0.005,
            tip_radius: 0.002,
        };
        let old_chains = [
            chain(0, 0, ChainShape::StrandGroup { thickness: 0.001 }),
            chain(1, 1, cluster),
            chain(2, 1, cluster),
        ];
        let old_offsets = [0, 2, 4, 6];
        let old: Vec<Clearance> = (0..12).map(|i| at(i as f32)).collect();
        let chains = [
            chain(0, 1, cluster),
            chain(1, 1, cluster),
            chain(2, 2, ChainShape::Patch { width: 0.02 }),
        ];
        let offsets = [0, 2, 4, 6];
        let carried = carry_clearances((&old_chains, &old_offsets, &old), (&chains, &offsets), 2);
        assert_eq!(carried.len(), 12);
        assert_eq!(carried[..8], old[4..12]);
        assert!(carried[8..].iter().all(|c| *c == Clearance::default()));
        // A chain whose node count changed starts at zero.
        let carried = carry_clearances(
            (&old_chains, &old_offsets, &old),
            (&chains[..1], &[0, 3]),
            2,
        );
        assert!(carried.iter().all(|c| *c == Clearance::default()));
    }
}
