//! Curves read from a groom file: [`Curves`], flat struct-of-arrays polylines in metres, +Y up,
//! and the degenerate curves a reader left out ([`SkippedCurve`], [`SkipReason`]). The readers
//! that produce them are in the `hair-formats` crate.

use std::fmt;

use glam::Vec3;

/// Polylines read from a file, stored flat: curve `i` owns `points[offsets[i]..offsets[i + 1]]`,
/// root first. Metres, +Y up, right-handed (after the reader's import axes, `hair_formats::ImportAxes`).
///
/// Every curve has at least two points, every segment a non-zero length, every value is finite
/// and every width is >= 0. `offsets` has one entry more than there are curves and starts at 0 (it
/// is empty only for the empty default). The same layout as
/// `hair_formats::obj::ObjWriter::polylines_flat` takes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Curves {
    /// Points of all curves [m].
    pub points: Vec<Vec3>,
    /// Start of each curve in `points`, and the end of the last: curve count + 1 entries.
    pub offsets: Vec<u32>,
    /// Width (diameter) at each point [m], where the file has them.
    pub widths: Option<Vec<f32>>,
    /// Linear RGB colour at each point, where the file has them.
    pub colors: Option<Vec<Vec3>>,
    /// Curves of the file left out as degenerate, in file order.
    pub skipped: Vec<SkippedCurve>,
}

impl Curves {
    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of points of all curves.
    pub fn point_count(&self) -> usize {
        self.points.len()
    }

    /// The range of curve `index` in `points` (and `widths`, `colors`).
    ///
    /// # Panics
    /// When `index >= curve_count()`.
    pub fn range(&self, index: usize) -> std::ops::Range<usize> {
        self.offsets[index] as usize..self.offsets[index + 1] as usize
    }

    /// The points of curve `index` [m], root first.
    ///
    /// # Panics
    /// When `index >= curve_count()`.
    pub fn curve(&self, index: usize) -> &[Vec3] {
        &self.points[self.range(index)]
    }

    /// The points of each curve [m], in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &[Vec3]> + '_ {
        self.offsets
            .windows(2)
            .map(|w| &self.points[w[0] as usize..w[1] as usize])
    }

    /// The root (first point) of each curve [m].
    pub fn roots(&self) -> impl ExactSizeIterator<Item = Vec3> + '_ {
        self.iter().map(|curve| curve[0])
    }

    /// Axis-aligned bounds `(min, max)` of all points [m]; `None` without points.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.points.first()?;
        Some(
            self.points
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }

    /// Checks the layout (what a writer needs): offsets start at 0, never decrease and end at the
    /// point count (or are empty with no points), widths and colours have one entry per point, and
    /// every value is finite. Returns a message naming the first problem.
    pub fn check_layout(&self) -> Result<(), String> {
        let offsets_ok = match self.offsets.as_slice() {
            [] => self.points.is_empty(),
            [first, ..] => {
                *first == 0
                    && self.offsets.windows(2).all(|w| w[0] <= w[1])
                    && self.offsets[self.offsets.len() - 1] as usize == self.points.len()
            }
        };
        if !offsets_ok {
            return Err(format!(
                "curve offsets must start at 0, never decrease and end at the {} points",
                self.points.len()
            ));
        }
        if let Some(widths) = &self.widths
            && widths.len() != self.points.len()
        {
            return Err(format!(
                "{} widths for {} points",
                widths.len(),
                self.points.len()
            ));
        }
        if let Some(colors) = &self.colors
            && colors.len() != self.points.len()
        {
            return Err(format!(
                "{} colours for {} points",
                colors.len(),
                self.points.len()
            ));
        }
        if let Some(i) = self.points.iter().position(|p| !p.is_finite()) {
            return Err(format!("point {i} is not finite: {}", self.points[i]));
        }
        if let Some(i) = self.widths.iter().flatten().position(|w| !w.is_finite()) {
            return Err(format!("width {i} is not finite"));
        }
        if let Some(i) = self.colors.iter().flatten().position(|c| !c.is_finite()) {
            return Err(format!("colour {i} is not finite"));
        }
        Ok(())
    }
}

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
