//! The Ogawa container of an Alembic `.abc` archive, walked and checked before the `ogawa-rs`
//! crate reads it: `ogawa-rs` allocates buffers sized from the file's counts before it checks them
//! against the file's length, so every count and offset is checked here first.
//!
//! The layout: a 16-byte header (`Ogawa`, a frozen byte `0xff` once the writer closed the file, a
//! big-endian `u16` version 1, the root group's `u64` offset), then groups (a `u64` child count
//! and as many `u64` child offsets; the top bit marks a data child, offset 0 an empty group or
//! empty data) and data blocks (a `u64` size and as many bytes); all little-endian but the
//! version. Every group is walked once, at most
//! [`MAX_DEPTH`] deep and never inside itself; every data block must lie inside the file.

use std::collections::HashSet;

use super::binary::Bytes;
use super::error::{FormatErrorKind, Location};

/// Size of the Ogawa header [bytes].
pub(crate) const HEADER_LEN: u64 = 16;
/// Deepest group nesting read (an Alembic object takes two levels per generation).
pub(crate) const MAX_DEPTH: usize = 256;
/// The bit of a child offset that marks a data block.
pub(crate) const DATA_BIT: u64 = 1 << 63;

/// The little-endian `u64` at byte `at` of `slice` (0 when out of range: check first).
pub(crate) fn u64_at(slice: &[u8], at: usize) -> u64 {
    let mut bytes = [0; 8];
    if let Some(source) = at.checked_add(8).and_then(|end| slice.get(at..end)) {
        bytes.copy_from_slice(source);
    }
    u64::from_le_bytes(bytes)
}

/// An error in the archive's structure at byte `offset`.
pub(crate) fn structure(
    element: impl Into<String>,
    message: String,
    offset: u64,
) -> FormatErrorKind {
    FormatErrorKind::Alembic {
        element: element.into(),
        message,
        location: Location::Byte(offset),
    }
}

/// Checks the header and returns the root group's offset.
pub(crate) fn check_header(bytes: &Bytes) -> Result<u64, FormatErrorKind> {
    let available = bytes.available(0).min(5);
    let signature = bytes.slice(0, u128::from(available), String::new)?;
    if signature != b"Ogawa" {
        return Err(FormatErrorKind::WrongMagic {
            format: "binary (Ogawa) Alembic",
            found: format!("\"{}\"", signature.escape_ascii()),
            expected: "\"Ogawa\" (an HDF5 Alembic archive is not read)",
        });
    }
    let header = bytes.slice(0, u128::from(HEADER_LEN), || "the Ogawa header".into())?;
    if header[5] != 0xff {
        return Err(FormatErrorKind::InvalidField {
            field: "frozen flag".into(),
            value: format!("{:#04x}", header[5]),
            offset: 5,
            allowed: "0xff: an archive its writer closed",
        });
    }
    // Written high byte first (`0, 1`), unlike every other number of the format.
    let version = u16::from_be_bytes([header[6], header[7]]);
    if version != 1 {
        return Err(FormatErrorKind::UnsupportedVersion {
            format: "Ogawa",
            version: version.to_string(),
            offset: 6,
            supported: "1",
        });
    }
    Ok(u64_at(header, 8))
}

/// The child offsets of the group at `offset` (none for offset 0), checked against the file.
pub(crate) fn group_children(bytes: &Bytes, offset: u64) -> Result<Vec<u64>, FormatErrorKind> {
    if offset == 0 {
        return Ok(Vec::new());
    }
    let count = bytes.slice(offset, 8, || "the child count of an Ogawa group".into())?;
    let count = u64_at(count, 0);
    bytes.require_counts(
        || format!("child_count {count} of the Ogawa group"),
        offset,
        offset + 8,
        u128::from(count) * 8,
    )?;
    let children = bytes.slice(offset + 8, u128::from(count) * 8, String::new)?;
    Ok(children.chunks_exact(8).map(|c| u64_at(c, 0)).collect())
}

/// The bytes of the data child `child` (empty for empty data), checked against the file;
/// `Ok(None)` when `child` is a group.
pub(crate) fn data_block<'a>(
    bytes: &Bytes<'a>,
    child: u64,
) -> Result<Option<(u64, &'a [u8])>, FormatErrorKind> {
    if child & DATA_BIT == 0 {
        return Ok(None);
    }
    let at = child & !DATA_BIT;
    if at == 0 {
        return Ok(Some((0, &[])));
    }
    let size = bytes.slice(at, 8, || "the size of an Ogawa data block".into())?;
    let size = u64_at(size, 0);
    bytes.require_counts(
        || format!("size {size} of the Ogawa data block"),
        at,
        at + 8,
        u128::from(size),
    )?;
    Ok(Some((
        at + 8,
        bytes.slice(at + 8, u128::from(size), String::new)?,
    )))
}

/// Walks every group from `root`: each child offset and data size inside the file, no group
/// inside itself, at most [`MAX_DEPTH`] deep.
pub(crate) fn check_container(bytes: &Bytes, root: u64) -> Result<(), FormatErrorKind> {
    let mut walk = Walk {
        bytes,
        done: HashSet::new(),
        open: HashSet::new(),
    };
    walk.group(root, 0)
}

struct Walk<'b, 'a> {
    bytes: &'b Bytes<'a>,
    /// Groups checked.
    done: HashSet<u64>,
    /// Groups being checked (the path from the root).
    open: HashSet<u64>,
}

impl Walk<'_, '_> {
    fn group(&mut self, offset: u64, depth: usize) -> Result<(), FormatErrorKind> {
        if offset == 0 || self.done.contains(&offset) {
            return Ok(());
        }
        if self.open.contains(&offset) {
            return Err(structure(
                "Ogawa group",
                "the group contains itself (a cycle of group offsets)".into(),
                offset,
            ));
        }
        if depth >= MAX_DEPTH {
            return Err(structure(
                "Ogawa group",
                format!("groups nested deeper than {MAX_DEPTH} levels"),
                offset,
            ));
        }
        let children = group_children(self.bytes, offset)?;
        self.open.insert(offset);
        for child in children {
            if data_block(self.bytes, child)?.is_none() {
                self.group(child, depth + 1)?;
            }
        }
        self.open.remove(&offset);
        self.done.insert(offset);
        Ok(())
    }
}
