//! The structure every fit has, checked ([`FittedHierarchy::check_structure`]): every curve in
//! exactly one strand group, groups nested in clusters in sections, 9 chains per section with the
//! section's node count, every value finite, sizes and errors consistent, and skeletons that
//! measure into rest angles. The fit's tests run it on synthetic and real grooms; a caller can
//! run it on a hierarchy it built or changed.

use super::FittedHierarchy;
use crate::level::Level;

/// A fitted hierarchy that breaks its structure: what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("fitted hierarchy: {0}")]
pub struct StructureError(pub String);

/// Returns a [`StructureError`] with the formatted message unless `condition` holds.
macro_rules! ensure {
    ($condition:expr, $($message:tt)+) => {
        if !$condition {
            return Err(StructureError(format!($($message)+)));
        }
    };
}

impl FittedHierarchy {
    /// Checks the structure any fit of `curve_count` curves must have (the module's list); the
    /// first broken rule is the error.
    pub fn check_structure(&self, curve_count: usize) -> Result<(), StructureError> {
        let s = self.section_count();
        ensure!(s >= 1, "no section");
        ensure!(
            self.chain_count() == 9 * s,
            "{} chains for {s} sections (9 each)",
            self.chain_count()
        );
        ensure!(
            self.group_offsets.len() == 5 * s + 1,
            "{} group offsets for {s} sections (5 groups each, plus one)",
            self.group_offsets.len()
        );
        ensure!(
            self.strand_groups.len() == curve_count && self.root_offsets.len() == curve_count,
            "{} strand groups and {} root offsets for {curve_count} curves",
            self.strand_groups.len(),
            self.root_offsets.len()
        );
        self.check_groups(curve_count)?;
        self.check_sections(curve_count)?;
        self.check_values()?;
        self.check_report(curve_count)?;
        // The skeletons measure into rest angles and build back to the same nodes.
        let rest = self
            .skeleton_rest()
            .map_err(|error| StructureError(format!("the skeletons do not measure: {error}")))?;
        ensure!(
            rest.chain_count() == self.chain_count()
                && rest.node_count() == self.node_positions.len(),
            "the rest skeletons have {} chains and {} nodes, the fit {} and {}",
            rest.chain_count(),
            rest.node_count(),
            self.chain_count(),
            self.node_positions.len()
        );
        Ok(())
    }

    /// Every curve in exactly one group, the one `strand_groups` names; each group's cluster a
    /// chain of the same section.
    fn check_groups(&self, curve_count: usize) -> Result<(), StructureError> {
        let mut seen = vec![0u32; curve_count];
        for group in 0..5 * self.section_count() {
            let members = self.group_members(group);
            ensure!(!members.is_empty(), "strand group {group} is empty");
            for &curve in members {
                let curve = curve as usize;
                ensure!(curve < curve_count, "group {group} holds curve {curve}");
                seen[curve] += 1;
                ensure!(
                    self.strand_groups[curve] as usize == group,
                    "curve {curve} is in group {group}, strand_groups says {}",
                    self.strand_groups[curve]
                );
            }
            let cluster = self.cluster_of_group(group);
            ensure!(
                self.section_chains(group / 5, Level::Cluster)
                    .contains(&cluster),
                "group {group}'s cluster {cluster} is not a chain of its section"
            );
        }
        if let Some(curve) = seen.iter().position(|&n| n != 1) {
            return Err(StructureError(format!(
                "curve {curve} is in {} groups",
                seen[curve]
            )));
        }
        Ok(())
    }

    /// Each section's strands are its groups', at least 5; its chains have its node count; its
    /// patch's root is its centre.
    fn check_sections(&self, curve_count: usize) -> Result<(), StructureError> {
        let mut total = 0;
        for (section, data) in self.sections.iter().enumerate() {
            ensure!(
                data.strand_count >= 5,
                "section {section} has {} strands (at least 5)",
                data.strand_count
            );
            let in_groups: usize = (0..5)
                .map(|c| self.group_members(5 * section + c).len())
                .sum();
            ensure!(
                in_groups == data.strand_count,
                "section {section} counts {} strands, its groups hold {in_groups}",
                data.strand_count
            );
            total += data.strand_count;
            for level in Level::ALL {
                for chain in self.section_chains(section, level) {
                    ensure!(
                        self.nodes(chain).len() == data.node_count,
                        "chain {chain} has {} nodes, its section {}",
                        self.nodes(chain).len(),
                        data.node_count
                    );
                }
            }
            ensure!(
                data.node_count >= 4,
                "section {section} has {} nodes per chain (at least 4)",
                data.node_count
            );
            ensure!(
                data.width.is_finite() && data.width >= 0.0,
                "section {section} is {} m wide",
                data.width
            );
            ensure!(
                self.chain_positions(section)[0] == data.root_position,
                "section {section}'s patch does not start at its root"
            );
        }
        ensure!(
            total == curve_count,
            "the sections hold {total} strands of {curve_count} curves"
        );
        Ok(())
    }

    /// Node positions, radii, widths and root offsets: as many of each, finite, sizes ≥ 0.
    fn check_values(&self) -> Result<(), StructureError> {
        let nodes = self.node_positions.len();
        ensure!(
            self.node_radii.len() == nodes && self.node_widths.len() == nodes,
            "{nodes} nodes, {} radii, {} widths",
            self.node_radii.len(),
            self.node_widths.len()
        );
        ensure!(
            self.node_positions.iter().all(|p| p.is_finite()),
            "a node position is not finite"
        );
        ensure!(
            self.node_radii
                .iter()
                .chain(&self.node_widths)
                .all(|r| r.is_finite() && *r >= 0.0),
            "a node radius or width is negative or not finite"
        );
        ensure!(
            self.root_offsets.iter().all(|o| o.is_finite()),
            "a root offset is not finite"
        );
        Ok(())
    }

    /// The report counts what the fit holds, and its error statistics are finite and ordered
    /// (mean ≤ max, p95 ≤ max ≤ worst point).
    fn check_report(&self, curve_count: usize) -> Result<(), StructureError> {
        let report = &self.report;
        ensure!(
            report.strands == curve_count && report.sections == self.section_count(),
            "the report counts {} strands in {} sections",
            report.strands,
            report.sections
        );
        for level in Level::ALL {
            let errors = &report.errors[level];
            for stats in [errors.drawn, errors.per_node_offsets, errors.centreline] {
                ensure!(stats.is_finite(), "{level:?}: {stats:?} is not finite");
                ensure!(
                    stats.mean <= stats.max + 1e-9
                        && stats.p95 <= stats.max
                        && stats.max <= stats.worst_point + 1e-9,
                    "{level:?}: {stats:?} is out of order"
                );
            }
        }
        ensure!(
            report.discretisation.is_finite(),
            "the discretisation error is not finite"
        );
        Ok(())
    }
}
