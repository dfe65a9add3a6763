//! What a fit produces: [`FittedHierarchy`], the sections with their skeletons at every level,
//! the strands' membership and root offsets, radii and widths, and the [`FitReport`].

use std::ops::Range;

use glam::{Vec2, Vec3};

use super::report::FitReport;
use crate::error::Result;
use crate::frame::Frame;
use crate::groom::StrandSet;
use crate::level::Level;
use crate::skeleton::{SkeletonRest, measure_chain};

/// The cluster (0, 1 or 2) each strand group (0..5) of a section belongs to: groups {0, 1},
/// {2} and {3, 4}. Every group nests in one cluster; the centre cluster *is* the centre group
/// (same strands, same skeleton), so §4.2's "the centre child inherits the parent exactly" holds
/// between the cluster and strand levels; the side clusters hold two neighbouring groups each.
pub const CLUSTER_OF_GROUP: [usize; 5] = [0, 0, 1, 2, 2];

/// One fitted section.
#[derive(Debug, Clone, PartialEq)]
pub struct FittedSection {
    /// Root of its patch skeleton [m]: the section's centre.
    pub root_position: Vec3,
    /// Root frame shared by its skeletons: tangent = the strands' mean growth direction,
    /// binormal = across the section (the direction its roots spread most, perpendicular to the
    /// tangent; strand groups 0..5 are laid along it), normal = binormal × tangent.
    pub root_frame: Frame,
    /// Extent of its strands' roots along the binormal [m].
    pub width: f32,
    /// Nodes of each of its skeletons.
    pub node_count: usize,
    /// Strands it holds.
    pub strand_count: usize,
}

/// A groom's curves fitted with the paper's hierarchy (§3): sections of 1 patch, 3 clusters and
/// 5 strand groups, each a skeleton.
///
/// Chains are numbered like [`Groom`](crate::Groom)'s: first the `S` patches, then the `3S`
/// clusters, then the `5S` strand groups, each level section-major, so section `s` owns chains
/// `s`, `S + 3s .. S + 3s + 3` and `4S + 5s .. 4S + 5s + 5`. Chain `c` owns nodes
/// `chain_offsets[c]..chain_offsets[c + 1]`, root first.
#[derive(Debug, Clone, PartialEq)]
pub struct FittedHierarchy {
    /// The sections, ordered by their lowest curve index.
    pub sections: Vec<FittedSection>,
    /// Node ranges of the chains: `9S + 1` entries starting at 0.
    pub chain_offsets: Vec<u32>,
    /// Skeleton nodes [m], chain-major, at equal arc-length steps along each representative curve.
    pub node_positions: Vec<Vec3>,
    /// Radius enclosing the chain's strands at each node [m], one per node: the largest distance
    /// of a member strand (at the same fraction of its length) from the node, across the node's
    /// tangent. A cluster's generalized cylinder with these radii holds its strands.
    pub node_radii: Vec<f32>,
    /// Width at each node [m], one per node: twice the largest distance of a member strand from
    /// the node along the node frame's binormal. A patch this wide, centred on its skeleton,
    /// spans its strands.
    pub node_widths: Vec<f32>,
    /// Strand ranges of the strand groups in `group_strands`: `5S + 1` entries starting at 0.
    pub group_offsets: Vec<u32>,
    /// Curve indices, group by group, each group in curve order.
    pub group_strands: Vec<u32>,
    /// Strand group (`0..5S`) of each curve, one per curve.
    pub strand_groups: Vec<u32>,
    /// Root offset of each curve from its strand group's skeleton root in the section's root
    /// frame's (normal, binormal) plane [m], one per curve, as
    /// [`StrandSet::root_offsets`](crate::StrandSet::root_offsets) holds them.
    pub root_offsets: Vec<Vec2>,
    /// Counts and errors.
    pub report: FitReport,
}

impl FittedHierarchy {
    /// Number of sections `S`.
    pub fn section_count(&self) -> usize {
        self.sections.len()
    }

    /// Number of chains (`9S`).
    pub fn chain_count(&self) -> usize {
        self.chain_offsets.len().saturating_sub(1)
    }

    /// The node range of chain `chain`.
    ///
    /// # Panics
    /// When `chain >= chain_count()`.
    pub fn nodes(&self, chain: usize) -> Range<usize> {
        self.chain_offsets[chain] as usize..self.chain_offsets[chain + 1] as usize
    }

    /// The node positions of chain `chain` [m].
    ///
    /// # Panics
    /// When `chain >= chain_count()`.
    pub fn chain_positions(&self, chain: usize) -> &[Vec3] {
        &self.node_positions[self.nodes(chain)]
    }

    /// The chains of every skeleton at `level`.
    pub fn level_chains(&self, level: Level) -> Range<usize> {
        level.chains(self.section_count())
    }

    /// The chains of section `section` at `level` (1, 3 or 5 consecutive chains).
    pub fn section_chains(&self, section: usize, level: Level) -> Range<usize> {
        level.section_chains(self.section_count(), section)
    }

    /// The curves of strand group `group` (`0..5S`).
    ///
    /// # Panics
    /// When `group >= 5S`.
    pub fn group_members(&self, group: usize) -> &[u32] {
        &self.group_strands
            [self.group_offsets[group] as usize..self.group_offsets[group + 1] as usize]
    }

    /// The section of curve `curve`.
    pub fn section_of(&self, curve: usize) -> usize {
        self.strand_groups[curve] as usize / 5
    }

    /// The cluster chain (`S..4S`) of strand group `group` (`0..5S`).
    pub fn cluster_of_group(&self, group: usize) -> usize {
        self.section_count() + 3 * (group / 5) + CLUSTER_OF_GROUP[group % 5]
    }

    /// The strands as a [`StrandSet`]: root offsets group by group, every shade 0.5, full length
    /// and parallel (the fitted strands' own shapes are in the skeletons).
    pub fn strand_set(&self) -> StrandSet {
        let root_offsets: Vec<Vec2> = self
            .group_strands
            .iter()
            .map(|&curve| self.root_offsets[curve as usize])
            .collect();
        StrandSet {
            group_offsets: self.group_offsets.clone(),
            shades: vec![0.5; root_offsets.len()],
            lengths: Vec::new(),
            tip_scales: Vec::new(),
            root_offsets,
            ..StrandSet::default()
        }
    }

    /// The skeletons as a [`SkeletonRest`] (same chain order): segment lengths and rest angles
    /// measured from the nodes ([`measure_chain`]) in each section's root frame, natural angles
    /// equal to the rest angles. An error names a chain whose nodes cannot be measured (two
    /// coinciding nodes).
    pub fn skeleton_rest(&self) -> Result<SkeletonRest> {
        let mut rest = SkeletonRest::default();
        for level in Level::ALL {
            for (s, section) in self.sections.iter().enumerate() {
                for chain in self.section_chains(s, level) {
                    let positions = self.chain_positions(chain);
                    let angles = measure_chain(&section.root_frame, positions)?;
                    rest.push_chain(positions[0], section.root_frame, &angles)?;
                }
            }
        }
        Ok(rest)
    }
}
