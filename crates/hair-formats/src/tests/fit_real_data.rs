//! The TressFX samples read and fitted (hair-core's `fit`): the Ratboy mohawk (metres) and the
//! four ponytail parts (centimetres). Prints counts, errors per level and fit times
//! (`-- --nocapture`). Here rather than in hair-core, which cannot read files.

use std::time::Instant;

use hair_core::fit::{FitSettings, FittedHierarchy, fit_hierarchy};
use hair_core::level::Level;

use super::real_data::{centimetres, data_file};
use crate::{Curves, ImportOptions, read_curves_file};

/// Checks the structure any fit must have ([`FittedHierarchy::check_structure`]).
fn assert_well_formed(fit: &FittedHierarchy, curve_count: usize) {
    if let Err(error) = fit.check_structure(curve_count) {
        panic!("{error}");
    }
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
