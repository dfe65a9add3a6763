//! Alembic `.abc` curves: the fixture `tests/data/curves.abc` (written by PyAlembic through
//! `tests/make_alembic_fixture.py`, whose docstring lists its objects and values) read point for
//! point, through its transform, at its first time sample; and what the reader refuses.

use glam::Vec3;

use crate::{
    ImportAxes, ImportOptions, SkipReason, SkippedCurve, UpAxis, read_alembic, read_alembic_file,
    read_curves_file,
};

/// The fixture's path.
pub(crate) const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/curves.abc");

/// The fixture's bytes.
pub(crate) fn fixture() -> Vec<u8> {
    std::fs::read(FIXTURE).unwrap()
}

/// `/groom`'s transform in the generator: translate (10, 20, 30) after scale 2.
fn groom(p: Vec3) -> Vec3 {
    2.0 * p + Vec3::new(10.0, 20.0, 30.0)
}

#[test]
fn the_fixture_reads_every_curves_object_through_its_transform() {
    let curves = read_alembic_file(FIXTURE, &ImportOptions::default()).unwrap();
    // /plain: PLAIN_POINTS and PLAIN_COUNTS [3, 1, 2] of the generator, untransformed; its curve 1
    // (one point) is skipped.
    let plain = [
        vec![Vec3::ZERO, Vec3::Y, Vec3::new(0.0, 2.0, 0.5)],
        vec![Vec3::X, Vec3::new(1.0, 0.25, 0.0)],
    ];
    // /groom/tuft: TUFT_POINTS at the first sample (the second is moved by +100 in x), through
    // /groom's transform.
    let tuft = [
        [Vec3::ZERO, Vec3::Y, 2.0 * Vec3::Y],
        [Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, 2.0, 0.5)],
    ]
    .map(|curve| curve.map(groom).to_vec());
    let expected: Vec<Vec<Vec3>> = plain.into_iter().chain(tuft).collect();
    let read: Vec<Vec<Vec3>> = curves.iter().map(<[Vec3]>::to_vec).collect();
    assert_eq!(read, expected);
    assert_eq!(curves.offsets, [0, 3, 5, 8, 11]);
    assert_eq!(
        curves.skipped,
        [SkippedCurve {
            index: 1,
            reason: SkipReason::TooFewPoints { count: 1 }
        }]
    );
    // /plain's one constant width 0.1 on each of its points; TUFT_WIDTHS per point, doubled by
    // /groom's scale 2.
    let widths = curves.widths.as_ref().unwrap();
    let expected_widths = [0.1, 0.1, 0.1, 0.1, 0.1, 1.0, 0.5, 0.25, 1.0, 0.5, 0.0];
    assert_eq!(widths.len(), expected_widths.len());
    for (read, expected) in widths.iter().zip(expected_widths) {
        assert!((read - expected).abs() < 1e-7, "{widths:?}");
    }
    assert_eq!(curves.colors, None);
    assert_eq!(curves.check_layout(), Ok(()));
}

#[test]
fn the_fixture_goes_through_the_import_axes_and_the_dispatcher() {
    let axes = ImportAxes {
        scale_to_metres: 0.01,
        up: UpAxis::Z,
        mirror_x: false,
    };
    let curves = read_curves_file(FIXTURE, &ImportOptions::with_axes(axes)).unwrap();
    // The tuft's last point, (1, 2, 0.5) through /groom: (12, 24, 31) cm; Z up:
    // (0.12, 0.31, -0.24) m.
    let last = *curves.points.last().unwrap();
    assert!(
        (last - Vec3::new(0.12, 0.31, -0.24)).length() < 1e-6,
        "{last}"
    );
    // Widths scale to metres: the tuft's first width, 0.5 × 2 = 1 cm.
    assert!((curves.widths.as_ref().unwrap()[5] - 0.01).abs() < 1e-9);
}

#[test]
fn strict_reading_refuses_the_fixtures_one_point_curve() {
    let error = read_alembic(&fixture(), &ImportOptions::strict()).unwrap_err();
    // /plain's curve 1 is (5, 5, 5) alone: the fourth point of P, whose values start at byte
    // 16 (key) + 8 (size) past its block; the offset is where that point lies in the file.
    let text = error.to_string();
    assert!(
        text.starts_with("<memory>: curve 1 at byte ")
            && text.ends_with(": fewer than two points (1) (strict reading)"),
        "{text}"
    );
    let offset: usize = text["<memory>: curve 1 at byte ".len()..]
        .split(':')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let bytes = fixture();
    let point: Vec<f32> = bytes[offset..offset + 12]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(point, [5.0, 5.0, 5.0]);
}
