//! Checks of a binary USD crate file (`.usdc`) before the `openusd` crate reads it: the crate
//! allocates buffers sized by the counts it reads (`vec![0; count]`) before it reads the data, so
//! every count that it would trust is compared with the bytes left in the file first.
//!
//! Checked here: the bootstrap header (magic, version, table-of-contents offset), the table of
//! contents (section count, each section inside the file), and every count and compressed size of
//! the six structural sections (`TOKENS`, `STRINGS`, `FIELDS`, `FIELDSETS`, `PATHS`, `SPECS`);
//! then, before each value is decoded ([`check_value`]), the element count of an array, of a token,
//! string or path vector, and of a time-sample map with its times and values. A count passes when
//! the bytes left could hold it: raw, one byte per element at least; LZ4-compressed, the format's
//! largest expansion (255 to 1, and 4 integers per byte of integer coding). So the largest
//! allocation is a fixed multiple of the file's length, never a count read from it.
//!
//! Not checked (the crate's own decoding, which the caller runs under `catch_unwind`): indices
//! into the token, string, path and field tables, the integer coding itself, and values of other
//! types (dictionaries, list ops), which the curve and mesh readers never decode.

use super::error::{FormatErrorKind, Location};

/// The crate file's signature.
pub(crate) const MAGIC: &[u8; 8] = b"PXR-USDC";
/// Bytes of the bootstrap header: magic, version, table-of-contents offset, reserved.
const HEADER_LEN: u64 = 32;
/// Bytes of a table-of-contents entry: a 16-byte name, start and size.
const SECTION_LEN: u64 = 32;
/// LZ4's largest expansion of a compressed byte.
const LZ4_RATIO: u128 = 255;
/// The `openusd` crate reads files of version 0.4.0 to 0.12.x.
const SUPPORTED: &str = "0.4.0 to 0.12.x (write it with a newer USD, or `usdcat` it to .usda)";

/// The version of a crate file: (major, minor, patch).
pub(crate) type Version = (u8, u8, u8);

/// The file's bytes, read little-endian with every read checked.
struct Bytes<'a> {
    bytes: &'a [u8],
}

impl Bytes<'_> {
    fn len(&self) -> u64 {
        self.bytes.len() as u64
    }

    /// The `N` bytes at `offset`, or a truncation error naming `what`.
    fn array<const N: usize>(&self, offset: u64, what: &str) -> Result<[u8; N], FormatErrorKind> {
        let start = usize::try_from(offset).ok();
        start
            .and_then(|s| self.bytes.get(s..s.checked_add(N)?))
            .and_then(|b| b.try_into().ok())
            .ok_or_else(|| FormatErrorKind::Truncated {
                what: what.to_owned(),
                offset,
                needed: N as u128,
                available: self.len().saturating_sub(offset),
            })
    }

    fn u64(&self, offset: u64, what: &str) -> Result<u64, FormatErrorKind> {
        self.array::<8>(offset, what).map(u64::from_le_bytes)
    }

    fn u32(&self, offset: u64, what: &str) -> Result<u32, FormatErrorKind> {
        self.array::<4>(offset, what).map(u32::from_le_bytes)
    }
}

/// An error for `what = value` at `offset` needing `needed` bytes from `start` to `end`.
fn too_large(
    what: String,
    offset: u64,
    needed: u128,
    start: u64,
    file_len: u64,
) -> FormatErrorKind {
    FormatErrorKind::CountTooLarge {
        what,
        offset,
        needed,
        start,
        file_len,
    }
}

