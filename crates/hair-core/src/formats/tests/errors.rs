//! Every way a file can be broken, each with the message it gives: truncated files, wrong
//! signatures and versions, counts larger than the file, non-finite values, degenerate curves
//! (skipped by default, refused when strict), empty grooms, unknown extensions, missing files.

use glam::Vec3;

use super::scratch_dir;
use crate::error::HairError;
use crate::formats::cyhair::tests::sample_curves;
use crate::formats::tfx::tests::{tfx3_bytes, tfx4_bytes, two_strands};
use crate::formats::usc::tests::{strands_with_empty_roots, usc_bytes};
use crate::formats::{
    FormatErrorKind, ImportOptions, SkipReason, SkippedCurve, read_curves_file, read_hair,
    read_mesh_file, read_tfx, read_tfx_file, read_usc_data, write_hair_bytes,
};

fn message<T: std::fmt::Debug>(result: Result<T, crate::formats::FormatError>) -> String {
    result.unwrap_err().to_string()
}

#[test]
fn truncated_headers_name_what_was_cut() {
    let bytes = tfx4_bytes(&two_strands());
    assert_eq!(
        message(read_tfx(&bytes[..100], &ImportOptions::default())),
        "<memory>: truncated: the TressFX 4 header at byte 0 needs 160 bytes, but only 100 remain"
    );
    assert_eq!(
        message(read_tfx(
            &tfx3_bytes(&two_strands())[..200],
            &ImportOptions::default()
        )),
        "<memory>: truncated: the TressFX 3 header at byte 0 needs 296 bytes, but only 200 remain"
    );
    assert_eq!(
        message(read_tfx(&bytes[..2], &ImportOptions::default())),
        "<memory>: truncated: the TressFX version at byte 0 needs 4 bytes, but only 2 remain"
    );
    let hair = write_hair_bytes(&sample_curves()).unwrap();
    assert_eq!(
        message(read_hair(&hair[..64], &ImportOptions::default())),
        "<memory>: truncated: the cyHair header at byte 0 needs 128 bytes, but only 64 remain"
    );
}

#[test]
fn truncated_data_is_an_error_not_a_shorter_groom() {
    // TressFX and cyHair: the header's counts no longer fit.
    let bytes = tfx4_bytes(&two_strands());
    assert_eq!(
        message(read_tfx(&bytes[..200], &ImportOptions::default())),
        "<memory>: strand_count 2 × vertices_per_strand 4 = 8 vertices at byte 4 needs 128 bytes \
         from byte 160, but the file has 200 bytes (truncated, or a wrong count)"
    );
    let hair = write_hair_bytes(&sample_curves()).unwrap();
    assert!(
        message(read_hair(
            &hair[..hair.len() - 1],
            &ImportOptions::default()
        ))
        .contains("but the file has 329 bytes (truncated, or a wrong count)")
    );
    // USC-HairSalon: strand by strand.
    let data = usc_bytes(&strands_with_empty_roots());
    assert_eq!(
        message(read_usc_data(&data[..40], &ImportOptions::default())),
        "<memory>: truncated: the 3 vertices of strand 1 at byte 24 needs 36 bytes, but only 16 \
         remain"
    );
    assert_eq!(
        message(read_usc_data(&data[..22], &ImportOptions::default())),
        "<memory>: truncated: the vertex count of strand 1 at byte 20 needs 4 bytes, but only 2 \
         remain"
    );
}

#[test]
fn a_truncated_file_names_the_file() {
    let dir = scratch_dir("truncated");
    let path = dir.join("cut.tfx");
    std::fs::write(&path, &tfx4_bytes(&two_strands())[..100]).unwrap();
    let error = read_tfx_file(&path, &ImportOptions::default()).unwrap_err();
    assert_eq!(error.file, path.display().to_string());
    assert_eq!(
        error.to_string(),
        format!(
            "{}: truncated: the TressFX 4 header at byte 0 needs 160 bytes, but only 100 remain",
            path.display()
        )
    );
    // As a HairError: reading <path>: <what>.
    let hair_error = HairError::from(error);
    assert_eq!(
        hair_error.to_string(),
        format!(
            "reading {}: truncated: the TressFX 4 header at byte 0 needs 160 bytes, but only 100 \
             remain",
            path.display()
        )
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_wrong_signature_is_named() {
    let mut hair = write_hair_bytes(&sample_curves()).unwrap();
    hair[3] = b'X';
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::default())),
        "<memory>: not a cyHair file: found \"HAIX\" at byte 0, expected \"HAIR\""
    );
    hair[..4].copy_from_slice(&[0, 0xff, b'\n', b'a']);
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::default())),
        "<memory>: not a cyHair file: found \"\\x00\\xff\\na\" at byte 0, expected \"HAIR\""
    );
}

