//! Cem Yuksel's cyHair `.hair` format, read and written: a 128-byte header (`"HAIR"`, hair and
//! point counts, a bit field of the arrays present, defaults) followed by the arrays present, in
//! the order segments (`u16` per hair), points (`f32 xyz`), thickness, transparency and colours
//! (`f32 rgb`) per point. The layout is in `shared/data/README.md`.
//!
//! Read: thickness becomes [`Curves::widths`] (the header's default thickness where the file has
//! no thickness array and that default is > 0), colours become [`Curves::colors`] (only from the
//! per-point array); transparency is checked for size and left aside. Written: segments, points,
//! and thickness and colours where the curves have them, so a write then a read gives the same
//! curves bit for bit.

use std::io::{self, Write};
use std::path::Path;

use glam::Vec3;

use super::binary::{Bytes, f32_at, f32s, u16_at, u32_at, vec3s};
use super::curves::{Curves, CurvesBuilder, Field};
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::read_file;
use crate::obj::write_file_atomically;

/// Size of the cyHair header [bytes].
pub const HAIR_HEADER_LEN: u64 = 128;

/// Bit of the `arrays` field: a `u16` segment count per hair.
const SEGMENTS: u32 = 1;
/// Bit of the `arrays` field: `f32 x, y, z` per point.
const POINTS: u32 = 2;
/// Bit of the `arrays` field: `f32` thickness per point.
const THICKNESS: u32 = 4;
/// Bit of the `arrays` field: `f32` transparency per point.
const TRANSPARENCY: u32 = 8;
/// Bit of the `arrays` field: `f32 r, g, b` per point.
const COLORS: u32 = 16;

/// What the header says: counts, arrays present and where each array starts.
struct Layout {
    hair_count: u32,
    point_count: u32,
    arrays: u32,
    default_segments: u32,
    default_thickness: f32,
    segments_at: u64,
    points_at: u64,
    thickness_at: u64,
    colors_at: u64,
}

impl Layout {
    /// Reads the header and places the arrays, checking their total size against the file.
    fn read(bytes: &Bytes) -> Result<Layout, FormatErrorKind> {
        let signature = bytes.slice(0, 4, || "the cyHair signature".into())?;
        if signature != b"HAIR" {
            return Err(FormatErrorKind::WrongMagic {
                format: "cyHair",
                found: format!("\"{}\"", signature.escape_ascii()),
                expected: "\"HAIR\"",
            });
        }
        let header = bytes.slice(0, u128::from(HAIR_HEADER_LEN), || {
            "the cyHair header".into()
        })?;
        let hair_count = u32_at(header, 4);
        let point_count = u32_at(header, 8);
        let arrays = u32_at(header, 12);
        if arrays & POINTS == 0 {
            return Err(FormatErrorKind::InvalidField {
                field: "arrays".into(),
                value: format!("{arrays:#b}"),
                offset: 12,
                allowed: "the points bit (2) set: a cyHair file always has points",
            });
        }
        let (hairs, points) = (u64::from(hair_count), u64::from(point_count));
        let has = |bit: u32| arrays & bit != 0;
        let size = |bit: u32, bytes_each: u64| if has(bit) { bytes_each } else { 0 };
        let segments_at = HAIR_HEADER_LEN;
        let points_at = segments_at + size(SEGMENTS, 2 * hairs);
        let thickness_at = points_at + 12 * points;
        let transparency_at = thickness_at + size(THICKNESS, 4 * points);
        let colors_at = transparency_at + size(TRANSPARENCY, 4 * points);
        let end = colors_at + size(COLORS, 12 * points);
        bytes.require_counts(
            || {
                format!(
                    "hair_count {hair_count}, point_count {point_count} with arrays \
                     {arrays:#07b}"
                )
            },
            4,
            HAIR_HEADER_LEN,
            u128::from(end - HAIR_HEADER_LEN),
        )?;
        if bytes.len() > end {
            return Err(FormatErrorKind::TrailingBytes {
                offset: end,
                count: bytes.len() - end,
            });
        }
        Ok(Layout {
            hair_count,
            point_count,
            arrays,
            default_segments: u32_at(header, 16),
            default_thickness: f32_at(header, 20),
            segments_at,
            points_at,
            thickness_at,
            colors_at,
        })
    }

    fn has(&self, bit: u32) -> bool {
        self.arrays & bit != 0
    }

