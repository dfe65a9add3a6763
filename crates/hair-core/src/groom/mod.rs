//! Grooms: the sections of a head with their skeletons at every level, strands, radii and widths.
//!
//! Chains are stored level-major in one [`SkeletonRest`]: first the `S` patch skeletons (one per
//! section), then the `3S` cluster skeletons, then the `5S` strand-group skeletons, each level
//! section-major, so section `s` owns chains `s`, `S + 3s .. S + 3s + 3` and `4S + 5s .. 4S + 5s + 5`.

mod build;
mod fitted;
mod params;
mod placement;
mod section;
mod strands;

use std::ops::Range;

use serde::{Deserialize, Serialize};

pub use fitted::ChildStrands;
pub use params::{GroomParams, GroomPreset, PRESET_NAMES};
pub use section::Section;
pub use strands::{NO_PROFILE, PROFILE_SAMPLES, StrandSet, check_profiles};

use crate::level::Level;
use crate::skeleton::SkeletonRest;

/// A groom: the static model of a head of hair (rest shapes, roots, strands, sizes).
#[derive(Debug, Clone, PartialEq)]
pub struct Groom {
    /// The parameters it was generated from.
    pub params: GroomParams,
    /// The sections, ordered crown to nape.
    pub sections: Vec<Section>,
    /// Every skeleton of every level (see the module docs for the chain order).
    pub skeletons: SkeletonRest,
    /// The strands carried by the strand-group skeletons.
    pub strands: StrandSet,
    /// Root radius of each cluster's control circle [m], one per cluster (`3S`).
    pub cluster_root_radii: Vec<f32>,
    /// Tip radius of each cluster's control circle [m], one per cluster (`3S`).
    pub cluster_tip_radii: Vec<f32>,
    /// Width of each patch [m], one per patch (`S`).
    pub patch_widths: Vec<f32>,
    /// Radius of each strand group (the farthest strand root from its skeleton) [m], one per group
    /// (`5S`): the thickness of the group's swept-sphere volumes.
    pub strand_group_radii: Vec<f32>,
    /// Children grown around each guide strand ([`Groom::from_fit_with_children`]): in each
    /// strand group, every guide (a file's own strand) is followed by this many children, so
    /// strand `s` is a guide where `s % (1 + children_per_guide) == 0` ([`Groom::is_guide`]).
    /// 0 where every strand is its own (a generated groom, a file read without children).
    pub children_per_guide: usize,
}

/// How big a groom is, level by level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct GroomCounts {
    /// Sections.
    pub sections: usize,
    /// Patches (one per section).
    pub patches: usize,
    /// Clusters (three per section).
    pub clusters: usize,
    /// Strand groups (five per section).
    pub strand_groups: usize,
    /// Strands over all strand groups.
    pub strands: usize,
    /// Nodes of one skeleton (every skeleton of a groom has the same count).
    pub nodes_per_skeleton: usize,
    /// Skeleton nodes of all patches.
    pub patch_nodes: usize,
    /// Skeleton nodes of all clusters.
    pub cluster_nodes: usize,
    /// Skeleton nodes of all strand groups.
    pub strand_group_nodes: usize,
    /// Skeleton nodes over every level.
    pub skeleton_nodes: usize,
    /// NURBS control points of all strands (strands × nodes per skeleton).
    pub strand_control_points: usize,
}

impl Groom {
    /// Whether strand `strand` is a guide (a strand of its own, not a grown child:
    /// [`Groom::children_per_guide`]).
    pub fn is_guide(&self, strand: usize) -> bool {
        strand % (1 + self.children_per_guide) == 0
    }

    /// Number of guide strands ([`Groom::is_guide`]).
    pub fn guide_count(&self) -> usize {
        self.strands
            .strand_count()
            .div_ceil(1 + self.children_per_guide)
    }

    /// Number of sections `S`.
    pub fn section_count(&self) -> usize {
        self.sections.len()
    }

    /// The chains of every skeleton at `level`.
    pub fn level_chains(&self, level: Level) -> Range<usize> {
        level.chains(self.section_count())
    }

    /// The chains of section `section` at `level` (1, 3 or 5 consecutive chains).
    pub fn section_chains(&self, section: usize, level: Level) -> Range<usize> {
        level.section_chains(self.section_count(), section)
    }

    /// The centre chain of section `section` at `level` (it shares the section's root exactly).
    pub fn centre_chain(&self, section: usize, level: Level) -> usize {
        self.section_chains(section, level).start + level.skeletons_per_section() / 2
    }

    /// Which section, level and child (0-based across the width) chain `chain` is.
    pub fn chain_owner(&self, chain: usize) -> (usize, Level, usize) {
        let level = Level::ALL
            .into_iter()
            .find(|&level| self.level_chains(level).contains(&chain))
            .unwrap_or(Level::StrandGroup);
        let local = chain - self.level_chains(level).start;
        let per = level.skeletons_per_section();
        (local / per, level, local % per)
    }

    /// The counts of this groom.
    pub fn counts(&self) -> GroomCounts {
        let nodes_of = |level: Level| -> usize {
            self.level_chains(level)
                .map(|chain| self.skeletons.chain_node_count(chain))
                .sum()
        };
        let s = self.section_count();
        let nodes_per_skeleton = if s > 0 {
            self.skeletons.chain_node_count(0)
        } else {
            0
        };
        let strands = self.strands.strand_count();
        GroomCounts {
            sections: s,
            patches: s,
            clusters: 3 * s,
            strand_groups: 5 * s,
            strands,
            nodes_per_skeleton,
            patch_nodes: nodes_of(Level::Patch),
            cluster_nodes: nodes_of(Level::Cluster),
            strand_group_nodes: nodes_of(Level::StrandGroup),
            skeleton_nodes: self.skeletons.node_count(),
            strand_control_points: strands * nodes_per_skeleton,
        }
    }
}
