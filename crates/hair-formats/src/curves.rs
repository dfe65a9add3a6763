//! The one place that checks and converts every curve a reader finds ([`CurvesBuilder`]), so all
//! formats treat bad curves alike: the result is hair-core's [`Curves`], with the degenerate
//! curves that were skipped listed in [`Curves::skipped`].

use glam::Vec3;

use super::error::{FormatErrorKind, Location};
use super::options::ImportOptions;

pub use hair_core::curves::{Curves, SkipReason, SkippedCurve};

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
        let options = ImportOptions::with_axes(crate::ImportAxes {
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
