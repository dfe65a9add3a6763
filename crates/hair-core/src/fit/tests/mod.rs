//! Tests of the fit: synthetic grooms with known answers (`synthetic.rs`). The TressFX samples
//! are fitted in hair-formats (`src/tests/fit_real_data.rs`), which reads them.

mod synthetic;

use glam::Vec3;

use super::FittedHierarchy;
use crate::curves::Curves;
use crate::level::Level;

/// Curves from polylines (no widths, colours or skipped curves).
pub(super) fn curves_from(strands: &[Vec<Vec3>]) -> Curves {
    let mut curves = Curves {
        offsets: vec![0],
        ..Curves::default()
    };
    for strand in strands {
        curves.points.extend_from_slice(strand);
        curves.offsets.push(curves.points.len() as u32);
    }
    curves
}

/// Checks the structure any fit must have: every curve in exactly one strand group, groups
/// nested in clusters in sections, 9 chains per section with the section's node count, every
/// value finite, sizes and errors consistent.
pub(super) fn assert_well_formed(fit: &FittedHierarchy, curve_count: usize) {
    let s = fit.section_count();
    assert!(s >= 1);
    assert_eq!(fit.chain_count(), 9 * s);
    assert_eq!(fit.group_offsets.len(), 5 * s + 1);
    assert_eq!(fit.strand_groups.len(), curve_count);
    assert_eq!(fit.root_offsets.len(), curve_count);
    // Every curve appears in exactly one group, and that group is the one `strand_groups` names.
    let mut seen = vec![0u32; curve_count];
    for group in 0..5 * s {
        let members = fit.group_members(group);
        assert!(!members.is_empty(), "group {group} is empty");
        for &curve in members {
            seen[curve as usize] += 1;
            assert_eq!(fit.strand_groups[curve as usize] as usize, group);
        }
        // The group's cluster is a chain of the same section.
        let cluster = fit.cluster_of_group(group);
        assert!(
            fit.section_chains(group / 5, Level::Cluster)
                .contains(&cluster)
        );
    }
    assert!(
        seen.iter().all(|&n| n == 1),
        "a curve is in no group or in two"
    );
    let mut total = 0;
    for (section, data) in fit.sections.iter().enumerate() {
        assert!(data.strand_count >= 5);
        let in_groups: usize = (0..5)
            .map(|c| fit.group_members(5 * section + c).len())
            .sum();
        assert_eq!(in_groups, data.strand_count);
        total += data.strand_count;
        for level in Level::ALL {
            for chain in fit.section_chains(section, level) {
                assert_eq!(fit.nodes(chain).len(), data.node_count);
            }
        }
        assert!(data.node_count >= 4);
        assert!(data.width.is_finite() && data.width >= 0.0);
        // The patch's root is the section's centre.
        assert_eq!(fit.chain_positions(section)[0], data.root_position);
    }
    assert_eq!(total, curve_count);
    assert_eq!(fit.node_positions.len(), fit.node_radii.len());
    assert_eq!(fit.node_positions.len(), fit.node_widths.len());
    assert!(fit.node_positions.iter().all(|p| p.is_finite()));
    assert!(
        fit.node_radii
            .iter()
            .chain(&fit.node_widths)
            .all(|r| r.is_finite() && *r >= 0.0)
    );
    assert!(fit.root_offsets.iter().all(|o| o.is_finite()));
    let report = &fit.report;
    assert_eq!(report.strands, curve_count);
    assert_eq!(report.sections, s);
    for level in Level::ALL {
        let errors = &report.errors[level];
        for stats in [errors.drawn, errors.per_node_offsets, errors.centreline] {
            assert!(stats.is_finite(), "{level:?}: {stats:?}");
            assert!(stats.mean <= stats.max + 1e-9);
            assert!(stats.p95 <= stats.max && stats.max <= stats.worst_point + 1e-9);
        }
    }
    assert!(report.discretisation.is_finite());
    // The skeletons can be measured into rest angles and built back to the same nodes.
    let rest = fit.skeleton_rest().unwrap();
    assert_eq!(rest.chain_count(), fit.chain_count());
    assert_eq!(rest.node_count(), fit.node_positions.len());
}
