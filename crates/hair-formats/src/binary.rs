//! Little-endian reads from a byte slice that never panic: every read is bounds-checked and a
//! short file becomes [`FormatErrorKind::Truncated`], and every header count is checked against
//! the file's length before anything is allocated for it ([`Bytes::require_counts`]).

use glam::Vec3;

use super::error::FormatErrorKind;

/// A file's bytes, read at byte offsets.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Bytes { data }
    }

    /// Length of the file [bytes].
    pub(crate) fn len(&self) -> u64 {
        self.data.len() as u64
    }

    /// Bytes from `offset` to the end (0 past the end).
    pub(crate) fn available(&self, offset: u64) -> u64 {
        self.len().saturating_sub(offset)
    }

    /// The `len` bytes at `offset`, or [`FormatErrorKind::Truncated`] naming `what`.
    pub(crate) fn slice(
        &self,
        offset: u64,
        len: u128,
        what: impl FnOnce() -> String,
    ) -> Result<&'a [u8], FormatErrorKind> {
        let range = usize::try_from(offset)
            .ok()
            .zip(usize::try_from(len).ok())
            .and_then(|(start, len)| Some(start..start.checked_add(len)?));
        match range.and_then(|range| self.data.get(range)) {
            Some(slice) => Ok(slice),
            None => Err(FormatErrorKind::Truncated {
                what: what(),
                offset,
                needed: len,
                available: self.available(offset),
            }),
        }
    }

    /// Checks that `needed` bytes of data from `start`, asked for by header counts described by
    /// `what` (the first of them at byte `count_offset`), lie inside the file.
    pub(crate) fn require_counts(
        &self,
        what: impl FnOnce() -> String,
        count_offset: u64,
        start: u64,
        needed: u128,
    ) -> Result<(), FormatErrorKind> {
        if u128::from(start) + needed <= u128::from(self.len()) {
            Ok(())
        } else {
            Err(FormatErrorKind::CountTooLarge {
                what: what(),
                offset: count_offset,
                needed,
                start,
                file_len: self.len(),
            })
        }
    }
}

/// The 4 bytes of `slice` at `at` (which the caller has checked to exist).
fn four(slice: &[u8], at: usize) -> [u8; 4] {
    let mut bytes = [0; 4];
    if let Some(source) = at.checked_add(4).and_then(|end| slice.get(at..end)) {
        bytes.copy_from_slice(source);
    }
    bytes
}

/// The little-endian `u32` at byte `at` of `slice` (0 when out of range: check first).
pub(crate) fn u32_at(slice: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(four(slice, at))
}

/// The little-endian `i32` at byte `at` of `slice` (0 when out of range: check first).
pub(crate) fn i32_at(slice: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(four(slice, at))
}

/// The little-endian `f32` at byte `at` of `slice` (0 when out of range: check first).
pub(crate) fn f32_at(slice: &[u8], at: usize) -> f32 {
    f32::from_le_bytes(four(slice, at))
}

/// The little-endian `u16` at byte `at` of `slice` (0 when out of range: check first).
pub(crate) fn u16_at(slice: &[u8], at: usize) -> u16 {
    match at.checked_add(2).and_then(|end| slice.get(at..end)) {
        Some(&[a, b]) => u16::from_le_bytes([a, b]),
        _ => 0,
    }
}

/// The little-endian `f32` triples of `slice`, `stride` bytes apart (12 for packed xyz, 16 for
/// xyzw), appended to `out`.
pub(crate) fn vec3s(slice: &[u8], stride: usize, out: &mut Vec<Vec3>) {
    out.extend(
        slice
            .chunks_exact(stride)
            .map(|chunk| Vec3::new(f32_at(chunk, 0), f32_at(chunk, 4), f32_at(chunk, 8))),
    );
}

/// The little-endian `f32`s of `slice`, appended to `out`.
pub(crate) fn f32s(slice: &[u8], out: &mut Vec<f32>) {
    out.extend(slice.chunks_exact(4).map(|chunk| f32_at(chunk, 0)));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_past_the_end_are_truncation_errors() {
        let bytes = Bytes::new(&[1, 0, 0, 0, 2]);
        assert_eq!(bytes.slice(0, 4, String::new).unwrap(), &[1, 0, 0, 0]);
        let error = bytes.slice(3, 4, || "a u32".into()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "truncated: a u32 at byte 3 needs 4 bytes, but only 2 remain"
        );
        assert!(bytes.slice(u64::MAX, u128::MAX, String::new).is_err());
        assert!(bytes.slice(9, 0, String::new).is_err());
        assert_eq!(u32_at(&[1, 0, 0, 0], 0), 1);
        assert_eq!(
            u32_at(&[1, 0, 0], 0),
            0,
            "out of range reads 0, never panics"
        );
        assert_eq!(u16_at(&[1], 0), 0);
    }

    #[test]
    fn counts_are_checked_against_the_file_length() {
        let bytes = Bytes::new(&[0; 100]);
        assert!(bytes.require_counts(String::new, 4, 20, 80).is_ok());
        let error = bytes
            .require_counts(|| "n = 3".into(), 4, 20, 81)
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            "n = 3 at byte 4 needs 81 bytes from byte 20, but the file has 100 bytes (truncated, \
             or a wrong count)"
        );
    }
}
