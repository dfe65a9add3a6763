//! The error of the file readers: what is wrong, in which file, and where (a byte offset in a binary
//! file, a line in a text file), for every way a groom or body file can be broken.

use std::fmt;
use std::path::Path;

use thiserror::Error;

use hair_core::curves::SkipReason;
use hair_core::error::HairError;
use hair_core::mesh::MeshError;

/// Where in a file something was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// A byte offset from the start of a binary file.
    Byte(u64),
    /// A 1-based line number in a text file.
    Line(usize),
    /// No finer place is known (a reader that reports none, such as `tobj`).
    Unknown,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Byte(offset) => write!(f, "byte {offset}"),
            Location::Line(line) => write!(f, "line {line}"),
            Location::Unknown => f.write_str("an unknown line"),
        }
    }
}

/// A file that could not be read: the file's name and what is wrong with it.
///
/// Readers from memory (`read_tfx(&bytes, ..)`) name the data [`FormatError::IN_MEMORY`]; the
/// `read_*_file` wrappers name the path. Displays as `file: what`, for example
/// `ratboy_mohawk.tfx: strand_count × vertices_per_strand = 71296 at byte 4 needs 1140736 bytes
/// from byte 160, but the file has 1000 bytes (truncated, or a wrong count)`.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}: {kind}")]
pub struct FormatError {
    /// The file (its path as given), or [`FormatError::IN_MEMORY`].
    pub file: String,
    /// What is wrong, and where (boxed: a `Result` stays small).
    pub kind: Box<FormatErrorKind>,
}

impl FormatError {
    /// The name of data read from memory rather than from a file.
    pub const IN_MEMORY: &'static str = "<memory>";

    /// An error in data read from memory.
    pub fn in_memory(kind: FormatErrorKind) -> Self {
        FormatError {
            file: Self::IN_MEMORY.to_owned(),
            kind: Box::new(kind),
        }
    }

    /// The same error, naming `path` as the file.
    pub fn in_file(self, path: &Path) -> Self {
        FormatError {
            file: path.display().to_string(),
            kind: self.kind,
        }
    }
}

impl FormatErrorKind {
    /// The same error with its element renamed by `rename` where it names one value of an
    /// element (non-finite or invalid); any other error unchanged.
    pub(crate) fn renaming_element(self, rename: impl FnOnce(String) -> String) -> Self {
        match self {
            FormatErrorKind::NonFinite {
                element,
                what,
                value,
                location,
            } => FormatErrorKind::NonFinite {
                element: rename(element),
                what,
                value,
                location,
            },
            FormatErrorKind::InvalidValue {
                element,
                what,
                value,
                location,
                allowed,
            } => FormatErrorKind::InvalidValue {
                element: rename(element),
                what,
                value,
                location,
                allowed,
            },
            other => other,
        }
    }
}

impl From<FormatErrorKind> for FormatError {
    fn from(kind: FormatErrorKind) -> Self {
        FormatError::in_memory(kind)
    }
}

/// Reading a file is the one action a [`FormatError`] reports: it becomes a
/// [`HairError::Io`] with action `reading`, the file as path and the problem as message.
impl From<FormatError> for HairError {
    fn from(error: FormatError) -> Self {
        HairError::Io {
            action: "reading",
            path: error.file,
            message: error.kind.to_string(),
        }
    }
}

