//! How well a fit stands for its strands: [`FitReport`] with, per level, the distance between
//! each strand and its element's skeleton under three offset models ([`LevelErrors`]).

use std::fmt;

use crate::level::Level;
use crate::per_level::PerLevel;

/// Statistics of one error over the strands [m]. A strand's error is the mean, over its
/// `samples_per_strand` points at equal fractions of its length, of the distance between the
/// strand and its model at the same fraction.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ErrorStats {
    /// Mean of the strands' errors [m].
    pub mean: f32,
    /// 95th percentile (nearest rank) of the strands' errors [m].
    pub p95: f32,
    /// Largest strand error [m].
    pub max: f32,
    /// Largest distance at any one sample of any strand [m].
    pub worst_point: f32,
}

impl ErrorStats {
    /// The statistics of per-strand errors `(mean distance, largest distance)` [m].
    pub fn from_strands(errors: impl IntoIterator<Item = (f32, f32)>) -> ErrorStats {
        let mut means = Vec::new();
        let mut worst_point = 0.0f32;
        for (mean, max) in errors {
            means.push(mean);
            worst_point = worst_point.max(max);
        }
        if means.is_empty() {
            return ErrorStats::default();
        }
        means.sort_by(f32::total_cmp);
        let n = means.len();
        let total: f64 = means.iter().map(|&e| f64::from(e)).sum();
        // Nearest rank: the smallest value with at least 95 % of the values at or below it.
        let rank = (0.95 * n as f64).ceil() as usize;
        ErrorStats {
            mean: (total / n as f64) as f32,
            p95: means[rank.clamp(1, n) - 1],
            max: means[n - 1],
            worst_point,
        }
    }

    /// Whether every field is finite.
    pub fn is_finite(&self) -> bool {
        [self.mean, self.p95, self.max, self.worst_point]
            .iter()
            .all(|v| v.is_finite())
    }
}

/// The errors of one level, each strand measured against the skeleton of the element (patch,
/// cluster or strand group) it belongs to at that level.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct LevelErrors {
    /// The model as drawn today: the strand is its element's skeleton plus one constant root
    /// offset in the node frames' (normal, binormal) plane, `node_i + x·normal_i + y·binormal_i`,
    /// with `(x, y)` the strand root's offset from the skeleton root in the root frame. This is
    /// the shape error (the strand's position is removed by its offset).
    pub drawn: ErrorStats,
    /// If each node could carry its own offset in its (normal, binormal) plane: what is left is
    /// the part of the difference along the node's tangent, plus the chord error between nodes.
    /// `drawn − per_node_offsets` is what the constant offset costs.
    pub per_node_offsets: ErrorStats,
    /// No offset at all: the distance from the strand to the skeleton itself (the element's
    /// thickness, roughly).
    pub centreline: ErrorStats,
}

/// What [`fit_hierarchy`](super::fit_hierarchy) made and how well it fits.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct FitReport {
    /// Strands fitted (the curves' count).
    pub strands: usize,
    /// Sections asked for ([`FitSettings::section_count_for`](super::FitSettings::section_count_for)).
    pub requested_sections: usize,
    /// Sections made.
    pub sections: usize,
    /// Sections of fewer than 5 strands (or none) that were merged into their nearest neighbour
    /// (by root centroid), or left empty by the clustering.
    pub merged_sections: usize,
    /// Strands of the smallest section.
    pub smallest_section: usize,
    /// Strands of the largest section.
    pub largest_section: usize,
    /// Fewest nodes of a skeleton.
    pub min_nodes: usize,
    /// Most nodes of a skeleton.
    pub max_nodes: usize,
    /// Errors per level.
    pub errors: PerLevel<LevelErrors>,
    /// The floor under every level: each strand resampled to its section's node count and drawn
    /// through those nodes (what any per-node model at that node count loses).
    pub discretisation: ErrorStats,
    /// Elements per level whose representative is a medoid (the rest are means).
    pub medoid_elements: PerLevel<usize>,
    /// Largest distance between a section's patch root (the section's centre) and its centre
    /// cluster's root (the same as its centre strand group's) [m].
    pub max_centre_gap: f32,
}

/// Millimetres, for messages.
fn mm(metres: f32) -> String {
    format!("{:.3}", metres * 1e3)
}

impl fmt::Display for ErrorStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "mean {} p95 {} max {} worst point {} mm",
            mm(self.mean),
            mm(self.p95),
            mm(self.max),
            mm(self.worst_point)
        )
    }
}

impl fmt::Display for FitReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} strands in {} sections ({} asked, {} merged; {}..={} strands each), {}..={} nodes",
            self.strands,
            self.sections,
            self.requested_sections,
            self.merged_sections,
            self.smallest_section,
            self.largest_section,
            self.min_nodes,
            self.max_nodes
        )?;
        for level in Level::ALL {
            let errors = &self.errors[level];
            writeln!(
                f,
                "  {:8} drawn (root offset) {}\n  {:8} per-node offsets   {}\n  {:8} centreline         {}\n  {:8} medoids: {}",
                level.name(),
                errors.drawn,
                "",
                errors.per_node_offsets,
                "",
                errors.centreline,
                "",
                self.medoid_elements[level]
            )?;
        }
        write!(
            f,
            "  discretisation floor       {}\n  largest centre gap {} mm",
            self.discretisation,
            mm(self.max_centre_gap)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_use_the_nearest_rank() {
        // 20 strands with errors 1..=20 mm: mean 10.5, p95 = the 19th value.
        let stats = ErrorStats::from_strands((1..=20).map(|i| (i as f32 * 1e-3, i as f32 * 2e-3)));
        assert!((stats.mean - 10.5e-3).abs() < 1e-7);
        assert_eq!(stats.p95, 19.0 * 1e-3);
        assert_eq!(stats.max, 20.0 * 1e-3);
        assert_eq!(stats.worst_point, 20.0 * 2e-3);
        assert_eq!(ErrorStats::from_strands([]), ErrorStats::default());
    }
}