/// Checks the header, the table of contents and the structural sections; returns the version.
pub(crate) fn check_structure(bytes: &[u8]) -> Result<Version, FormatErrorKind> {
    let file = Bytes { bytes };
    if !bytes.starts_with(MAGIC) {
        let start = &bytes[..bytes.len().min(8)];
        return Err(FormatErrorKind::WrongMagic {
            format: "USD crate",
            found: format!("\"{}\"", start.escape_ascii()),
            expected: "\"PXR-USDC\"",
        });
    }
    let version_bytes = file.array::<8>(8, "the crate header's version")?;
    let version = (version_bytes[0], version_bytes[1], version_bytes[2]);
    if version.0 != 0 || version.1 < 4 || version.1 > 12 {
        return Err(FormatErrorKind::UnsupportedVersion {
            format: "USD crate",
            version: format!("{}.{}.{}", version.0, version.1, version.2),
            offset: 8,
            supported: SUPPORTED,
        });
    }
    let toc = file.u64(16, "the crate header's table-of-contents offset")?;
    if toc < HEADER_LEN {
        return Err(FormatErrorKind::InvalidField {
            field: "table-of-contents offset".into(),
            value: toc.to_string(),
            offset: 16,
            allowed: "an offset after the 32-byte header",
        });
    }
    let count = file.u64(toc, "the crate's section count")?;
    if count == 0 || count >= 64 {
        return Err(FormatErrorKind::InvalidField {
            field: "section count".into(),
            value: count.to_string(),
            offset: toc,
            allowed: "1 to 63",
        });
    }
    let entries = toc + 8;
    let needed = u128::from(count) * u128::from(SECTION_LEN);
    if needed > u128::from(file.len().saturating_sub(entries)) {
        return Err(too_large(
            format!("section count = {count}"),
            toc,
            needed,
            entries,
            file.len(),
        ));
    }
    for i in 0..count {
        let at = entries + i * SECTION_LEN;
        let name = file.array::<16>(at, "a section name")?;
        let name_len = name.iter().position(|&b| b == 0).unwrap_or(16);
        let name = String::from_utf8_lossy(&name[..name_len]).into_owned();
        let start = file.u64(at + 16, "a section start")?;
        let size = file.u64(at + 24, "a section size")?;
        if u128::from(start) + u128::from(size) > u128::from(file.len()) {
            return Err(too_large(
                format!("section {name} (size {size})"),
                at + 24,
                u128::from(size),
                start,
                file.len(),
            ));
        }
        let section = Section {
            file: &file,
            name: &name,
            end: start + size,
        };
        match name.as_str() {
            "TOKENS" => section.tokens(start)?,
            "STRINGS" => section.strings(start)?,
            "FIELDS" => section.blocks(start, &[Block::Ints, Block::Raw(8)])?,
            "FIELDSETS" => section.blocks(start, &[Block::Ints])?,
            "PATHS" => section.paths(start)?,
            "SPECS" => section.blocks(start, &[Block::Ints, Block::Ints, Block::Ints])?,
            _ => {}
        }
    }
    Ok(version)
}

/// What a compressed block decodes to.
#[derive(Clone, Copy)]
enum Block {
    /// Integers in Pixar's integer coding (at least 4 per decoded byte).
    Ints,
    /// Raw elements of this many bytes.
    Raw(u128),
}

/// A structural section being checked.
struct Section<'a> {
    file: &'a Bytes<'a>,
    name: &'a str,
    /// Offset just past the section.
    end: u64,
}

