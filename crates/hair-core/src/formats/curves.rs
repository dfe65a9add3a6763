//! What the curve readers produce: [`Curves`], flat struct-of-arrays polylines in metres, +Y up,
//! with the degenerate curves that were skipped listed in [`Curves::skipped`]; and the one place
//! that checks and converts every curve a reader finds, so all formats treat bad curves alike.

use glam::Vec3;

use super::error::{FormatErrorKind, Location};
use super::options::ImportOptions;

pub use super::skip::{SkipReason, SkippedCurve};

/// Polylines read from a file, stored flat: curve `i` owns `points[offsets[i]..offsets[i + 1]]`,
/// root first. Metres, +Y up, right-handed (after [`ImportAxes`](super::ImportAxes)).
///
/// Every curve has at least two points, every segment a non-zero length, every value is finite
/// and every width is >= 0. `offsets` has one entry more than there are curves and starts at 0 (it
/// is empty only for the empty default). The same layout as
/// [`ObjWriter::polylines_flat`](crate::obj::ObjWriter::polylines_flat) takes.
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

/// Formats a vector as `[x, y, z]` for messages.
pub(crate) fn vector_text(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// Which per-point array a location is asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Field {
    /// The position.
    Position,
    /// The width.
    Width,
    /// The colour.
    Colour,
}

/// Collects the curves a reader finds, checking and converting each: non-finite values are errors
/// (the file is broken); degenerate curves are skipped and listed, or errors under strict reading.
pub(crate) struct CurvesBuilder<'o> {
    options: &'o ImportOptions,
    curves: Curves,
    /// Curves seen in the file so far, skipped ones included.
    in_file: usize,
}

impl<'o> CurvesBuilder<'o> {
    /// A builder for curves with (or without) widths and colours. `point_capacity` must be a
    /// count already checked against the file's length.
    pub(crate) fn new(
        options: &'o ImportOptions,
        point_capacity: usize,
        widths: bool,
        colors: bool,
    ) -> Self {
        CurvesBuilder {
            options,
            curves: Curves {
                points: Vec::with_capacity(point_capacity),
                offsets: vec![0],
                widths: widths.then(|| Vec::with_capacity(point_capacity)),
                colors: colors.then(|| Vec::with_capacity(point_capacity)),
                skipped: Vec::new(),
            },
            in_file: 0,
        }
    }

    /// Adds the next curve of the file: its `points` [file units], its `widths` [file units] and
    /// `colors` (each empty, or one per point, as the builder was made). `locate(field, j)` says
    /// where `field` of point `j` is in the file.
    pub(crate) fn push(
        &mut self,
        points: &[Vec3],
        widths: &[f32],
        colors: &[Vec3],
        locate: impl Fn(Field, usize) -> Location,
    ) -> Result<(), FormatErrorKind> {
        let index = self.in_file;
        self.in_file += 1;
        let element = |j: usize| format!("curve {index}, point {j}");
        if let Some(j) = points.iter().position(|p| !p.is_finite()) {
            return Err(FormatErrorKind::NonFinite {
                element: element(j),
                what: "position",
                value: vector_text(points[j]),
                location: locate(Field::Position, j),
            });
        }
        if let Some(j) = widths.iter().position(|w| !w.is_finite()) {
            return Err(FormatErrorKind::NonFinite {
                element: element(j),
                what: "width",
                value: widths[j].to_string(),
                location: locate(Field::Width, j),
            });
        }
        if let Some(j) = widths.iter().position(|&w| w < 0.0) {
            return Err(FormatErrorKind::InvalidValue {
                element: element(j),
                what: "width",
                value: widths[j].to_string(),
                location: locate(Field::Width, j),
                allowed: "a width >= 0",
            });
        }
        if let Some(j) = colors.iter().position(|c| !c.is_finite()) {
            return Err(FormatErrorKind::NonFinite {
                element: element(j),
                what: "colour",
                value: vector_text(colors[j]),
                location: locate(Field::Colour, j),
            });
        }
        if points.len() < 2 {
            return self.skip(
                SkipReason::TooFewPoints {
                    count: points.len(),
                },
                locate(Field::Position, 0),
            );
        }
        let axes = &self.options.axes;
        let start = self.curves.points.len();
        if start as u64 + points.len() as u64 > u64::from(u32::MAX) {
            return Err(FormatErrorKind::TooManyPoints {
                count: start as u64 + points.len() as u64,
            });
        }
        self.curves
            .points
            .extend(points.iter().map(|&p| axes.point(p)));
        let converted = &self.curves.points[start..];
        if let Some(j) = converted.iter().position(|p| !p.is_finite()) {
            let value = format!("{} (after scaling to metres)", vector_text(converted[j]));
            return Err(FormatErrorKind::NonFinite {
                element: element(j),
                what: "position",
                value,
                location: locate(Field::Position, j),
            });
        }
        if let Some(segment) = converted.windows(2).position(|w| w[0] == w[1]) {
            self.curves.points.truncate(start);
            return self.skip(
                SkipReason::ZeroLengthSegment { segment },
                locate(Field::Position, segment),
            );
        }
        if let Some(all) = &mut self.curves.widths {
            let first = all.len();
            all.extend(widths.iter().map(|&w| axes.length(w)));
            if let Some(j) = all[first..].iter().position(|w| !w.is_finite()) {
                return Err(FormatErrorKind::NonFinite {
                    element: element(j),
                    what: "width",
                    value: format!("{} (after scaling to metres)", all[first + j]),
                    location: locate(Field::Width, j),
                });
            }
        }
        if let Some(all) = &mut self.curves.colors {
            all.extend_from_slice(colors);
        }
        self.curves.offsets.push(self.curves.points.len() as u32);
        Ok(())
    }

