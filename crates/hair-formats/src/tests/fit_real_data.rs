//! The TressFX samples read and fitted (hair-core's `fit`): the Ratboy mohawk (metres) and the
//! four ponytail parts (centimetres). Prints counts, errors per level and fit times
//! (`-- --nocapture`). Here rather than in hair-core, which cannot read files.

use std::time::Instant;

use hair_core::fit::{FitSettings, FittedHierarchy, fit_hierarchy};
use hair_core::level::Level;

use super::real_data::{centimetres, data_file};
use crate::{Curves, ImportOptions, read_curves_file};

/// Checks the structure any fit must have: every curve in exactly one strand group, groups
/// nested in clusters in sections, 9 chains per section with the section's node count, every
/// value finite, sizes and errors consistent.
fn assert_well_formed(fit: &FittedHierarchy, curve_count: usize) {
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

/// Fits `curves` with the default settings, printing the report and the time; checks what every
/// real fit must show.
fn fit_and_check(name: &str, curves: &Curves) -> FittedHierarchy {
    let start = Instant::now();
    let fit = fit_hierarchy(curves, &FitSettings::default()).unwrap();
    let elapsed = start.elapsed().as_secs_f64();
    eprintln!(
        "{name}: fitted in {:.1} ms (test profile, {} threads)\n{}",
        elapsed * 1e3,
        rayon::current_num_threads(),
        fit.report
    );
    assert_well_formed(&fit, curves.curve_count());
    let report = &fit.report;
    // About 50 strands per section, none under 5, none over 50 · 1.25 (merging may add a few).
    assert_eq!(
        report.requested_sections,
        (curves.curve_count() as f64 / 50.0).round() as usize
    );
    assert!(report.smallest_section >= 5);
    assert!(
        report.largest_section <= 63 + 5,
        "{}",
        report.largest_section
    );
    // Finer levels fit better: strand groups < clusters < patches, in mean and p95.
    let drawn = |level: Level| report.errors[level].drawn;
    assert!(drawn(Level::StrandGroup).mean < drawn(Level::Cluster).mean);
    assert!(drawn(Level::Cluster).mean < drawn(Level::Patch).mean);
    assert!(drawn(Level::StrandGroup).p95 < drawn(Level::Patch).p95);
    // Free per-node offsets can only help (they include the constant one at every node... up to
    // the tangential part, which both keep), and the discretisation floor is under everything.
    for level in Level::ALL {
        let errors = &report.errors[level];
        assert!(
            errors.per_node_offsets.mean <= errors.drawn.mean + 1e-6,
            "{level:?}"
        );
        assert!(report.discretisation.mean <= errors.per_node_offsets.mean + 1e-6);
    }
    fit
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_fits_with_errors_that_shrink_level_by_level() {
    let curves =
        read_curves_file(data_file("ratboy_mohawk.tfx"), &ImportOptions::strict()).unwrap();
    let fit = fit_and_check("ratboy_mohawk.tfx", &curves);
    assert_eq!(fit.report.strands, 2228);
    // The root offset helps at every level: drawn with it, strands are closer than the
    // skeleton itself is to them.
    for level in Level::ALL {
        let errors = &fit.report.errors[level];
        assert!(errors.drawn.mean < errors.centreline.mean, "{level:?}");
    }
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_ponytail_parts_fit_in_centimetres() {
    for name in [
        "ponytail_back.tfx",
        "ponytail_front_top.tfx",
        "ponytail_side.tfx",
        "ponytail_tail.tfx",
    ] {
        let curves = read_curves_file(data_file(name), &centimetres()).unwrap();
        let fit = fit_and_check(name, &curves);
        // Read in metres: every section's root frame and width are those of a head, not of a
        // building (a width over 1 m would mean the centimetres were taken for metres).
        assert!(fit.sections.iter().all(|s| s.width < 0.5), "{name}");
    }
}