impl Section<'_> {
    /// The u64 count at `offset`, inside the section.
    fn count(&self, offset: u64, what: &str) -> Result<u64, FormatErrorKind> {
        if offset.saturating_add(8) > self.end {
            return Err(FormatErrorKind::Truncated {
                what: format!("the {what} of section {}", self.name),
                offset,
                needed: 8,
                available: self.end.saturating_sub(offset),
            });
        }
        self.file.u64(offset, what)
    }

    /// Checks the compressed block at `offset` that must decode to `count` elements of `block`;
    /// returns the offset after it.
    fn block(&self, offset: u64, count: u64, block: Block) -> Result<u64, FormatErrorKind> {
        let compressed = self.count(offset, "compressed size")?;
        let data = offset + 8;
        if u128::from(compressed) > u128::from(self.end - data) {
            return Err(too_large(
                format!("compressed size = {compressed} in section {}", self.name),
                offset,
                u128::from(compressed),
                data,
                self.file.len(),
            ));
        }
        let most = match block {
            Block::Ints => 4 * LZ4_RATIO * u128::from(compressed) + 4,
            Block::Raw(size) => LZ4_RATIO * u128::from(compressed) / size + 1,
        };
        if u128::from(count) > most {
            return Err(too_large(
                format!("count = {count} in section {}", self.name),
                offset,
                u128::from(count),
                data,
                self.file.len(),
            ));
        }
        Ok(data + compressed)
    }

    /// A count, then one compressed block per entry of `blocks`, each of that many elements.
    fn blocks(&self, start: u64, blocks: &[Block]) -> Result<(), FormatErrorKind> {
        let count = self.count(start, "element count")?;
        let mut at = start + 8;
        for &block in blocks {
            at = self.block(at, count, block)?;
        }
        Ok(())
    }

    /// Token count, decompressed size, then a compressed block of that many bytes.
    fn tokens(&self, start: u64) -> Result<(), FormatErrorKind> {
        let size = self.count(start + 8, "decompressed size")?;
        self.block(start + 16, size, Block::Raw(1)).map(|_| ())
    }

    /// A count of 4-byte string indices, stored raw.
    fn strings(&self, start: u64) -> Result<(), FormatErrorKind> {
        let count = self.count(start, "string count")?;
        let needed = u128::from(count) * 4;
        if needed > u128::from(self.end - start - 8) {
            return Err(too_large(
                format!("string count = {count}"),
                start,
                needed,
                start + 8,
                self.file.len(),
            ));
        }
        Ok(())
    }

    /// The path count (a table the crate allocates), then three coded blocks.
    fn paths(&self, start: u64) -> Result<(), FormatErrorKind> {
        let paths = self.count(start, "path count")?;
        let room = u128::from(self.end - start);
        if u128::from(paths) > 4 * LZ4_RATIO * room {
            return Err(too_large(
                format!("path count = {paths}"),
                start,
                u128::from(paths),
                start + 8,
                self.file.len(),
            ));
        }
        self.blocks(start + 8, &[Block::Ints, Block::Ints, Block::Ints])
    }
}

/// Type codes of the crate's value representations that this check follows.
const TIME_SAMPLES: u64 = 46;
const DOUBLE_VECTOR: u64 = 48;
const COUNTED_VECTORS: [u64; 3] = [40, 41, 50]; // path, token and string vectors
/// Types whose values hold counts this module does not check: dictionaries and list ops (31 to
/// 39), variant selection maps, payloads, layer offset vectors, opaque values, payload list ops
/// and relocates.
const UNCHECKED: [u64; 16] = [
    31, 32, 33, 34, 35, 36, 37, 38, 39, 45, 47, 49, 52, 53, 54, 55,
];
/// Integer types (int, uint, int64, uint64), whose arrays may be compressed.
const INTS: [u64; 4] = [3, 4, 5, 6];
/// Float types (half, float, double, double vector), whose arrays may be compressed, and the bytes
/// of one element.
const FLOATS: [u64; 4] = [7, 8, 9, DOUBLE_VECTOR];
const FLOAT_SIZES: [u128; 4] = [2, 4, 8, 8];

/// Checks the counts that decoding the value representation `rep` (the crate's 64-bit `ValueRep`)
/// would allocate from: arrays, token/string/path vectors, and time samples with their times and
/// values. `element` names the attribute in errors.
pub(crate) fn check_value(
    bytes: &[u8],
    version: Version,
    rep: u64,
    element: &str,
) -> Result<(), FormatErrorKind> {
    check_rep(&Bytes { bytes }, version, rep, element, true)
}

