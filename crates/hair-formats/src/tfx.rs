//! AMD TressFX `.tfx` grooms, versions 4.x and 3.x (told apart by the version float at byte 0).
//!
//! Both hold `strand_count` strands of `vertices_per_strand` vertices each, root first, as `f32`
//! coordinates at a byte offset given in the header: `x, y, z, w` in 4.x (`w` 0 at pinned
//! vertices), `x, y, z` in 3.x. Only the positions are read: UVs, per-strand thickness scales and
//! colours (none in the sample files) and 3.x's follow-hair settings are left aside. The layouts
//! are in `shared/data/README.md`.

use std::path::Path;

use super::binary::{Bytes, f32_at, u32_at, vec3s};
use super::curves::{Curves, CurvesBuilder};
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::read_file;

/// Size of the TressFX 4.x header [bytes].
pub const TFX4_HEADER_LEN: u64 = 160;
/// Size of the TressFX 3.x header [bytes].
pub const TFX3_HEADER_LEN: u64 = 296;

/// Which TressFX layout a file uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// 4.x: 160-byte header, `f32 x, y, z, w` per vertex.
    V4,
    /// 3.x: 296-byte header, `f32 x, y, z` per vertex.
    V3,
}

impl Layout {
    fn header_len(self) -> u64 {
        match self {
            Layout::V4 => TFX4_HEADER_LEN,
            Layout::V3 => TFX3_HEADER_LEN,
        }
    }

    /// Bytes per vertex.
    fn stride(self) -> u64 {
        match self {
            Layout::V4 => 16,
            Layout::V3 => 12,
        }
    }

    /// Byte offset of the header field holding the positions' offset.
    fn position_offset_field(self) -> u64 {
        match self {
            Layout::V4 => 12,
            Layout::V3 => 144,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Layout::V4 => "TressFX 4",
            Layout::V3 => "TressFX 3",
        }
    }
}

