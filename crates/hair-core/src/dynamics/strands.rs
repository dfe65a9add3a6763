//! Skeleton models to simulate from a groom: the skeletons of one level on their own, or every
//! strand as a skeleton of its own (the finest simulation there is, for benchmarks and for
//! comparing levels of detail).

use glam::Vec3;

use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::groom::Groom;
use crate::level::Level;
use crate::skeleton::{SkeletonRest, measure_chain};
use crate::transform::RigidTransform;

/// The skeletons of `groom` at `level` alone, in the groom's order (chain `c` of the result is
/// chain `groom.level_chains(level).start + c` of the groom): `S`, `3S` or `5S` chains.
pub fn level_skeletons(groom: &Groom, level: Level) -> Result<SkeletonRest> {
    let mut rest = SkeletonRest::default();
    for chain in groom.level_chains(level) {
        rest.push_chain_from(&groom.skeletons, chain)?;
    }
    Ok(rest)
}

/// A [`SkeletonRest`] with one chain per strand of `groom`, strands in the groom's order (strand
/// group `g`'s strands `groom.strands.strands(g)` are chains of the same indices).
///
/// Strand `s` of group `g` has the rest shape of its control points: node `k` at
/// `p_k + x·n_k + y·b_k` [m], where `p_k` are the group skeleton's rest nodes (head at identity),
/// `(n_k, b_k)` its node frames' normal and binormal and `(x, y)` the strand's root offset
/// ([`StrandSet::root_offsets`](crate::StrandSet::root_offsets)). Its root frame is the group's
/// root frame (the same growth direction from a root moved by the offset); its lengths and rest
/// angles are measured from those nodes, so the chain rebuilds them exactly.
///
/// Fails with an error naming the strand when a strand's nodes are degenerate (two coincident
/// control points), or when the groom's strand groups and skeletons disagree.
pub fn strand_skeletons(groom: &Groom) -> Result<SkeletonRest> {
    let groups = groom.level_chains(Level::StrandGroup);
    if groom.strands.group_count() != groups.len() {
        return Err(HairError::SizeMismatch {
            what: "strand groups",
            actual: groom.strands.group_count(),
            expected: groups.len(),
        });
    }
    let skeletons = &groom.skeletons;
    let head = RigidTransform::IDENTITY;
    let mut rest = SkeletonRest::default();
    let mut group_positions = Vec::new();
    let mut group_frames = Vec::new();
    let mut strand_positions = Vec::new();
    for (group, chain) in groups.enumerate() {
        let nodes = skeletons.chain_node_count(chain);
        group_positions.resize(nodes, Vec3::ZERO);
        group_frames.resize(nodes, Frame::default());
        strand_positions.resize(nodes, Vec3::ZERO);
        skeletons.rest_positions_of(chain, &head, &mut group_positions);
        let root_frame = skeletons.world_root_frame(chain, &head);
        crate::skeleton::node_frames(&root_frame, &group_positions, &mut group_frames);
        for strand in groom.strands.strands(group) {
            let offset = groom.strands.root_offsets[strand];
            for ((target, node), frame) in strand_positions
                .iter_mut()
                .zip(&group_positions)
                .zip(&group_frames)
            {
                *target = *node + frame.normal * offset.x + frame.binormal * offset.y;
            }
            let angles = measure_chain(&root_frame, &strand_positions).map_err(|error| {
                HairError::invalid(
                    "strand",
                    format!("strand {strand} of strand group {group}: {error}"),
                    "control points that are pairwise distinct",
                )
            })?;
            rest.push_chain(strand_positions[0], root_frame, &angles)?;
        }
    }
    Ok(rest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::groom::GroomParams;
    use crate::head::{Head, HeadParams};

    #[test]
    fn strand_chains_rebuild_the_strand_control_points() {
        // Reference: control point k of strand s is node_k + x·normal_k + y·binormal_k (the
        // definition in StrandSet); the measured chain must rebuild it to f32 rounding along the
        // chain (≈ nodes × ε × length).
        let head = Head::procedural(&HeadParams::default()).unwrap();
        let params = GroomParams {
            section_count: 4,
            strands_per_group: 6,
            ..GroomParams::paper_curly()
        };
        let groom = Groom::generate(&params, &head).unwrap();
        let rest = strand_skeletons(&groom).unwrap();
        assert_eq!(rest.chain_count(), groom.strands.strand_count());
        let positions = rest.rest_positions(&RigidTransform::IDENTITY);
        let group_chain = groom.level_chains(Level::StrandGroup).start;
        let nodes = groom.skeletons.chain_node_count(group_chain);
        let mut group_positions = vec![Vec3::ZERO; nodes];
        let mut frames = vec![Frame::default(); nodes];
        groom.skeletons.rest_positions_of(
            group_chain,
            &RigidTransform::IDENTITY,
            &mut group_positions,
        );
        node_frames_of(&groom, group_chain, &group_positions, &mut frames);
        for strand in groom.strands.strands(0) {
            let offset = groom.strands.root_offsets[strand];
            for k in 0..nodes {
                let expected = group_positions[k]
                    + frames[k].normal * offset.x
                    + frames[k].binormal * offset.y;
                let actual = positions[rest.nodes(strand).start + k];
                assert!(
                    (actual - expected).length() < 1e-5,
                    "{actual} vs {expected}"
                );
            }
        }
    }

    fn node_frames_of(groom: &Groom, chain: usize, positions: &[Vec3], frames: &mut [Frame]) {
        let root = groom
            .skeletons
            .world_root_frame(chain, &RigidTransform::IDENTITY);
        crate::skeleton::node_frames(&root, positions, frames);
    }
}
