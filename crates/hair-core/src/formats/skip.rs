//! Why a curve of a file was skipped ([`SkipReason`], [`SkippedCurve`]).

use std::fmt;

/// Why a curve of a file was skipped (or, under strict reading, refused).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SkipReason {
    /// Fewer than two points: no segment to draw or simulate.
    TooFewPoints {
        /// Points the curve has (0 or 1).
        count: usize,
    },
    /// Two consecutive points coincide (after conversion to metres).
    ZeroLengthSegment {
        /// Index of the segment in the curve (between points `segment` and `segment + 1`).
        segment: usize,
    },
    /// A USC-HairSalon strand of one vertex: the format's mark for a root without hair. Skipped
    /// even under strict reading.
    EmptyRoot,
}

impl fmt::Display for SkipReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SkipReason::TooFewPoints { count } => {
                write!(f, "fewer than two points ({count})")
            }
            SkipReason::ZeroLengthSegment { segment } => {
                write!(f, "segment {segment} has zero length")
            }
            SkipReason::EmptyRoot => f.write_str("an empty root (one vertex)"),
        }
    }
}

/// A curve of the file that is not in [`Curves`], and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SkippedCurve {
    /// Index of the curve in the file (0-based, counting every curve the file holds).
    pub index: usize,
    /// Why it was skipped.
    pub reason: SkipReason,
}
