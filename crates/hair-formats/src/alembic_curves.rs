//! The curves of an Alembic archive's Curves objects (`alembic.rs` reads them) made into
//! [`Curves`]: each object's vertex counts and widths checked against its points, the widths
//! spread to one per point, and errors named by the object's path.

use glam::Vec3;

use super::curves::{Curves, CurvesBuilder, Field};
use super::error::{FormatErrorKind, Location};
use super::ogawa::structure;
use super::options::ImportOptions;

/// One Curves object's first sample, its points through its transforms [file units].
pub(crate) struct CurvesObject {
    pub(crate) path: String,
    pub(crate) points: Vec<Vec3>,
    /// Byte offset of the first position in the file.
    pub(crate) points_at: u64,
    pub(crate) counts: Vec<i32>,
    pub(crate) counts_at: u64,
    /// Widths [file units], after the transforms' scale, as the file gives them.
    pub(crate) widths: Option<Vec<f32>>,
    pub(crate) widths_at: u64,
}

/// Builds the curves of every object, checking the counts against the points.
pub(crate) fn build(
    objects: &[CurvesObject],
    options: &ImportOptions,
) -> Result<Curves, FormatErrorKind> {
    if objects.is_empty() {
        return Err(structure(
            "archive",
            "no Curves object (schema AbcGeom_Curve_v2)".into(),
            0,
        ));
    }
    let total: usize = objects.iter().map(|o| o.points.len()).sum();
    let with_widths = objects.iter().all(|o| o.widths.is_some());
    let mut builder = CurvesBuilder::new(options, total, with_widths, false);
    let mut curve_widths = Vec::new();
    for object in objects {
        let mut sum = 0u64;
        for (i, &count) in object.counts.iter().enumerate() {
            if count < 0 {
                return Err(FormatErrorKind::InvalidField {
                    field: format!("{} nVertices[{i}]", object.path),
                    value: count.to_string(),
                    offset: object.counts_at + 4 * i as u64,
                    allowed: "a vertex count >= 0",
                });
            }
            sum += count as u64;
        }
        if sum != object.points.len() as u64 {
            return Err(FormatErrorKind::InconsistentCounts {
                message: format!(
                    "{}: the {} nVertices add up to {sum} points, but P has {}",
                    object.path,
                    object.counts.len(),
                    object.points.len()
                ),
                offset: object.counts_at,
            });
        }
        let widths = match (&object.widths, with_widths) {
            (Some(widths), true) => Some(per_point_widths(object, widths)?),
            _ => None,
        };
        let mut first_point = 0usize;
        for &count in &object.counts {
            let range = first_point..first_point + count as usize;
            curve_widths.clear();
            if let Some(widths) = &widths {
                curve_widths.extend_from_slice(&widths[range.clone()]);
            }
            let widths_at = object.widths_at;
            let width_stride = if object.widths.as_ref().map(Vec::len) == Some(object.points.len())
            {
                4
            } else {
                0
            };
            let locate = |field: Field, j: usize| {
                let point = (first_point + j) as u64;
                Location::Byte(match field {
                    Field::Width => widths_at + width_stride * point,
                    _ => object.points_at + 12 * point,
                })
            };
            builder
                .push(&object.points[range], &curve_widths, &[], locate)
                // The object's path in front of the curve's element.
                .map_err(|error| {
                    error.renaming_element(|element| format!("{}: {element}", object.path))
                })?;
            first_point += count as usize;
        }
    }
    builder.finish()
}

/// One width per point: the file's per point, per curve or constant widths.
fn per_point_widths(object: &CurvesObject, widths: &[f32]) -> Result<Vec<f32>, FormatErrorKind> {
    if widths.len() == object.points.len() {
        Ok(widths.to_vec())
    } else if widths.len() == 1 {
        Ok(vec![widths[0]; object.points.len()])
    } else if widths.len() == object.counts.len() {
        Ok(object
            .counts
            .iter()
            .zip(widths)
            .flat_map(|(&count, &w)| std::iter::repeat_n(w, count as usize))
            .collect())
    } else {
        Err(FormatErrorKind::InconsistentCounts {
            message: format!(
                "{}: {} widths for {} curves of {} points (allowed: one per point, per curve, or \
                 one)",
                object.path,
                widths.len(),
                object.counts.len(),
                object.points.len()
            ),
            offset: object.widths_at,
        })
    }
}
