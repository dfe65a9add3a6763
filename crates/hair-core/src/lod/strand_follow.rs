//! Strand groups drawn on a coarser level's skeletons ([`StrandFollow`]): a section simulated as
//! clusters or as a patch gets its five strand-group skeletons rebuilt every frame from its
//! simulated skeletons, so that its strands can be drawn (issue 52, "strands at every level").
//!
//! Each strand-group node keeps, in the node frames of the one or two source skeletons beside it
//! across the section (the bracket of §4.2's hand-over, by root offset), its offset from their
//! node at rest. A frame's skeletons are then the sources' nodes plus those offsets turned by the
//! sources' current node frames, blended by offset across the section as the hand-over blends
//! them, and given their rest lengths by follow-the-leader from each chain's own root where the
//! head or a deforming body carries it ([`ChainRoots`], as the hand-over puts its chains). At
//! rest this
//! gives the strand groups' own rest skeletons (to rounding), and the centre strand group, which
//! shares the centre source's root and rest shape, is that source exactly. It differs from the
//! hand-over ([`hand_over`](super::hand_over)) beyond the outermost source: the hand-over shifts
//! along each node's binormal, which on a curl changes the curl's radius; here the offsets follow
//! the rest shape, as guide-and-follower hair does (TressFX's follow hairs, Unreal's groom
//! interpolation).

use glam::Vec3;

use crate::dynamics::{ChainRoots, follow_the_leader};
use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::groom::Groom;
use crate::level::Level;
use crate::skeleton::node_frames;
use crate::transform::RigidTransform;

use super::transfer::section_nodes;

/// How one strand-group chain follows a coarser level: the source children (section-local) on
/// either side of it and the weight of the second, `t` in `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Bracket {
    left: usize,
    right: usize,
    t: f32,
}

/// How the strand groups follow one coarser level.
#[derive(Debug, Clone, Default, PartialEq)]
struct LevelFollow {
    /// One per strand-group chain (numbered from the level's first chain).
    brackets: Vec<Bracket>,
    /// One per strand-group node (numbered from the level's first node): its rest offset [m]
    /// from the left and from the right source's node, in that node's rest frame (normal,
    /// binormal, tangent components).
    offsets: Vec<[Vec3; 2]>,
}

/// The strand groups' rest offsets from each coarser level's skeletons, built once per groom
/// ([`StrandFollow::new`]); [`StrandFollow::rebuild`] places a section's strand groups on its
/// simulated skeletons.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StrandFollow {
    patch: LevelFollow,
    cluster: LevelFollow,
}

/// Scratch of [`StrandFollow::rebuild`]: the source skeletons' node frames, kept between calls
/// so that rebuilding allocates nothing once it has grown.
#[derive(Debug, Clone, Default)]
pub struct FollowScratch {
    frames: Vec<Frame>,
}

/// The components of `v` in `frame` (normal, binormal, tangent).
fn to_local(frame: &Frame, v: Vec3) -> Vec3 {
    Vec3::new(
        frame.normal.dot(v),
        frame.binormal.dot(v),
        frame.tangent.dot(v),
    )
}

/// The bracket of strand-group child `child` of a section among `sources` source children: the
/// source at the same offset (both sides it), the two it lies between, or the outermost one.
fn bracket(groom: &Groom, section: usize, child: usize, sources: usize) -> Bracket {
    let description = &groom.sections[section];
    let offset = description.child_offset(child, Level::StrandGroup.skeletons_per_section());
    let source_offset = |source: usize| description.child_offset(source, sources);
    let tolerance = 1e-6 * description.width.max(1e-6);
    if let Some(source) = (0..sources).find(|&s| (source_offset(s) - offset).abs() <= tolerance) {
        return Bracket {
            left: source,
            right: source,
            t: 0.0,
        };
    }
    match (0..sources.saturating_sub(1))
        .find(|&left| source_offset(left) <= offset && offset <= source_offset(left + 1))
    {
        Some(left) => Bracket {
            left,
            right: left + 1,
            t: (offset - source_offset(left)) / (source_offset(left + 1) - source_offset(left)),
        },
        None => {
            let nearest = if offset < source_offset(0) {
                0
            } else {
                sources - 1
            };
            Bracket {
                left: nearest,
                right: nearest,
                t: 0.0,
            }
        }
    }
}

/// Node `k` of a chain of `count` nodes starting at `start`, clamped to its tip (chains of a
/// section may differ in node count).
fn clamped(start: usize, count: usize, k: usize) -> usize {
    start + k.min(count - 1)
}

