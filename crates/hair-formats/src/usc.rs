//! USC-HairSalon `.data` grooms (Hu et al., "Single-view hair modeling using a hairstyle
//! database", 2015): `i32 strand_count`, then per strand `i32 n` and `f32 x, y, z` × n, in
//! metres. A strand of one vertex marks a scalp root without hair: it is skipped
//! ([`SkipReason::EmptyRoot`](super::SkipReason::EmptyRoot)) even under strict reading.

use std::path::Path;

use super::binary::{Bytes, i32_at, vec3s};
use super::curves::{Curves, CurvesBuilder};
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::read_file;

/// Reads a USC-HairSalon `.data` groom from its bytes (metres before `options.axes`). Errors name
/// the byte offset; the data is called [`FormatError::IN_MEMORY`].
pub fn read_usc_data(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads a USC-HairSalon `.data` groom file; errors name the file. See [`read_usc_data`].
pub fn read_usc_data_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

fn read(data: &[u8], options: &ImportOptions) -> Result<Curves, FormatErrorKind> {
    options.axes.validate()?;
    let bytes = Bytes::new(data);
    let strand_count = i32_at(bytes.slice(0, 4, || "the strand count".into())?, 0);
    let Ok(strand_count) = u32::try_from(strand_count) else {
        return Err(FormatErrorKind::InvalidField {
            field: "strand_count".into(),
            value: strand_count.to_string(),
            offset: 0,
            allowed: "0 or more",
        });
    };
    // Every strand has at least its vertex count.
    bytes.require_counts(
        || format!("strand_count {strand_count}"),
        0,
        4,
        4 * u128::from(strand_count),
    )?;
    // No count to size the points by before reading the strands: the vectors grow as points are
    // read, each read checked against the file (so they stay below the file's size).
    let mut builder = CurvesBuilder::new(options, 0, false, false);
    let mut points = Vec::new();
    let mut offset = 4u64;
    for strand in 0..strand_count {
        let count_at = offset;
        let count = i32_at(
            bytes.slice(offset, 4, || format!("the vertex count of strand {strand}"))?,
            0,
        );
        offset += 4;
        let Ok(count) = u32::try_from(count) else {
            return Err(FormatErrorKind::InvalidField {
                field: format!("vertex count of strand {strand}"),
                value: count.to_string(),
                offset: count_at,
                allowed: "0 or more",
            });
        };
        let len = 12 * u128::from(count);
        let coordinates = bytes.slice(offset, len, || {
            format!("the {count} vertices of strand {strand}")
        })?;
        if count == 1 {
            builder.push_empty_root();
        } else {
            points.clear();
            vec3s(coordinates, 12, &mut points);
            let start = offset;
            builder.push(&points, &[], &[], |_, j| {
                Location::Byte(start + 12 * j as u64)
            })?;
        }
        offset += len as u64;
    }
    if offset < bytes.len() {
        return Err(FormatErrorKind::TrailingBytes {
            offset,
            count: bytes.len() - offset,
        });
    }
    builder.finish()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::SkipReason;

    /// A `.data` file of `strands`.
    pub(crate) fn usc_bytes(strands: &[Vec<[f32; 3]>]) -> Vec<u8> {
        let mut bytes = Vec::new();
        bytes.extend((strands.len() as i32).to_le_bytes());
        for strand in strands {
            bytes.extend((strand.len() as i32).to_le_bytes());
            for c in strand.iter().flatten() {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes
    }

    pub(crate) fn strands_with_empty_roots() -> Vec<Vec<[f32; 3]>> {
        vec![
            vec![[0.0, 1.6, 0.0]],
            vec![[0.0, 1.7, 0.0], [0.0, 1.65, 0.05], [0.0, 1.6, 0.08]],
            vec![[0.1, 1.6, 0.0]],
            vec![[0.1, 1.7, 0.0], [0.12, 1.6, 0.0]],
        ]
    }

    #[test]
    fn empty_roots_are_skipped_and_counted_even_when_strict() {
        let bytes = usc_bytes(&strands_with_empty_roots());
        let curves = read_usc_data(&bytes, &ImportOptions::strict()).unwrap();
        assert_eq!(curves.offsets, [0, 3, 5]);
        assert_eq!(curves.skipped.len(), 2);
        assert_eq!(curves.skipped[1].index, 2);
        assert_eq!(curves.skipped[1].reason, SkipReason::EmptyRoot);
    }

    #[test]
    fn a_negative_vertex_count_is_named() {
        let mut bytes = usc_bytes(&strands_with_empty_roots());
        // Strand 1's count follows strand 0 (4 + 12 bytes) and the strand count.
        bytes[20..24].copy_from_slice(&(-3i32).to_le_bytes());
        let error = read_usc_data(&bytes, &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: invalid vertex count of strand 1 = -3 at byte 20 (allowed: 0 or more)"
        );
    }

    #[test]
    fn a_file_of_empty_roots_is_an_empty_groom() {
        let bytes = usc_bytes(&[vec![[0.0; 3]], vec![[1.0; 3]]]);
        let error = read_usc_data(&bytes, &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: no usable curve: the file has 2 curves, 2 of them skipped"
        );
    }
}
