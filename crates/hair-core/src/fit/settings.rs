//! What a fit is asked for: [`FitSettings`] (how many sections, how shape weighs against root
//! position, node counts) and the smoothness rule [`Smoothness`].

use crate::error::{HairError, Result, require_in_range, require_non_negative, require_positive};

/// How many sections a fit makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SectionCount {
    /// Exactly this many sections (fewer when some would hold fewer than 5 strands: they are
    /// merged, see [`FitReport::merged_sections`](super::FitReport::merged_sections)).
    Fixed(usize),
    /// About this many strands per section: `S = round(N / strands)`, at least 1.
    StrandsPerSection(usize),
}

/// Which curve stands for the strands of a patch, cluster or strand group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Representative {
    /// The mean of the members, point by point at equal fractions of their arc lengths.
    Mean,
    /// The member whose shape (root removed) is closest on average to the others'.
    Medoid,
    /// Per element, the mean or the medoid, whichever has the lower mean drawn error
    /// ([`LevelErrors::drawn`](super::LevelErrors::drawn)) over its strands (the mean on a tie).
    Best,
}

/// How a section's strands are cut into its 5 strand groups (both give sizes within one strand
/// of each other, numbered across the section along its binormal).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupSplit {
    /// Balanced k-means (5 clusters, sizes within one) on the strands' features, the groups then
    /// numbered by their root centroids along the section's binormal: groups of alike strands,
    /// side by side.
    KMeans,
    /// Runs of the strands sorted along the principal direction of their features: strict slabs
    /// across the section.
    Slabs,
}

/// Whether the skeletons of different sections may have different node counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeCountScope {
    /// Every skeleton of a section (its patch, 3 clusters and 5 strand groups) has the same node
    /// count, the largest any of them needs, so that level transitions (§4.2) hand state over
    /// node by node; sections differ.
    PerSection,
    /// One node count for the whole groom, the largest any section needs (what
    /// [`GroomCounts::nodes_per_skeleton`](crate::GroomCounts::nodes_per_skeleton) assumes today).
    Uniform,
}

/// The smoothness rule for node counts (§3.2: "the number of control points is decided
/// automatically based on ... the length of the hair, the waviness or curliness ... and the
/// desired smoothness"; §3.6: tighter curls need shorter segments, so more nodes).
///
/// A curve of length `L` [m] whose direction turns by `Θ` [rad] in all (the sum of the angles
/// between consecutive segments, i.e. ∫|κ| ds) gets
/// `segments = max(⌈L / max_segment_length⌉, ⌈Θ / max_turn_per_segment⌉, 3)`, at most
/// `max_nodes − 1`, and `nodes = segments + 1`: no segment is longer than the smoothness and, with
/// the turning spread evenly, no node bends by more than `max_turn_per_segment`. The floor of 3
/// segments is [`MIN_SEGMENT_COUNT`](crate::style::MIN_SEGMENT_COUNT): a cubic NURBS needs 4
/// control points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Smoothness {
    /// Longest segment [m] (the styles' `smoothness`).
    pub max_segment_length: f32,
    /// Largest turn of the direction per segment [rad].
    pub max_turn_per_segment: f32,
    /// Most nodes a skeleton may have (≥ 4). The position-based and XPBD integrators step
    /// chains of at most [`MAX_CHAIN_NODES`](crate::dynamics::MAX_CHAIN_NODES) (64, the
    /// default); more is for the other integrators.
    pub max_nodes: usize,
}

impl Default for Smoothness {
    /// 2.5 cm segments (the straight preset's smoothness), 20° per segment, at most 64 nodes.
    fn default() -> Self {
        Smoothness {
            max_segment_length: 0.025,
            max_turn_per_segment: 20f32.to_radians(),
            max_nodes: 64,
        }
    }
}

impl Smoothness {
    /// Checks every field, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        require_positive("smoothness max_segment_length (m)", self.max_segment_length)?;
        require_in_range(
            "smoothness max_turn_per_segment (rad)",
            self.max_turn_per_segment,
            1e-4,
            std::f32::consts::PI,
            "a finite angle in 1e-4..=π rad",
        )?;
        if !(4..=100_000).contains(&self.max_nodes) {
            return Err(HairError::invalid(
                "smoothness max_nodes",
                self.max_nodes,
                "4..=100000 nodes",
            ));
        }
        Ok(())
    }
}

/// Everything [`fit_hierarchy`](super::fit_hierarchy) is asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct FitSettings {
    /// How many sections.
    pub sections: SectionCount,
    /// Weight of a strand's shape (its middle and tip relative to its root [m]) against its root
    /// position [m] when strands are put into sections and strand groups, `>= 0` (0: roots only).
    pub shape_weight: f32,
    /// How much larger than `N / S` strands a section may grow when the clustering is balanced,
    /// as a fraction, `0..=10` (0: sizes within one strand of each other).
    pub section_size_slack: f32,
    /// Points each strand is resampled to (at equal arc-length steps) for clustering and for
    /// measuring errors, `4..=4096`.
    pub samples_per_strand: usize,
    /// How sections are cut into strand groups.
    pub group_split: GroupSplit,
    /// The node count rule.
    pub smoothness: Smoothness,
    /// Node counts per section or for the whole groom.
    pub node_counts: NodeCountScope,
    /// Which curve stands for each element's strands.
    pub representative: Representative,
    /// Seed of the k-means++ initialisation; equal seeds give equal fits.
    pub seed: u64,
}

impl Default for FitSettings {
    /// About 50 strands per section, shape weight 0.5, 25 % slack, 32 samples per strand, the
    /// k-means strand groups, the default smoothness, node counts per section, the best of mean and medoid, seed 1.
    fn default() -> Self {
        FitSettings {
            sections: SectionCount::StrandsPerSection(50),
            shape_weight: 0.5,
            section_size_slack: 0.25,
            samples_per_strand: 32,
            group_split: GroupSplit::KMeans,
            smoothness: Smoothness::default(),
            node_counts: NodeCountScope::PerSection,
            representative: Representative::Best,
            seed: 1,
        }
    }
}

impl FitSettings {
    /// Checks every field, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        match self.sections {
            SectionCount::Fixed(0) => {
                return Err(HairError::invalid("sections", 0, "at least 1 section"));
            }
            SectionCount::StrandsPerSection(0) => {
                return Err(HairError::invalid(
                    "strands per section",
                    0,
                    "at least 1 strand per section",
                ));
            }
            _ => {}
        }
        require_non_negative("shape_weight", self.shape_weight)?;
        require_in_range(
            "section_size_slack",
            self.section_size_slack,
            0.0,
            10.0,
            "a fraction in 0..=10",
        )?;
        if !(4..=4096).contains(&self.samples_per_strand) {
            return Err(HairError::invalid(
                "samples_per_strand",
                self.samples_per_strand,
                "4..=4096 samples",
            ));
        }
        self.smoothness.validate()
    }

    /// The section count for `strand_count` strands (before small sections are merged).
    pub fn section_count_for(&self, strand_count: usize) -> usize {
        match self.sections {
            SectionCount::Fixed(count) => count.max(1),
            SectionCount::StrandsPerSection(per) => {
                ((strand_count as f64 / per.max(1) as f64).round() as usize).max(1)
            }
        }
    }
}
