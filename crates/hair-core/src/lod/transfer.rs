//! Handing skeleton state between levels (§4.2): when a section splits, the centre child inherits
//! the parent exactly and the others are interpolated from the parents by their roots' positions
//! across the section; when it merges, each parent takes the state of the child at its position
//! (the centre parent: the centre child, exactly) or interpolates between its neighbours.

use glam::Vec3;

use crate::dynamics::{ChainRoots, follow_the_leader};
use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::groom::Groom;
use crate::level::Level;
use crate::skeleton::node_frames;

/// Node positions [m] and velocities [m/s] of one section's skeletons at one level: its 1, 3 or 5
/// chains one after the other, each with the groom's node count for that chain.
#[derive(Debug, Clone, Copy)]
pub struct SectionStateRef<'a> {
    /// Positions [m], chain-major.
    pub positions: &'a [Vec3],
    /// Velocities [m/s], chain-major.
    pub velocities: &'a [Vec3],
}

/// Writes into `to_positions` / `to_velocities` the state of section `section` at level `to`
/// handed over from its state `from` at level `from_level`, with the roots where `roots` puts
/// them (on the posed head, or carried by a deforming body, chain by chain).
///
/// Target chain `j` sits at offset `u_j` across the section ([`Section::child_offset`]
/// (crate::Section::child_offset)). A source chain at the same offset is copied exactly (the
/// centre child of a split, the centre parent of a merge). A target between two source chains
/// gets, node by node, the linear interpolation of their positions and velocities by offset. A
/// target beyond the outermost source is that source moved by `u_j − u_source` along its node
/// frames' binormals (the direction across the section), with its velocities. Interpolated chains
/// are then put on their own root (`roots` places it) and given their rest segment lengths by a
/// follow-the-leader pass; exact copies are left untouched.
///
/// Allocates a little scratch (transitions are rare, unlike steps).
#[allow(clippy::too_many_arguments)]
pub fn hand_over(
    groom: &Groom,
    section: usize,
    from_level: Level,
    from: SectionStateRef<'_>,
    to: Level,
    to_positions: &mut [Vec3],
    to_velocities: &mut [Vec3],
    roots: &ChainRoots<'_>,
) -> Result<()> {
    let skeletons = &groom.skeletons;
    let source_nodes = section_nodes(groom, section, from_level)?;
    let target_nodes = section_nodes(groom, section, to)?;
    let source_chains = groom.section_chains(section, from_level);
    let target_chains = groom.section_chains(section, to);
    for (what, actual, expected) in [
        ("source positions", from.positions.len(), source_nodes),
        ("source velocities", from.velocities.len(), source_nodes),
        ("target positions", to_positions.len(), target_nodes),
        ("target velocities", to_velocities.len(), target_nodes),
    ] {
        if actual != expected {
            return Err(HairError::SizeMismatch {
                what,
                actual,
                expected,
            });
        }
    }
    let description = &groom.sections[section];
    let source_count = source_chains.len();
    let target_count = target_chains.len();
    let source_offsets: Vec<f32> = (0..source_count)
        .map(|child| description.child_offset(child, source_count))
        .collect();
    // Node ranges of each chain inside the section-local arrays.
    let local_ranges = |chains: std::ops::Range<usize>| -> Vec<std::ops::Range<usize>> {
        let mut start = 0;
        chains
            .map(|chain| {
                let count = skeletons.chain_node_count(chain);
                start += count;
                start - count..start
            })
            .collect()
    };
    let source_ranges = local_ranges(source_chains.clone());
    let target_ranges = local_ranges(target_chains.clone());
    let same_shape = |a: usize, b: usize| source_ranges[a].len() == target_ranges[b].len();
    let tolerance = 1e-6 * description.width.max(1e-6);
    let mut frames = Vec::new();
    for (target, target_chain) in target_chains.enumerate() {
        let offset = description.child_offset(target, target_count);
        let range = target_ranges[target].clone();
        let positions = &mut to_positions[range.clone()];
        let velocities = &mut to_velocities[range];
        // Exact copy where a source sits at the same place.
        if let Some(source) = source_offsets
            .iter()
            .position(|&u| (u - offset).abs() <= tolerance)
            .filter(|&source| same_shape(source, target))
        {
            positions.copy_from_slice(&from.positions[source_ranges[source].clone()]);
            velocities.copy_from_slice(&from.velocities[source_ranges[source].clone()]);
            continue;
        }
        let bracket = source_offsets
            .windows(2)
            .position(|pair| pair[0] <= offset && offset <= pair[1]);
        match bracket {
            Some(left) => {
                let right = left + 1;
                let t = (offset - source_offsets[left])
                    / (source_offsets[right] - source_offsets[left]);
                let (a, b) = (source_ranges[left].clone(), source_ranges[right].clone());
                for k in 0..positions.len() {
                    let (ka, kb) = (a.start + k.min(a.len() - 1), b.start + k.min(b.len() - 1));
                    positions[k] = from.positions[ka].lerp(from.positions[kb], t);
                    velocities[k] = from.velocities[ka].lerp(from.velocities[kb], t);
                }
            }
            None => {
                let nearest = if offset < source_offsets[0] {
                    0
                } else {
                    source_count - 1
                };
                let source_range = source_ranges[nearest].clone();
                let source_positions = &from.positions[source_range.clone()];
                frames.clear();
                frames.resize(source_positions.len(), Frame::default());
                let source_chain = groom.section_chains(section, from_level).start + nearest;
                let root_frame =
                    skeletons.world_root_frame(source_chain, &roots.pose(source_chain));
                node_frames(&root_frame, source_positions, &mut frames);
                let shift = offset - source_offsets[nearest];
                for k in 0..positions.len() {
                    let ks = k.min(source_positions.len() - 1);
                    positions[k] = source_positions[ks] + frames[ks].binormal * shift;
                    velocities[k] = from.velocities[source_range.start + ks];
                }
            }
        }
        positions[0] = roots
            .pose(target_chain)
            .transform_point(skeletons.root_positions[target_chain]);
        follow_the_leader(
            positions,
            &skeletons.segment_rest_lengths[skeletons.nodes(target_chain)],
        );
    }
    Ok(())
}

/// The node count of section `section`'s skeletons at `level` (its chains one after the other);
/// an error names a section that is not one of `groom`'s.
pub(super) fn section_nodes(groom: &Groom, section: usize, level: Level) -> Result<usize> {
    if section >= groom.section_count() {
        return Err(HairError::invalid(
            "section index",
            section,
            "less than the groom's section count",
        ));
    }
    Ok(groom
        .section_chains(section, level)
        .map(|chain| groom.skeletons.chain_node_count(chain))
        .sum())
}
