//! Every way a file can be broken, each with the message it gives: truncated files, wrong
//! signatures and versions, counts larger than the file, non-finite values, degenerate curves
//! (skipped by default, refused when strict), empty grooms, unknown extensions, missing files.

use glam::Vec3;

use super::scratch_dir;
use crate::cyhair::tests::sample_curves;
use crate::tfx::tests::{tfx3_bytes, tfx4_bytes, two_strands};
use crate::usc::tests::{strands_with_empty_roots, usc_bytes};
use crate::{
    FormatErrorKind, ImportOptions, SkipReason, SkippedCurve, read_curves_file, read_hair,
    read_mesh_file, read_tfx, read_tfx_file, read_usc_data, write_hair_bytes,
};
use hair_core::error::HairError;

fn message<T: std::fmt::Debug>(result: Result<T, crate::FormatError>) -> String {
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
    let options = ImportOptions::with_axes(crate::ImportAxes {
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
    let error = read_curves_file("groom.fbx", &ImportOptions::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "groom.fbx: unknown file extension `fbx` (known: .tfx, .hair, .data, .obj, .usda, .usdc, \
         .usd, .abc)"
    );
    let error = read_mesh_file("body.stl", &ImportOptions::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "body.stl: unknown file extension `stl` (known: .tfxmesh, .obj, .usda, .usdc, .usd)"
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

/// The Alembic fixture with `value` written at byte `at` (offsets from
/// `tests/make_alembic_fixture.py`'s archive, listed where used).
fn patched_alembic(at: usize, value: &[u8]) -> Vec<u8> {
    let mut bytes = super::alembic::fixture();
    bytes[at..at + value.len()].copy_from_slice(value);
    bytes
}

fn alembic_message(bytes: &[u8]) -> String {
    message(crate::read_alembic(bytes, &ImportOptions::default()))
}

#[test]
fn alembic_signature_version_and_frozen_flag_are_checked() {
    assert_eq!(
        alembic_message(b"\x89HDF\r\n\x1a\n and more"),
        "<memory>: not a binary (Ogawa) Alembic file: found \"\\x89HDF\\r\" at byte 0, expected \
         \"Ogawa\" (an HDF5 Alembic archive is not read)"
    );
    // Byte 5: 0xff once the writer closed the archive.
    assert_eq!(
        alembic_message(&patched_alembic(5, &[0])),
        "<memory>: invalid frozen flag = 0x00 at byte 5 (allowed: 0xff: an archive its writer \
         closed)"
    );
    // Bytes 6 and 7: the version, high byte first.
    assert_eq!(
        alembic_message(&patched_alembic(6, &[0, 2])),
        "<memory>: unsupported Ogawa version 2 at byte 6 (supported: 1)"
    );
}

#[test]
fn a_truncated_alembic_archive_names_the_file_and_the_offset() {
    let bytes = super::alembic::fixture();
    assert_eq!(
        alembic_message(&bytes[..10]),
        "<memory>: truncated: the Ogawa header at byte 0 needs 16 bytes, but only 10 remain"
    );
    // The root group is at byte 2802 (the header's last 8 bytes), past the cut.
    let dir = scratch_dir("alembic-truncated");
    let path = dir.join("cut.abc");
    std::fs::write(&path, &bytes[..2000]).unwrap();
    assert_eq!(
        message(read_curves_file(&path, &ImportOptions::default())),
        format!(
            "{}: truncated: the child count of an Ogawa group at byte 2802 needs 8 bytes, but \
             only 0 remain",
            path.display()
        )
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn alembic_sizes_beyond_the_file_are_refused_before_allocating() {
    // /plain's P block starts at byte 40 with its u64 size (88).
    assert_eq!(
        alembic_message(&patched_alembic(40, &(1u64 << 40).to_le_bytes())),
        "<memory>: size 1099511627776 of the Ogawa data block at byte 40 needs 1099511627776 \
         bytes from byte 48, but the file has 2858 bytes (truncated, or a wrong count)"
    );
    // The root group's child count, at byte 2802.
    assert_eq!(
        alembic_message(&patched_alembic(2802, &u64::MAX.to_le_bytes())),
        "<memory>: child_count 18446744073709551615 of the Ogawa group at byte 2802 needs \
         147573952589676412920 bytes from byte 2810, but the file has 2858 bytes (truncated, or a \
         wrong count)"
    );
    // The time samplings' block (48 bytes from byte 2294 + 8) with the first sampling's sample
    // count, after its u32 max sample and f64 time per cycle, set to u32::MAX.
    assert_eq!(
        alembic_message(&patched_alembic(2314, &u32::MAX.to_le_bytes())),
        "<memory>: Alembic time samplings: the sample times of a time sampling needs 34359738360 \
         bytes, but only 32 remain in its block (at byte 2318)"
    );
}

#[test]
fn alembic_groups_that_loop_are_refused() {
    // The top object's group (byte 2184) lists /plain's group at byte 2200; point it back at
    // the top object's group.
    assert_eq!(
        alembic_message(&patched_alembic(2200, &2184u64.to_le_bytes())),
        "<memory>: Alembic Ogawa group: the group contains itself (a cycle of group offsets) (at \
         byte 2184)"
    );
}

#[test]
fn alembic_points_and_counts_are_checked_by_object_and_byte() {
    // /plain's P values start at byte 40 + 8 (size) + 16 (key).
    assert_eq!(
        alembic_message(&patched_alembic(64, &f32::NAN.to_le_bytes())),
        "<memory>: /plain: curve 0, point 0 at byte 64: position [NaN, 0, 0] is not finite"
    );
    assert_eq!(
        alembic_message(&patched_alembic(68, &f32::INFINITY.to_le_bytes())),
        "<memory>: /plain: curve 0, point 0 at byte 64: position [0, inf, 0] is not finite"
    );
    // /plain's nVertices [3, 1, 2] start at byte 136 + 8 + 16.
    assert_eq!(
        alembic_message(&patched_alembic(160, &4i32.to_le_bytes())),
        "<memory>: inconsistent counts at byte 160: /plain: the 3 nVertices add up to 7 points, \
         but P has 6"
    );
    assert_eq!(
        alembic_message(&patched_alembic(164, &(-1i32).to_le_bytes())),
        "<memory>: invalid /plain nVertices[1] = -1 at byte 164 (allowed: a vertex count >= 0)"
    );
}

#[test]
fn alembic_without_linear_curves_is_refused() {
    let no_curves = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/no_curves.abc");
    assert_eq!(
        message(read_curves_file(no_curves, &ImportOptions::default())),
        format!(
            "{no_curves}: Alembic archive: no Curves object (schema AbcGeom_Curve_v2) (at byte 0)"
        )
    );
    // curveBasisAndType (type, periodicity, basis) at byte 172 + 8 + 16: cubic, then periodic.
    assert_eq!(
        alembic_message(&patched_alembic(196, &[0, 0, 2])),
        "<memory>: Alembic /plain .geom curveBasisAndType: type cubic (basis b-spline); only \
         linear, non-periodic curves are read (convert the curves to linear polylines first) (at \
         byte 196)"
    );
    assert!(alembic_message(&patched_alembic(196, &[1, 1])).contains("periodic (closed) curves"),);
}