/// Reads a TressFX `.tfx` groom (4.x or 3.x) from its bytes. Coordinates are taken as metres
/// before `options.axes`; TressFX has no unit field, and AMD's samples differ: the 4.x mohawk
/// (`ratboy_mohawk.tfx`) is in metres, the 3.x ponytail and `testhair1.tfx` are in centimetres
/// (read them with [`ImportAxes::scale_to_metres`](super::ImportAxes::scale_to_metres) = 0.01).
/// `vertices_per_strand` need not be a power of two. Errors name the byte offset; the data is called
/// [`FormatError::IN_MEMORY`].
pub fn read_tfx(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads a TressFX `.tfx` groom file; errors name the file. See [`read_tfx`].
pub fn read_tfx_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

fn read(data: &[u8], options: &ImportOptions) -> Result<Curves, FormatErrorKind> {
    options.axes.validate()?;
    let bytes = Bytes::new(data);
    let version_bytes = bytes.slice(0, 4, || "the TressFX version".into())?;
    if let Some(first_line) = text_first_line(data) {
        return Err(text_tfx_error(&first_line));
    }
    let version = f32_at(version_bytes, 0);
    let layout = if (3.0..4.0).contains(&version) {
        Layout::V3
    } else if (4.0..5.0).contains(&version) {
        Layout::V4
    } else {
        return Err(FormatErrorKind::UnsupportedVersion {
            format: "TressFX",
            version: version.to_string(),
            offset: 0,
            supported: "3.x and 4.x",
        });
    };
    let header = bytes.slice(0, u128::from(layout.header_len()), || {
        format!("the {} header", layout.name())
    })?;
    let strand_count = u32_at(header, 4);
    let vertices_per_strand = u32_at(header, 8);
    if vertices_per_strand == 0 {
        return Err(FormatErrorKind::InvalidField {
            field: "vertices_per_strand".into(),
            value: "0".into(),
            offset: 8,
            allowed: "1 or more (TressFX writes a power of two, 4..64)",
        });
    }
    let field = layout.position_offset_field();
    let mut start = u64::from(u32_at(header, field as usize));
    if start == 0 && layout == Layout::V3 {
        // Some 3.x exporters leave the offset at 0: the positions follow the header.
        start = TFX3_HEADER_LEN;
    }
    if start < layout.header_len() {
        return Err(FormatErrorKind::InvalidField {
            field: "offset of the vertex positions".into(),
            value: start.to_string(),
            offset: field,
            allowed: "past the header (0 means no positions)",
        });
    }
    let vertex_count = u64::from(strand_count) * u64::from(vertices_per_strand);
    let needed = u128::from(vertex_count) * u128::from(layout.stride());
    bytes.require_counts(
        || {
            format!(
                "strand_count {strand_count} × vertices_per_strand {vertices_per_strand} = \
                 {vertex_count} vertices"
            )
        },
        4,
        start,
        needed,
    )?;
    // Checked above: the vertices lie inside the file, so their count fits in memory. With no
    // strands, `vertices_per_strand` is unchecked: it sizes nothing.
    let positions = bytes.slice(start, needed, String::new)?;
    let mut builder = CurvesBuilder::new(options, vertex_count as usize, false, false);
    if strand_count == 0 {
        return builder.finish();
    }
    let stride = layout.stride() as usize;
    let strand_bytes = vertices_per_strand as usize * stride;
    let mut points = Vec::new();
    for (strand, chunk) in positions.chunks_exact(strand_bytes).enumerate() {
        points.clear();
        vec3s(chunk, stride, &mut points);
        let strand_start = start + (strand * strand_bytes) as u64;
        builder.push(&points, &[], &[], |_, j| {
            Location::Byte(strand_start + (j * stride) as u64)
        })?;
    }
    builder.finish()
}

/// The first line of `data` (at most 64 bytes, trimmed) when its first four bytes are printable
/// ASCII or whitespace: a text file, not a binary `.tfx` (whose first four bytes, a
/// little-endian `f32` version 3.x or 4.x, start with two zero bytes).
fn text_first_line(data: &[u8]) -> Option<String> {
    let head = data.get(..4)?;
    if !head
        .iter()
        .all(|b| b.is_ascii_graphic() || b.is_ascii_whitespace())
    {
        return None;
    }
    let line: Vec<u8> = data
        .iter()
        .take(64)
        .take_while(|&&b| b != b'\n' && b != b'\r')
        .copied()
        .collect();
    Some(String::from_utf8_lossy(&line).trim().to_string())
}

/// The error for a text file read as a binary `.tfx`: a TressFX 2.x text groom
/// (`version 2.0` on its first line, as FibermeshCurve2TressFX and the TressFX 2 SDK write them)
/// or some other text.
fn text_tfx_error(first_line: &str) -> FormatErrorKind {
    let mut words = first_line.split_whitespace();
    let what = match (words.next(), words.next()) {
        (Some(key), Some(version))
            if key.eq_ignore_ascii_case("version") && version.parse::<f32>().is_ok() =>
        {
            format!("`{first_line}` (a TressFX {version} text file)")
        }
        _ => format!("`{first_line}` (a text file)"),
    };
    FormatErrorKind::WrongMagic {
        format: "binary TressFX (3.x or 4.x)",
        found: what,
        expected: "a little-endian f32 version 3.x or 4.x (the binary .tfx AMD's TressFX 3 and 4 \
                   exporters write); a TressFX 2 text .tfx (FibermeshCurve2TressFX writes them) \
                   is not read: convert its strands to OBJ polylines (`v x y z` per vertex, one \
                   `l` line per strand) or a cyHair .hair file and read that",
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A TressFX 4 file of `strands` (all of the same length), with strand UVs after the positions.
    pub(crate) fn tfx4_bytes(strands: &[Vec<[f32; 3]>]) -> Vec<u8> {
        let count = strands.len() as u32;
        let per = strands.first().map_or(0, Vec::len) as u32;
        let mut bytes = Vec::new();
        bytes.extend(4.0f32.to_le_bytes());
        for value in [count, per, 160, 160 + count * per * 16, 0, 0, 0] {
            bytes.extend(value.to_le_bytes());
        }
        bytes.resize(160, 0);
        for strand in strands {
            for (j, p) in strand.iter().enumerate() {
                for c in p {
                    bytes.extend(c.to_le_bytes());
                }
                bytes.extend(if j < 2 { 0.0f32 } else { 1.0f32 }.to_le_bytes());
            }
        }
        for _ in strands {
            bytes.extend([0.5f32, 0.5].iter().flat_map(|v| v.to_le_bytes()));
        }
        bytes
    }

    /// A TressFX 3 file of `strands` (all of the same length).
    pub(crate) fn tfx3_bytes(strands: &[Vec<[f32; 3]>]) -> Vec<u8> {
        let mut bytes = Vec::new();
        bytes.extend(3.0f32.to_le_bytes());
        bytes.extend((strands.len() as u32).to_le_bytes());
        bytes.extend((strands.first().map_or(0, Vec::len) as u32).to_le_bytes());
        bytes.resize(144, 0);
        bytes.extend(296u32.to_le_bytes());
        bytes.resize(296, 0);
        for p in strands.iter().flatten() {
            for c in p {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes
    }

    pub(crate) fn two_strands() -> Vec<Vec<[f32; 3]>> {
        vec![
            vec![
                [0.0, 0.0, 0.0],
                [0.0, 0.1, 0.0],
                [0.0, 0.2, 0.01],
                [0.0, 0.3, 0.02],
            ],
            vec![
                [0.1, 0.0, 0.0],
                [0.1, -0.1, 0.0],
                [0.1, -0.2, 0.0],
                [0.1, -0.3, 0.0],
            ],
        ]
    }

    #[test]
    fn both_versions_read_the_same_strands() {
        let strands = two_strands();
        for bytes in [tfx4_bytes(&strands), tfx3_bytes(&strands)] {
            let curves = read_tfx(&bytes, &ImportOptions::default()).unwrap();
            assert_eq!(curves.curve_count(), 2);
            assert_eq!(curves.offsets, [0, 4, 8]);
            assert_eq!(curves.curve(1)[3], glam::Vec3::new(0.1, -0.3, 0.0));
            assert!(curves.skipped.is_empty() && curves.widths.is_none());
        }
    }

    #[test]
    fn a_zero_vertex_count_is_refused() {
        let mut bytes = tfx4_bytes(&two_strands());
        bytes[8..12].copy_from_slice(&0u32.to_le_bytes());
        let error = read_tfx(&bytes, &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: invalid vertices_per_strand = 0 at byte 8 (allowed: 1 or more (TressFX \
             writes a power of two, 4..64))"
        );
    }

    #[test]
    fn positions_inside_the_header_are_refused() {
        let mut bytes = tfx4_bytes(&two_strands());
        bytes[12..16].copy_from_slice(&100u32.to_le_bytes());
        let error = read_tfx(&bytes, &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: invalid offset of the vertex positions = 100 at byte 12 (allowed: past the \
             header (0 means no positions))"
        );
    }

    /// A TressFX 2.0 text groom (FibermeshCurve2TressFX's layout) is named as what it is, with
    /// what to convert it to, not read as a version float.
    #[test]
    fn a_tressfx_2_text_file_is_named_as_one() {
        let text = b"version 2.0\nscale 1.0\nnumStrands 1\nis sorted 1\n\
                     strand 0 numVerts 2 texcoord 0.0 0.0\n0, 0, 0\n0, 1, 0\n";
        let error = read_tfx(text, &ImportOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("`version 2.0` (a TressFX 2.0 text file)"),
            "{error}"
        );
        assert!(
            error.contains("not a binary TressFX (3.x or 4.x) file"),
            "{error}"
        );
        assert!(error.contains("OBJ polylines"), "{error}");
        assert!(!error.contains("unsupported TressFX version"), "{error}");
        let error = read_tfx(b"hello world", &ImportOptions::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains("`hello world` (a text file)"), "{error}");
        // A binary file of an unknown version still says so.
        let mut bytes = tfx4_bytes(&two_strands());
        bytes[..4].copy_from_slice(&7.0f32.to_le_bytes());
        let error = read_tfx(&bytes, &ImportOptions::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains("unsupported TressFX version 7"), "{error}");
    }
}