/// What is wrong with a file, and where.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FormatErrorKind {
    /// The file could not be read at all (missing, unreadable).
    #[error("{message}")]
    Io {
        /// The operating system's message.
        message: String,
    },
    /// The file name's extension names no format that this reader knows.
    #[error("unknown file extension `{extension}` (known: {known})")]
    UnknownExtension {
        /// The extension found (empty when none).
        extension: String,
        /// The known extensions, comma separated.
        known: &'static str,
    },
    /// An import option is out of range.
    #[error("invalid import option {name} = {value} (allowed: {allowed})")]
    InvalidOption {
        /// Name of the option.
        name: &'static str,
        /// The value given, formatted.
        value: String,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The file ends before a fixed-size part (a header, a record) is complete.
    #[error("truncated: {what} at byte {offset} needs {needed} bytes, but only {available} remain")]
    Truncated {
        /// What was being read (`the TressFX 4 header`, `the points of strand 12`).
        what: String,
        /// Byte offset where it starts.
        offset: u64,
        /// Bytes it needs.
        needed: u128,
        /// Bytes left in the file from `offset`.
        available: u64,
    },
    /// The file does not start with the signature of its format.
    #[error("not a {format} file: found {found} at byte 0, expected {expected}")]
    WrongMagic {
        /// The format expected (`cyHair`).
        format: &'static str,
        /// What the file starts with, formatted.
        found: String,
        /// The signature expected, formatted.
        expected: &'static str,
    },
    /// A version this reader does not know.
    #[error("unsupported {format} version {version} at byte {offset} (supported: {supported})")]
    UnsupportedVersion {
        /// The format (`TressFX`).
        format: &'static str,
        /// The version found, formatted.
        version: String,
        /// Byte offset of the version field.
        offset: u64,
        /// The versions supported, in words.
        supported: &'static str,
    },
    /// Counts in the header ask for more data than the file holds; checked before anything is
    /// allocated.
    #[error(
        "{what} at byte {offset} needs {needed} bytes from byte {start}, but the file has \
         {file_len} bytes (truncated, or a wrong count)"
    )]
    CountTooLarge {
        /// The counts, named and valued (`strand_count × vertices_per_strand = 71296`).
        what: String,
        /// Byte offset of the (first) count in the header.
        offset: u64,
        /// Bytes the counts need.
        needed: u128,
        /// Byte offset where that data starts.
        start: u64,
        /// Length of the file [bytes].
        file_len: u64,
    },
    /// A header field or a count has a value the format does not allow.
    #[error("invalid {field} = {value} at byte {offset} (allowed: {allowed})")]
    InvalidField {
        /// The field (`vertices_per_strand`, `vertex count of strand 3`).
        field: String,
        /// Its value, formatted.
        value: String,
        /// Byte offset of the field.
        offset: u64,
        /// The allowed values, in words.
        allowed: &'static str,
    },
    /// Counts that must agree do not (cyHair's segments and point count).
    #[error("inconsistent counts at byte {offset}: {message}")]
    InconsistentCounts {
        /// What disagrees, with the values.
        message: String,
        /// Byte offset of the first count involved.
        offset: u64,
    },
    /// Bytes after the last element of a format whose length the counts fix: a sign of a wrong
    /// count.
    #[error("{count} unexpected bytes after the data, from byte {offset}")]
    TrailingBytes {
        /// Byte offset where the data ended.
        offset: u64,
        /// Number of bytes left over.
        count: u64,
    },
    /// A coordinate is NaN or infinite (in the file, or after scaling to metres).
    #[error("{element} at {location}: {what} {value} is not finite")]
    NonFinite {
        /// The element (`curve 3, point 7`, `vertex 12`).
        element: String,
        /// The quantity (`position`, `normal`, `width`, `colour`).
        what: &'static str,
        /// The offending value, formatted.
        value: String,
        /// Where it is in the file.
        location: Location,
    },
    /// A finite value outside its allowed range (a negative width).
    #[error("{element} at {location}: {what} {value} is invalid (allowed: {allowed})")]
    InvalidValue {
        /// The element (`curve 3, point 7`).
        element: String,
        /// The quantity (`width`).
        what: &'static str,
        /// The offending value, formatted.
        value: String,
        /// Where it is in the file.
        location: Location,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A degenerate curve, under strict reading (by default it is skipped and reported in
    /// [`Curves::skipped`](super::Curves::skipped)).
    #[error("curve {curve} at {location}: {reason} (strict reading)")]
    DegenerateCurve {
        /// Index of the curve in the file (0-based).
        curve: usize,
        /// What is wrong with it.
        reason: SkipReason,
        /// Where the curve starts in the file.
        location: Location,
    },
    /// No usable curve: the file holds none, or all were skipped.
    #[error("no usable curve: the file has {in_file} curves, {skipped} of them skipped")]
    NoCurves {
        /// Curves in the file.
        in_file: usize,
        /// Curves skipped as degenerate.
        skipped: usize,
    },
    /// More points than `u32` curve offsets can address.
    #[error("{count} points, more than u32 offsets can address")]
    TooManyPoints {
        /// Number of points.
        count: u64,
    },
    /// A text file's syntax is wrong.
    #[error("line {line}: {message}")]
    Syntax {
        /// 1-based line number.
        line: usize,
        /// What was expected and found.
        message: String,
    },
    /// A mesh with no triangles (a body mesh needs a surface).
    #[error("the mesh has no triangles")]
    NoTriangles,
    /// A mesh sequence over the reader's memory cap ([`SequenceLimits`](super::SequenceLimits)).
    #[error("mesh sequence too large: {message}")]
    SequenceTooLarge {
        /// Its samples, points and size, and the cap.
        message: String,
    },
    /// The mesh read is malformed (the check of [`hair_core::mesh::TriangleMesh::validate`]).
    #[error("invalid mesh: {0}")]
    Mesh(MeshError),
    /// The OBJ parser (`tobj`) refused the file; it reports no line.
    #[error("OBJ: {0}")]
    Obj(String),
    /// A USD layer read through the `openusd` crate is malformed or holds what is not read; the
    /// element is a prim or attribute path (`/groom/hair.points`) or the layer's part.
    #[error("USD {element}: {message}{}", location_suffix(location))]
    Usd {
        /// The prim or attribute path, or the part of the file (`crate file`).
        element: String,
        /// What is wrong, with the values.
        message: String,
        /// Where it is in the file ([`Location::Unknown`] where the crate does not say).
        location: Location,
    },
    /// An Alembic archive read through the `ogawa-rs` crate is malformed or holds what is not
    /// read; the element is an object path (`/groom/hair`), a property or the archive's part.
    #[error("Alembic {element}: {message}{}", location_suffix(location))]
    Alembic {
        /// The object path (`/groom/hair`), with the property where one is meant, or the part of
        /// the file (`Ogawa group`).
        element: String,
        /// What is wrong, with the values.
        message: String,
        /// Where it is in the file (a byte offset; [`Location::Unknown`] where none is known).
        location: Location,
    },
}

/// ` (at byte 12)` or ` (at line 3)`, or nothing for [`Location::Unknown`].
fn location_suffix(location: &Location) -> String {
    match location {
        Location::Unknown => String::new(),
        known => format!(" (at {known})"),
    }
}