    /// Skips the current curve (already counted) for `reason`, or refuses it when strict.
    fn skip(&mut self, reason: SkipReason, location: Location) -> Result<(), FormatErrorKind> {
        let index = self.in_file - 1;
        if self.options.strict && reason != SkipReason::EmptyRoot {
            return Err(FormatErrorKind::DegenerateCurve {
                curve: index,
                reason,
                location,
            });
        }
        self.curves.skipped.push(SkippedCurve { index, reason });
        Ok(())
    }

    /// Counts the next curve of the file as an empty root (USC-HairSalon), skipped.
    pub(crate) fn push_empty_root(&mut self) {
        self.in_file += 1;
        let index = self.in_file - 1;
        self.curves.skipped.push(SkippedCurve {
            index,
            reason: SkipReason::EmptyRoot,
        });
    }

    /// The curves; an error when none is usable.
    pub(crate) fn finish(self) -> Result<Curves, FormatErrorKind> {
        if self.curves.curve_count() == 0 {
            return Err(FormatErrorKind::NoCurves {
                in_file: self.in_file,
                skipped: self.curves.skipped.len(),
            });
        }
        Ok(self.curves)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(curves: &[&[Vec3]], options: &ImportOptions) -> Result<Curves, FormatErrorKind> {
        let mut builder = CurvesBuilder::new(options, 0, false, false);
        for (i, points) in curves.iter().enumerate() {
            builder.push(points, &[], &[], |_, j| Location::Line(100 * i + j))?;
        }
        builder.finish()
    }

    #[test]
    fn degenerate_curves_are_skipped_and_listed() {
        let good: &[Vec3] = &[Vec3::ZERO, Vec3::Y];
        let single: &[Vec3] = &[Vec3::X];
        let repeated: &[Vec3] = &[Vec3::ZERO, Vec3::X, Vec3::X];
        let curves = build(&[single, good, repeated, good], &ImportOptions::default()).unwrap();
        assert_eq!(curves.curve_count(), 2);
        assert_eq!(curves.offsets, [0, 2, 4]);
        assert_eq!(
            curves.skipped,
            [
                SkippedCurve {
                    index: 0,
                    reason: SkipReason::TooFewPoints { count: 1 }
                },
                SkippedCurve {
                    index: 2,
                    reason: SkipReason::ZeroLengthSegment { segment: 1 }
                },
            ]
        );
        assert_eq!(curves.curve(1), good);
        assert_eq!(curves.roots().collect::<Vec<_>>(), [Vec3::ZERO, Vec3::ZERO]);
        assert_eq!(curves.bounds(), Some((Vec3::ZERO, Vec3::Y)));
        assert_eq!(curves.check_layout(), Ok(()));
    }

    #[test]
    fn strict_reading_refuses_the_first_degenerate_curve() {
        let good: &[Vec3] = &[Vec3::ZERO, Vec3::Y];
        let repeated: &[Vec3] = &[Vec3::ZERO, Vec3::X, Vec3::X];
        let error = build(&[good, repeated], &ImportOptions::strict()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "curve 1 at line 101: segment 1 has zero length (strict reading)"
        );
    }

    #[test]
    fn a_scale_that_overflows_is_not_finite() {
        let options = ImportOptions::with_axes(super::super::ImportAxes {
            scale_to_metres: 1e30,
            ..Default::default()
        });
        let huge: &[Vec3] = &[Vec3::ZERO, Vec3::splat(1e10)];
        let error = build(&[huge], &options).unwrap_err();
        assert_eq!(
            error.to_string(),
            "curve 0, point 1 at line 1: position [inf, inf, inf] (after scaling to metres) is not \
             finite"
        );
    }
}