    /// Points per hair: from the segments array, else the default; checked against the point
    /// count.
    fn hair_lengths<'a>(&self, bytes: &Bytes<'a>) -> Result<HairLengths<'a>, FormatErrorKind> {
        let hairs = u64::from(self.hair_count);
        if self.has(SEGMENTS) {
            let segments = bytes.slice(self.segments_at, u128::from(2 * hairs), String::new)?;
            let total: u64 = segments
                .chunks_exact(2)
                .map(|s| u64::from(u16_at(s, 0)) + 1)
                .sum();
            if total != u64::from(self.point_count) {
                return Err(FormatErrorKind::InconsistentCounts {
                    message: format!(
                        "the segments array gives the {hairs} hairs {total} points, but \
                         point_count is {}",
                        self.point_count
                    ),
                    offset: 4,
                });
            }
            Ok(HairLengths::Array(segments))
        } else {
            let per_hair = u64::from(self.default_segments) + 1;
            let total = u128::from(hairs) * u128::from(per_hair);
            if total != u128::from(self.point_count) {
                return Err(FormatErrorKind::InconsistentCounts {
                    message: format!(
                        "hair_count {hairs} × (default_segments {} + 1) = {total} points, but \
                         point_count is {}",
                        self.default_segments, self.point_count
                    ),
                    offset: 4,
                });
            }
            Ok(HairLengths::Default(per_hair as usize))
        }
    }
}

/// Points per hair.
enum HairLengths<'a> {
    /// `u16` segment counts, one per hair.
    Array(&'a [u8]),
    /// The same for every hair.
    Default(usize),
}

impl HairLengths<'_> {
    fn points(&self, hair: usize) -> usize {
        match self {
            HairLengths::Array(segments) => usize::from(u16_at(segments, 2 * hair)) + 1,
            HairLengths::Default(points) => *points,
        }
    }
}