#[test]
fn a_wrong_version_is_named() {
    let mut bytes = tfx4_bytes(&two_strands());
    for (version, text) in [(2.0f32, "2"), (5.0, "5"), (f32::NAN, "NaN"), (-4.0, "-4")] {
        bytes[..4].copy_from_slice(&version.to_le_bytes());
        assert_eq!(
            message(read_tfx(&bytes, &ImportOptions::default())),
            format!(
                "<memory>: unsupported TressFX version {text} at byte 0 (supported: 3.x and 4.x)"
            )
        );
    }
    // 4.1 and 3.5 are read as their major version.
    bytes[..4].copy_from_slice(&4.1f32.to_le_bytes());
    assert!(read_tfx(&bytes, &ImportOptions::default()).is_ok());
}

#[test]
fn counts_beyond_the_file_are_refused_before_allocating() {
    let mut bytes = tfx4_bytes(&two_strands());
    bytes[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    bytes[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    assert_eq!(
        message(read_tfx(&bytes, &ImportOptions::default())),
        "<memory>: strand_count 4294967295 × vertices_per_strand 4294967295 = \
         18446744065119617025 vertices at byte 4 needs 295147905041913872400 bytes from byte 160, \
         but the file has 304 bytes (truncated, or a wrong count)"
    );
    let mut hair = write_hair_bytes(&sample_curves()).unwrap();
    hair[8..12].copy_from_slice(&0x4000_0000u32.to_le_bytes());
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::default())),
        "<memory>: hair_count 3, point_count 1073741824 with arrays 0b10111 at byte 4 needs \
         30064771078 bytes from byte 128, but the file has 330 bytes (truncated, or a wrong count)"
    );
    let mut data = usc_bytes(&strands_with_empty_roots());
    data[..4].copy_from_slice(&i32::MAX.to_le_bytes());
    assert_eq!(
        message(read_usc_data(&data, &ImportOptions::default())),
        "<memory>: strand_count 2147483647 at byte 0 needs 8589934588 bytes from byte 4, but the \
         file has 104 bytes (truncated, or a wrong count)"
    );
    // A single strand's count, too.
    let mut data = usc_bytes(&strands_with_empty_roots());
    data[20..24].copy_from_slice(&i32::MAX.to_le_bytes());
    assert_eq!(
        message(read_usc_data(&data, &ImportOptions::default())),
        "<memory>: truncated: the 2147483647 vertices of strand 1 at byte 24 needs 25769803764 \
         bytes, but only 80 remain"
    );
}

#[test]
fn non_finite_coordinates_name_curve_point_and_byte() {
    let mut strands = two_strands();
    strands[1][2][1] = f32::NAN;
    // Strand 1 starts at 160 + 4 × 16; its point 2 is 2 × 16 further.
    assert_eq!(
        message(read_tfx(&tfx4_bytes(&strands), &ImportOptions::default())),
        "<memory>: curve 1, point 2 at byte 256: position [0.1, NaN, 0] is not finite"
    );
    strands[1][2][1] = f32::NEG_INFINITY;
    assert_eq!(
        message(read_tfx(&tfx3_bytes(&strands), &ImportOptions::default())),
        "<memory>: curve 1, point 2 at byte 368: position [0.1, -inf, 0] is not finite"
    );
    let curves = sample_curves();
    let mut hair = write_hair_bytes(&curves).unwrap();
    // Point 4 of the file (curve 1, point 2): after the header and 3 segment counts; its z.
    let at = 128 + 6 + 4 * 12 + 8;
    hair[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::default())),
        "<memory>: curve 1, point 2 at byte 182: position [0.01, -0.04, inf] is not finite"
    );
    // Widths and colours too, at their own arrays' bytes: width 6 of the file (curve 2, point 1)
    // after the header, 3 segment counts and 7 points.
    let mut hair = write_hair_bytes(&curves).unwrap();
    let at = 128 + 6 + 7 * 12 + 6 * 4;
    hair[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::default())),
        "<memory>: curve 2, point 1 at byte 242: width NaN is not finite"
    );
    hair[at..at + 4].copy_from_slice(&(-1.0f32).to_le_bytes());
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::default())),
        "<memory>: curve 2, point 1 at byte 242: width -1 is invalid (allowed: a width >= 0)"
    );
    // Colour 5 (curve 2, point 0): after the 7 widths; its green.
    let mut hair = write_hair_bytes(&curves).unwrap();
    let at = 128 + 6 + 7 * 12 + 7 * 4 + 5 * 12 + 4;
    hair[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::default())),
        "<memory>: curve 2, point 0 at byte 306: colour [0.5, inf, 0.3] is not finite"
    );
    let mut data = usc_bytes(&strands_with_empty_roots());
    data[24..28].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(
        message(read_usc_data(&data, &ImportOptions::default())),
        "<memory>: curve 1, point 0 at byte 24: position [NaN, 1.7, 0] is not finite"
    );
}

