//! Tests of the fit: synthetic grooms with known answers (`synthetic.rs`). The TressFX samples
//! are fitted in hair-formats (`src/tests/fit_real_data.rs`), which reads them.

mod synthetic;

use glam::Vec3;

use super::FittedHierarchy;
use crate::curves::Curves;

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

/// Checks the structure any fit must have ([`FittedHierarchy::check_structure`]).
pub(super) fn assert_well_formed(fit: &FittedHierarchy, curve_count: usize) {
    if let Err(error) = fit.check_structure(curve_count) {
        panic!("{error}");
    }
}