/// Reads a cyHair `.hair` groom from its bytes. Coordinates and thickness are taken as metres
/// before `options.axes` (cyHair has no unit; many files are in centimetres: set
/// [`ImportAxes::scale_to_metres`](super::ImportAxes::scale_to_metres)). Errors name the byte
/// offset; the data is called [`FormatError::IN_MEMORY`].
pub fn read_hair(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads a cyHair `.hair` groom file; errors name the file. See [`read_hair`].
pub fn read_hair_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

fn read(data: &[u8], options: &ImportOptions) -> Result<Curves, FormatErrorKind> {
    options.axes.validate()?;
    let bytes = Bytes::new(data);
    let layout = Layout::read(&bytes)?;
    let lengths = layout.hair_lengths(&bytes)?;
    let point_count = u128::from(layout.point_count);
    let points = bytes.slice(layout.points_at, 12 * point_count, String::new)?;
    let thickness = if layout.has(THICKNESS) {
        Some(bytes.slice(layout.thickness_at, 4 * point_count, String::new)?)
    } else {
        None
    };
    let default_width = layout.default_thickness;
    let widths = thickness.is_some() || (default_width.is_finite() && default_width > 0.0);
    let colors = if layout.has(COLORS) {
        Some(bytes.slice(layout.colors_at, 12 * point_count, String::new)?)
    } else {
        None
    };
    let mut builder = CurvesBuilder::new(
        options,
        layout.point_count as usize,
        widths,
        colors.is_some(),
    );
    let (mut hair_points, mut hair_widths, mut hair_colors) = (Vec::new(), Vec::new(), Vec::new());
    let mut first = 0usize;
    for hair in 0..layout.hair_count as usize {
        let count = lengths.points(hair);
        let end = first + count;
        hair_points.clear();
        hair_widths.clear();
        hair_colors.clear();
        // In range: the hair lengths add up to the point count, whose arrays are in the file.
        vec3s(
            points.get(12 * first..12 * end).unwrap_or_default(),
            12,
            &mut hair_points,
        );
        match thickness {
            Some(thickness) => f32s(
                thickness.get(4 * first..4 * end).unwrap_or_default(),
                &mut hair_widths,
            ),
            None if widths => hair_widths.resize(count, default_width),
            None => {}
        }
        if let Some(colors) = colors {
            vec3s(
                colors.get(12 * first..12 * end).unwrap_or_default(),
                12,
                &mut hair_colors,
            );
        }
        let locate = |field: Field, j: usize| {
            let point = (first + j) as u64;
            Location::Byte(match field {
                Field::Position => layout.points_at + 12 * point,
                Field::Width if thickness.is_some() => layout.thickness_at + 4 * point,
                Field::Width => 20,
                Field::Colour => layout.colors_at + 12 * point,
            })
        };
        builder.push(&hair_points, &hair_widths, &hair_colors, locate)?;
        first = end;
    }
    builder.finish()
}

fn invalid_input(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

/// Checks that `curves` can be written as cyHair: a valid layout
/// ([`Curves::check_layout`]), at most `u32::MAX` curves and points, and every curve of 1 to
/// 65,536 points (a `u16` segment count).
fn check_writable(curves: &Curves) -> io::Result<()> {
    curves.check_layout().map_err(invalid_input)?;
    if u32::try_from(curves.curve_count()).is_err() || u32::try_from(curves.point_count()).is_err()
    {
        return Err(invalid_input(format!(
            "{} curves of {} points: cyHair counts are u32",
            curves.curve_count(),
            curves.point_count()
        )));
    }
    for (index, curve) in curves.iter().enumerate() {
        if curve.is_empty() || curve.len() > usize::from(u16::MAX) + 1 {
            return Err(invalid_input(format!(
                "curve {index} has {} points; cyHair holds 1 to 65536 per curve",
                curve.len()
            )));
        }
    }
    Ok(())
}

/// Writes `curves` [m] as a cyHair file to `writer`: segments and points always, thickness where
/// the curves have widths, colours where they have colours; no transparency. The header's default
/// thickness is 0 (no width) and its default colour mid grey. Checks everything before writing
/// anything: an invalid layout, a non-finite value or a curve of 0 or more than 65,536 points is
/// an `InvalidInput` error.
pub fn write_hair_to<W: Write>(writer: &mut W, curves: &Curves) -> io::Result<()> {
    check_writable(curves)?;
    let mut arrays = SEGMENTS | POINTS;
    if curves.widths.is_some() {
        arrays |= THICKNESS;
    }
    if curves.colors.is_some() {
        arrays |= COLORS;
    }
    let mut header = Vec::with_capacity(HAIR_HEADER_LEN as usize);
    header.extend_from_slice(b"HAIR");
    header.extend((curves.curve_count() as u32).to_le_bytes());
    header.extend((curves.point_count() as u32).to_le_bytes());
    header.extend(arrays.to_le_bytes());
    header.extend(0u32.to_le_bytes()); // default segments: every hair has its own
    header.extend(0f32.to_le_bytes()); // default thickness
    header.extend(0f32.to_le_bytes()); // default transparency
    for channel in [0.5f32; 3] {
        header.extend(channel.to_le_bytes());
    }
    header.extend_from_slice(b"hairlod cyHair export, metres");
    header.resize(HAIR_HEADER_LEN as usize, 0);
    writer.write_all(&header)?;
    let mut buffer = Vec::with_capacity(64 * 1024);
    /// Passes the buffer on when it is nearly full (or when `force`).
    fn flush<W: Write>(buffer: &mut Vec<u8>, writer: &mut W, force: bool) -> io::Result<()> {
        if force || buffer.len() >= 60 * 1024 {
            writer.write_all(buffer)?;
            buffer.clear();
        }
        Ok(())
    }
    for curve in curves.iter() {
        buffer.extend(((curve.len() - 1) as u16).to_le_bytes());
        flush(&mut buffer, writer, false)?;
    }
    for p in &curves.points {
        for c in p.to_array() {
            buffer.extend(c.to_le_bytes());
        }
        flush(&mut buffer, writer, false)?;
    }
    for w in curves.widths.iter().flatten() {
        buffer.extend(w.to_le_bytes());
        flush(&mut buffer, writer, false)?;
    }
    for c in curves.colors.iter().flatten() {
        for channel in Vec3::to_array(c) {
            buffer.extend(channel.to_le_bytes());
        }
        flush(&mut buffer, writer, false)?;
    }
    flush(&mut buffer, writer, true)
}

/// [`write_hair_to`] into a new byte vector.
pub fn write_hair_bytes(curves: &Curves) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    write_hair_to(&mut bytes, curves)?;
    Ok(bytes)
}

/// Writes `curves` [m] as the cyHair file at `path` ([`write_hair_to`]), atomically: the file is
/// either replaced whole or left as it was. Errors name the path.
pub fn write_hair(path: impl AsRef<Path>, curves: &Curves) -> io::Result<()> {
    let path = path.as_ref();
    check_writable(curves)
        .map_err(|e| io::Error::new(e.kind(), format!("writing {}: {e}", path.display())))?;
    write_file_atomically(path, |writer| write_hair_to(writer, curves))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Three curves with widths and colours.
    pub(crate) fn sample_curves() -> Curves {
        let points = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.01, 0.001),
            Vec3::new(0.01, 0.0, 0.0),
            Vec3::new(0.01, -0.02, 0.0),
            Vec3::new(0.01, -0.04, 0.003),
            Vec3::new(-0.01, 0.1, 0.2),
            Vec3::new(-0.01, 0.1, 0.3),
        ];
        Curves {
            widths: Some((0..7).map(|i| 1e-4 * (7 - i) as f32).collect()),
            colors: Some(
                (0..7)
                    .map(|i| Vec3::new(0.1 * i as f32, 0.2, 0.3))
                    .collect(),
            ),
            points,
            offsets: vec![0, 2, 5, 7],
            skipped: Vec::new(),
        }
    }

    #[test]
    fn a_written_file_reads_back_bit_for_bit() {
        let curves = sample_curves();
        let bytes = write_hair_bytes(&curves).unwrap();
        assert_eq!(bytes.len(), 128 + 3 * 2 + 7 * (12 + 4 + 12));
        let read = read_hair(&bytes, &ImportOptions::default()).unwrap();
        assert_eq!(read, curves);
        let bare = Curves {
            widths: None,
            colors: None,
            ..curves
        };
        let read = read_hair(&write_hair_bytes(&bare).unwrap(), &ImportOptions::strict()).unwrap();
        assert_eq!(read, bare);
    }

    #[test]
    fn the_default_thickness_and_segments_apply_without_arrays() {
        let mut bytes = Vec::new();
        bytes.extend_from_slice(b"HAIR");
        for value in [2u32, 6, POINTS, 2] {
            bytes.extend(value.to_le_bytes());
        }
        bytes.extend(0.002f32.to_le_bytes());
        bytes.resize(128, 0);
        for i in 0..6 {
            for c in [i as f32, 0.0, 0.0] {
                bytes.extend(c.to_le_bytes());
            }
        }
        let options = ImportOptions::with_axes(crate::ImportAxes {
            scale_to_metres: 0.01,
            ..Default::default()
        });
        let curves = read_hair(&bytes, &options).unwrap();
        assert_eq!(curves.offsets, [0, 3, 6]);
        assert_eq!(curves.points[4], Vec3::new(0.04, 0.0, 0.0));
        assert_eq!(curves.widths, Some(vec![0.002 * 0.01; 6]));
        assert_eq!(curves.colors, None);
    }

    #[test]
    fn curves_that_cyhair_cannot_hold_are_refused_before_writing() {
        let mut curves = sample_curves();
        curves.points[3].z = f32::NAN;
        let mut out = Vec::new();
        let error = write_hair_to(&mut out, &curves).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        assert!(
            error.to_string().contains("point 3 is not finite"),
            "{error}"
        );
        assert!(out.is_empty());
        let mut curves = sample_curves();
        curves.offsets = vec![0, 0, 7];
        let error = write_hair_bytes(&curves).unwrap_err();
        assert!(
            error.to_string().contains("curve 0 has 0 points"),
            "{error}"
        );
        let dir = std::env::temp_dir().join(format!("hairlod-cyhair-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("refused.hair");
        let error = write_hair(&path, &curves).unwrap_err();
        assert!(error.to_string().starts_with("writing "), "{error}");
        assert!(!path.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn segments_that_disagree_with_the_point_count_are_refused() {
        let mut bytes = write_hair_bytes(&sample_curves()).unwrap();
        bytes[128..130].copy_from_slice(&5u16.to_le_bytes());
        let error = read_hair(&bytes, &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: inconsistent counts at byte 4: the segments array gives the 3 hairs 11 \
             points, but point_count is 7"
        );
    }

    #[test]
    fn bytes_after_the_arrays_are_refused() {
        let mut bytes = write_hair_bytes(&sample_curves()).unwrap();
        let len = bytes.len() as u64;
        bytes.extend([0; 5]);
        let error = read_hair(&bytes, &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            format!("<memory>: 5 unexpected bytes after the data, from byte {len}")
        );
    }

    #[test]
    fn a_file_without_points_is_refused() {
        let mut bytes = write_hair_bytes(&sample_curves()).unwrap();
        bytes[12..16].copy_from_slice(&SEGMENTS.to_le_bytes());
        let error = read_hair(&bytes, &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: invalid arrays = 0b1 at byte 12 (allowed: the points bit (2) set: a cyHair \
             file always has points)"
        );
    }
}