impl StrandFollow {
    /// The offsets of every strand-group node of `groom` from its patch and cluster skeletons at
    /// rest (head at the identity).
    pub fn new(groom: &Groom) -> StrandFollow {
        let skeletons = &groom.skeletons;
        let (positions, frames) = skeletons.rest_pose(&RigidTransform::IDENTITY);
        let strand_chains = groom.level_chains(Level::StrandGroup);
        let first_node = skeletons.nodes(strand_chains.start).start;
        let follow = |level: Level| -> LevelFollow {
            let mut brackets = Vec::with_capacity(strand_chains.len());
            let mut offsets = Vec::new();
            for chain in strand_chains.clone() {
                let (section, _, child) = groom.chain_owner(chain);
                let sources = groom.section_chains(section, level);
                let bracket = bracket(groom, section, child, sources.len());
                brackets.push(bracket);
                let target = skeletons.nodes(chain);
                debug_assert_eq!(target.start - first_node, offsets.len());
                let left = skeletons.nodes(sources.start + bracket.left);
                let right = skeletons.nodes(sources.start + bracket.right);
                for k in 0..target.len() {
                    let p = positions[target.start + k];
                    let offset_from = |range: &std::ops::Range<usize>| {
                        let node = clamped(range.start, range.len(), k);
                        to_local(&frames[node], p - positions[node])
                    };
                    offsets.push([offset_from(&left), offset_from(&right)]);
                }
            }
            LevelFollow { brackets, offsets }
        };
        StrandFollow {
            patch: follow(Level::Patch),
            cluster: follow(Level::Cluster),
        }
    }

    /// Writes into `out` the strand-group skeletons of section `section` (its five chains one
    /// after the other, chain-major) rebuilt from `from_positions` [m], its skeletons simulated
    /// at `from_level` (chain-major), with each chain's root where `roots` carries it (the head,
    /// or a deforming body and the head): copied at the strand-group level; from a coarser one,
    /// each node at its rest offset from its source nodes turned by their current node frames
    /// (rooted in their carried root frames), blended across the section, then put on its own
    /// carried root with its rest segment lengths. Reads the state and never writes it;
    /// allocates nothing once `scratch` has grown.
    /// Errors name a section out of range or a wrongly sized slice (for a follow of another
    /// groom).
    #[allow(clippy::too_many_arguments)]
    pub fn rebuild(
        &self,
        groom: &Groom,
        section: usize,
        from_level: Level,
        from_positions: &[Vec3],
        roots: &ChainRoots<'_>,
        out: &mut [Vec3],
        scratch: &mut FollowScratch,
    ) -> Result<()> {
        let skeletons = &groom.skeletons;
        let source_nodes = section_nodes(groom, section, from_level)?;
        let strand_nodes = section_nodes(groom, section, Level::StrandGroup)?;
        let sources = groom.section_chains(section, from_level);
        let targets = groom.section_chains(section, Level::StrandGroup);
        for (what, actual, expected) in [
            ("source positions", from_positions.len(), source_nodes),
            ("strand-group positions", out.len(), strand_nodes),
        ] {
            if actual != expected {
                return Err(HairError::SizeMismatch {
                    what,
                    actual,
                    expected,
                });
            }
        }
        let follow = match from_level {
            Level::StrandGroup => {
                out.copy_from_slice(from_positions);
                return Ok(());
            }
            Level::Cluster => &self.cluster,
            Level::Patch => &self.patch,
        };
        let strand_chains = groom.level_chains(Level::StrandGroup);
        let first_node = skeletons.nodes(strand_chains.start).start;
        if follow.brackets.len() != strand_chains.len()
            || follow.offsets.len() != skeletons.node_count() - first_node
        {
            return Err(HairError::SizeMismatch {
                what: "strand follow (built for another groom)",
                actual: follow.offsets.len(),
                expected: skeletons.node_count() - first_node,
            });
        }
        // The sources' node frames, section-local like `from_positions`.
        let frames = &mut scratch.frames;
        frames.clear();
        frames.resize(from_positions.len(), Frame::default());
        let mut source_starts = [0usize; 5];
        let mut start = 0;
        for (child, chain) in sources.clone().enumerate() {
            let count = skeletons.chain_node_count(chain);
            node_frames(
                &skeletons.world_root_frame(chain, &roots.pose(chain)),
                &from_positions[start..start + count],
                &mut frames[start..start + count],
            );
            source_starts[child.min(4)] = start;
            start += count;
        }
        let source_node = |child: usize, k: usize| {
            clamped(
                source_starts[child.min(4)],
                skeletons.chain_node_count(sources.start + child),
                k,
            )
        };
        let mut start = 0;
        for chain in targets {
            let bracket = follow.brackets[chain - strand_chains.start];
            let nodes = skeletons.nodes(chain);
            let positions = &mut out[start..start + nodes.len()];
            for (k, position) in positions.iter_mut().enumerate() {
                let [left_offset, right_offset] = follow.offsets[nodes.start - first_node + k];
                let (left, right) = (source_node(bracket.left, k), source_node(bracket.right, k));
                let from_left = from_positions[left] + frames[left].to_world(left_offset);
                *position = if bracket.right == bracket.left {
                    from_left
                } else {
                    let from_right = from_positions[right] + frames[right].to_world(right_offset);
                    from_left.lerp(from_right, bracket.t)
                };
            }
            positions[0] = roots
                .pose(chain)
                .transform_point(skeletons.root_positions[chain]);
            follow_the_leader(positions, &skeletons.segment_rest_lengths[nodes]);
            start += positions.len();
        }
        Ok(())
    }
}