fn check_rep(
    file: &Bytes,
    version: Version,
    rep: u64,
    element: &str,
    follow_samples: bool,
) -> Result<(), FormatErrorKind> {
    let (array, inlined, compressed) = (rep >> 63 == 1, (rep >> 62) & 1 == 1, (rep >> 61) & 1 == 1);
    let ty = (rep >> 48) & 0xFF;
    let payload = rep & ((1 << 48) - 1);
    if inlined || payload == 0 && (array || ty == DOUBLE_VECTOR) {
        return Ok(());
    }
    let what = |what: &str| format!("{what} of {element}");
    if !array && UNCHECKED.contains(&ty) {
        // The crate would allocate from counts inside these, which are not checked: no reader
        // wants them where it looks.
        return Err(FormatErrorKind::Usd {
            element: element.to_owned(),
            message: format!(
                "holds a value of crate type {ty} (a dictionary, list op, payload or the like), \
                 which is not read"
            ),
            location: Location::Unknown,
        });
    }
    if array || ty == DOUBLE_VECTOR {
        let mut at = payload;
        if version.1 < 5 {
            at += 4;
        }
        let (count, after) = if version.1 < 7 {
            (u64::from(file.u32(at, &what("an array count"))?), at + 4)
        } else {
            (file.u64(at, &what("an array count"))?, at + 8)
        };
        let left = u128::from(file.len().saturating_sub(after));
        // The crate reads compressed arrays of 4 elements or more: integers from version 0.5.0,
        // floats from 0.6.0; others raw.
        let float_size = FLOATS.iter().position(|&t| t == ty).map(|i| FLOAT_SIZES[i]);
        let coded =
            (INTS.contains(&ty) && version.1 >= 5) || (float_size.is_some() && version.1 >= 6);
        if compressed && count >= 4 && coded {
            let mut block = after;
            if let Some(size) = float_size {
                let code = file.array::<1>(after, &what("an array's compression code"))?[0];
                block = after + 1;
                if code == b't' {
                    // A raw look-up table, then the coded indices.
                    let table = file.u32(after + 1, &what("a look-up table size"))?;
                    let needed = u128::from(table) * size;
                    if needed > u128::from(file.len().saturating_sub(after + 5)) {
                        return Err(too_large(
                            what(&format!("look-up table size = {table}")),
                            after + 1,
                            needed,
                            after + 5,
                            file.len(),
                        ));
                    }
                    block = after + 5 + u64::from(table) * size as u64;
                }
            }
            compressed_ints(file, block, count, &what("a compressed array"))?;
        } else if u128::from(count) > left {
            return Err(too_large(
                what(&format!("array count = {count}")),
                at,
                u128::from(count),
                after,
                file.len(),
            ));
        }
    } else if COUNTED_VECTORS.contains(&ty) {
        let count = file.u64(payload, &what("a vector count"))?;
        let needed = u128::from(count) * 4;
        if needed > u128::from(file.len().saturating_sub(payload + 8)) {
            return Err(too_large(
                what(&format!("vector count = {count}")),
                payload,
                needed,
                payload + 8,
                file.len(),
            ));
        }
    } else if ty == TIME_SAMPLES && follow_samples {
        // An offset to the times' representation, then an offset to the count and the values'.
        let times_at = jump(file, payload, &what("a time-sample offset"))?;
        let times = file.u64(times_at, &what("the time-sample times"))?;
        check_rep(file, version, times, element, false)?;
        let values_at = jump(file, times_at + 8, &what("a time-sample offset"))?;
        let count = file.u64(values_at, &what("the time-sample count"))?;
        let needed = u128::from(count) * 8;
        if needed > u128::from(file.len().saturating_sub(values_at + 8)) {
            return Err(too_large(
                what(&format!("time-sample count = {count}")),
                values_at,
                needed,
                values_at + 8,
                file.len(),
            ));
        }
        for i in 0..count {
            let value = file.u64(values_at + 8 + 8 * i, &what("a time-sample value"))?;
            check_rep(file, version, value, element, false)?;
        }
    }
    Ok(())
}

/// Checks a compressed block of `count` coded integers at `at`: its size inside the file, and
/// `count` no more than it can expand to.
fn compressed_ints(file: &Bytes, at: u64, count: u64, what: &str) -> Result<(), FormatErrorKind> {
    let compressed = file.u64(at, what)?;
    let data = at + 8;
    let left = file.len().saturating_sub(data);
    if compressed > left {
        return Err(too_large(
            format!("{what}: compressed size = {compressed}"),
            at,
            u128::from(compressed),
            data,
            file.len(),
        ));
    }
    if u128::from(count) > 4 * LZ4_RATIO * u128::from(compressed) + 4 {
        return Err(too_large(
            format!("{what}: count = {count}"),
            at,
            u128::from(count),
            data,
            file.len(),
        ));
    }
    Ok(())
}

/// The crate's recursive offset: the i64 at `at` counts from `at`.
fn jump(file: &Bytes, at: u64, what: &str) -> Result<u64, FormatErrorKind> {
    let offset = file.u64(at, what)? as i64;
    match at.checked_add_signed(offset) {
        Some(target) if target <= file.len() => Ok(target),
        _ => Err(FormatErrorKind::InvalidField {
            field: what.to_owned(),
            value: offset.to_string(),
            offset: at,
            allowed: "an offset inside the file",
        }),
    }
}