/// A TressFX 4 groom of three strands: one good, one with a repeated point, one good.
fn tfx_with_a_zero_length_segment() -> Vec<u8> {
    let mut strands = two_strands();
    let mut repeated = strands[0].clone();
    repeated[2] = repeated[1];
    strands.insert(1, repeated);
    tfx4_bytes(&strands)
}

#[test]
fn zero_length_segments_are_skipped_or_refused_when_strict() {
    let bytes = tfx_with_a_zero_length_segment();
    let curves = read_tfx(&bytes, &ImportOptions::default()).unwrap();
    assert_eq!(curves.curve_count(), 2);
    assert_eq!(
        curves.curve(1)[0],
        Vec3::new(0.1, 0.0, 0.0),
        "curve 2 of the file"
    );
    assert_eq!(
        curves.skipped,
        [SkippedCurve {
            index: 1,
            reason: SkipReason::ZeroLengthSegment { segment: 1 }
        }]
    );
    // Strand 1 starts at 160 + 4 × 16; segment 1 at its point 1.
    assert_eq!(
        message(read_tfx(&bytes, &ImportOptions::strict())),
        "<memory>: curve 1 at byte 240: segment 1 has zero length (strict reading)"
    );
}

#[test]
fn curves_of_one_point_are_skipped_or_refused_when_strict() {
    let mut curves = sample_curves();
    // Curve 1 becomes a single point; its other two points move to curve 2.
    curves.offsets = vec![0, 2, 3, 7];
    curves.points[3] = Vec3::new(0.5, 0.5, 0.5);
    curves.points[4] = Vec3::new(0.5, 0.6, 0.5);
    let hair = write_hair_bytes(&curves).unwrap();
    let read = read_hair(&hair, &ImportOptions::default()).unwrap();
    assert_eq!(read.offsets, [0, 2, 6]);
    assert_eq!(
        read.skipped,
        [SkippedCurve {
            index: 1,
            reason: SkipReason::TooFewPoints { count: 1 }
        }]
    );
    assert_eq!(read.widths.as_ref().unwrap().len(), 6);
    assert_eq!(
        read.colors.as_ref().unwrap()[2],
        curves.colors.as_ref().unwrap()[3]
    );
    // Point 2 of the file: after the header, 3 segment counts and 2 points.
    assert_eq!(
        message(read_hair(&hair, &ImportOptions::strict())),
        "<memory>: curve 1 at byte 158: fewer than two points (1) (strict reading)"
    );
}

#[test]
fn an_empty_groom_is_always_an_error() {
    let mut bytes = tfx4_bytes(&two_strands());
    bytes[4..8].copy_from_slice(&0u32.to_le_bytes());
    assert_eq!(
        message(read_tfx(&bytes, &ImportOptions::default())),
        "<memory>: no usable curve: the file has 0 curves, 0 of them skipped"
    );
    let single_points = vec![vec![[0.0, 0.0, 0.0]], vec![[1.0, 0.0, 0.0]]];
    assert_eq!(
        message(read_tfx(
            &tfx3_bytes(&single_points),
            &ImportOptions::default()
        )),
        "<memory>: no usable curve: the file has 2 curves, 2 of them skipped"
    );
    let data = usc_bytes(&[]);
    assert_eq!(
        message(read_usc_data(&data, &ImportOptions::default())),
        "<memory>: no usable curve: the file has 0 curves, 0 of them skipped"
    );
}

#[test]
fn a_bad_scale_is_refused_by_every_reader() {
    let options = ImportOptions::with_axes(crate::formats::ImportAxes {
        scale_to_metres: -1.0,
        ..Default::default()
    });
    let error = read_tfx(&tfx4_bytes(&two_strands()), &options).unwrap_err();
    assert!(matches!(*error.kind, FormatErrorKind::InvalidOption { .. }));
    assert_eq!(
        error.to_string(),
        "<memory>: invalid import option scale_to_metres = -1 (allowed: a finite number > 0 \
         (metres per file unit))"
    );
}

#[test]
fn unknown_extensions_and_missing_files_name_the_file() {
    let error = read_curves_file("groom.abc", &ImportOptions::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "groom.abc: unknown file extension `abc` (known: .tfx, .hair, .data, .obj, .usda, .usd)"
    );
    let error = read_mesh_file("body.stl", &ImportOptions::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "body.stl: unknown file extension `stl` (known: .tfxmesh, .obj)"
    );
    let error = read_curves_file("/nonexistent/groom.TFX", &ImportOptions::default()).unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("/nonexistent/groom.TFX: No such file or directory"),
        "{error}"
    );
}

#[test]
fn trailing_bytes_after_a_usc_groom_are_refused() {
    let mut data = usc_bytes(&strands_with_empty_roots());
    data.extend([1, 2, 3]);
    assert_eq!(
        message(read_usc_data(&data, &ImportOptions::default())),
        "<memory>: 3 unexpected bytes after the data, from byte 104"
    );
}
