//! USD text (`.usda`) `BasisCurves`, read: every `def BasisCurves` prim of the file, in file
//! order, becomes curves of one [`Curves`]. The layer's `upAxis` and `metersPerUnit` are applied
//! first (USD's fallbacks: `Y` and 0.01, centimetres), then the reader's
//! [`ImportAxes`](super::ImportAxes).
//!
//! Read: `linear` curves (`wrap` `nonperiodic` or `pinned`); `curveVertexCounts`; `points`;
//! widths from `primvars:widths` or else `widths` (interpolation `constant`, `uniform`, `varying`
//! or `vertex`, indexed or not) into [`Curves::widths`]; `primvars:displayColor` likewise into
//! [`Curves::colors`]. Widths and colours are kept only when every prim has them. `cubic` curves
//! and `periodic` wraps are refused with the prim's line. Prim transforms are not applied and
//! composition arcs are not followed (flatten such a stage first: `usdcat --flatten`). Binary
//! crate files (`.usdc`) are recognised and refused, pointing to
//! [`read_usdc`](super::read_usdc), which reads them through the `openusd` crate.

use std::path::Path;

use glam::Vec3;

use super::curves::{Curves, CurvesBuilder, Field, vector_text};
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::{ImportAxes, ImportOptions};
use super::read_file;
use super::usda_parse::parse_layer;
use super::usda_prims::{CurvesPrim, PrimKind};
use super::usda_values::{Array, Attr, Sample};

/// Reads the `BasisCurves` of a USD text file from its bytes, at the default time: each
/// attribute's default value, or else its earliest time sample. Points and widths are converted
/// to metres, +Y up by the file's `metersPerUnit` and `upAxis`, then by `options.axes`. Errors name
/// the line; the data is called [`FormatError::IN_MEMORY`].
pub fn read_usda(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    read(bytes, None, options).map_err(FormatError::in_memory)
}

/// Reads the `BasisCurves` of a USD text file at time code `time` (USD's value resolution: the
/// sample at that time, held before the first and after the last sample, linear in between; the
/// default value where an attribute has no samples). See [`read_usda`].
pub fn read_usda_at(
    bytes: &[u8],
    time: f64,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read(bytes, Some(time), options).map_err(FormatError::in_memory)
}

/// Reads the `BasisCurves` of a USD text file (`.usda`, or `.usd` holding text); errors name the
/// file. See [`read_usda`].
pub fn read_usda_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, None, options))
}

/// Reads the `BasisCurves` of a USD text file at time code `time`; errors name the file. See
/// [`read_usda_at`].
pub fn read_usda_file_at(
    path: impl AsRef<Path>,
    time: f64,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, Some(time), options))
}

fn read(
    bytes: &[u8],
    time: Option<f64>,
    options: &ImportOptions,
) -> Result<Curves, FormatErrorKind> {
    options.axes.validate()?;
    if let Some(time) = time
        && !time.is_finite()
    {
        return Err(FormatErrorKind::InvalidOption {
            name: "time",
            value: time.to_string(),
            allowed: "a finite time code",
        });
    }
    if bytes.starts_with(b"PXR-USDC") {
        return Err(FormatErrorKind::WrongMagic {
            format: "USD text",
            found: "\"PXR-USDC\" (a binary crate file: read it with `read_usdc`, or name it \
                    .usdc or .usd)"
                .into(),
            expected: "\"#usda 1.0\"",
        });
    }
    if !bytes.starts_with(b"#usda ") {
        let start = &bytes[..bytes.len().min(8)];
        return Err(FormatErrorKind::WrongMagic {
            format: "USD text",
            found: format!("\"{}\"", start.escape_ascii()),
            expected: "\"#usda 1.0\"",
        });
    }
    let text = super::text::utf8_text(bytes)?;
    let layer = parse_layer(text, time, PrimKind::Curves)?;
    // Scaled in f64, so that centimetres become the nearest metres (10 cm is 0.1 m exactly).
    let meters_per_unit = layer.meters_per_unit;
    let up = ImportAxes {
        up: layer.up,
        ..ImportAxes::default()
    };
    let point = |p: Vec3| up.point((p.as_dvec3() * meters_per_unit).as_vec3());
    let length = |w: f32| (f64::from(w) * meters_per_unit) as f32;
    let prims = layer
        .curves
        .into_iter()
        .map(|prim| resolve(prim, time))
        .collect::<Result<Vec<_>, _>>()?;
    let capacity = prims.iter().map(|p| p.points.len()).sum();
    let widths = prims.iter().all(|p| p.widths.is_some());
    let colors = prims.iter().all(|p| p.colors.is_some());
    let mut builder = CurvesBuilder::new(options, capacity, widths, colors);
    let (mut points, mut curve_widths) = (Vec::new(), Vec::new());
    let mut curve = 0usize;
    for prim in &prims {
        let mut start = 0usize;
        for &count in &prim.counts {
            let range = start..start + count;
            start = range.end;
            // The file's values in messages, not the converted ones.
            let raw = prim.points.values.get(range.clone()).unwrap_or_default();
            if let Some(j) = raw.iter().position(|p| !p.is_finite()) {
                return Err(FormatErrorKind::NonFinite {
                    element: format!("curve {curve}, point {j}"),
                    what: "position",
                    value: vector_text(raw[j]),
                    location: Location::Line(prim.points.line(range.start + j, 1)),
                });
            }
            if let Some(w) = &prim.widths {
                let raw = w.values.get(range.clone()).unwrap_or_default();
                if let Some(j) = raw.iter().position(|w| !w.is_finite()) {
                    return Err(FormatErrorKind::NonFinite {
                        element: format!("curve {curve}, point {j}"),
                        what: "width",
                        value: raw[j].to_string(),
                        location: Location::Line(w.line(range.start + j, 1)),
                    });
                }
            }
            curve += 1;
            points.clear();
            curve_widths.clear();
            // In range: the counts add up to the points, and widths and colours were expanded
            // to one per point.
            let slice = |values: &[Vec3]| values.get(range.clone()).unwrap_or_default().to_vec();
            points.extend(slice(&prim.points.values).into_iter().map(point));
            if widths && let Some(w) = &prim.widths {
                let w = w.values.get(range.clone()).unwrap_or_default();
                curve_widths.extend(w.iter().map(|&w| length(w)));
            }
            let curve_colors = match &prim.colors {
                Some(c) if colors => slice(&c.values),
                _ => Vec::new(),
            };
            let locate = |field: Field, j: usize| {
                let i = range.start + j;
                let fallback = prim.points.line(0, 1);
                Location::Line(match (field, &prim.widths, &prim.colors) {
                    (Field::Width, Some(w), _) => w.line(i, fallback),
                    (Field::Colour, _, Some(c)) => c.line(i, fallback),
                    _ => prim.points.line(i, fallback),
                })
            };
            builder.push(&points, &curve_widths, &curve_colors, locate)?;
        }
    }
    builder.finish()
}

/// A prim's values at the time read, checked and expanded to one per point.
struct Resolved {
    counts: Vec<usize>,
    points: Array<Vec3>,
    widths: Option<Array<f32>>,
    colors: Option<Array<Vec3>>,
}

fn syntax(line: usize, message: String) -> FormatErrorKind {
    FormatErrorKind::Syntax { line, message }
}

/// The value of an optional token attribute, with its line; `fallback` when not authored.
fn token(
    attr: Option<Attr<String>>,
    time: Option<f64>,
    fallback: &str,
    line: usize,
) -> (String, usize) {
    match attr {
        Some(attr) => {
            let line = attr.line;
            (
                attr.resolve(time).unwrap_or_else(|| fallback.to_owned()),
                line,
            )
        }
        None => (fallback.to_owned(), line),
    }
}

fn resolve(prim: CurvesPrim, time: Option<f64>) -> Result<Resolved, FormatErrorKind> {
    let name = prim.name;
    let line = prim.line;
    let (curve_type, type_line) = token(prim.curve_type, time, "cubic", line);
    let (basis, _) = token(prim.basis, time, "bezier", line);
    let (wrap, wrap_line) = token(prim.wrap, time, "nonperiodic", line);
    match curve_type.as_str() {
        "linear" => {}
        "cubic" => {
            return Err(syntax(
                type_line,
                format!(
                    "BasisCurves {name} has type \"cubic\" (basis \"{basis}\"{}); only \"linear\" \
                     curves are read (convert the curves to linear polylines first)",
                    if type_line == line {
                        ", USD's fallback when `type` is not authored"
                    } else {
                        ""
                    }
                ),
            ));
        }
        other => {
            return Err(syntax(
                type_line,
                format!(
                    "BasisCurves {name} has an unknown type \"{}\" (allowed: \"linear\")",
                    super::text::shorten(other)
                ),
            ));
        }
    }
    if !matches!(wrap.as_str(), "nonperiodic" | "pinned") {
        return Err(syntax(
            wrap_line,
            format!(
                "BasisCurves {name} has wrap \"{}\"; only open curves (\"nonperiodic\", \
                 \"pinned\") are read",
                super::text::shorten(&wrap)
            ),
        ));
    }
    let missing = |what: &str| syntax(line, format!("BasisCurves {name} has no {what} value"));
    let counts_attr = prim.counts.ok_or_else(|| missing("curveVertexCounts"))?;
    let counts_line = counts_attr.line;
    let counts = counts_attr
        .resolve(time)
        .ok_or_else(|| missing("curveVertexCounts"))?;
    let points_attr = prim.points.ok_or_else(|| missing("points"))?;
    let points_line = points_attr.line;
    let points = points_attr.resolve(time).ok_or_else(|| missing("points"))?;
    let mut total: u128 = 0;
    let mut checked = Vec::with_capacity(counts.len());
    for (i, &count) in counts.values.iter().enumerate() {
        let Ok(count) = usize::try_from(count) else {
            return Err(syntax(
                counts.line(i, counts_line),
                format!("curveVertexCounts[{i}] of BasisCurves {name} is negative ({count})"),
            ));
        };
        total += count as u128;
        checked.push(count);
    }
    if total != points.len() as u128 {
        return Err(syntax(
            counts_line,
            format!(
                "the curveVertexCounts of BasisCurves {name} add up to {total} points, but its \
                 points (line {points_line}) hold {}",
                points.len()
            ),
        ));
    }
    let shape = Shape {
        name: &name,
        counts: &checked,
        points: points.len(),
        time,
    };
    let widths = match prim.primvar_widths {
        Some(w) => shape.expand("primvars:widths", w, prim.width_indices, "vertex")?,
        None => match prim.widths {
            Some(w) => shape.expand("widths", w, None, "vertex")?,
            None => None,
        },
    };
    let colors = match prim.colors {
        Some(c) => shape.expand("primvars:displayColor", c, prim.color_indices, "constant")?,
        None => None,
    };
    Ok(Resolved {
        counts: checked,
        points,
        widths,
        colors,
    })
}

/// A prim's curve sizes, to expand primvars to one value per point.
struct Shape<'a> {
    name: &'a str,
    counts: &'a [usize],
    points: usize,
    time: Option<f64>,
}

impl Shape<'_> {
    /// The primvar `attr` (with its `indices`) at the time, one value per point; `None` when not
    /// authored or blocked.
    fn expand<T: Sample + Copy>(
        &self,
        what: &str,
        attr: Attr<Array<T>>,
        indices: Option<Attr<Array<i64>>>,
        fallback: &str,
    ) -> Result<Option<Array<T>>, FormatErrorKind> {
        let (line, interpolation) = (attr.line, attr.interpolation.clone());
        let Some(mut values) = attr.resolve(self.time) else {
            return Ok(None);
        };
        if let Some(indices) = indices.and_then(|i| i.resolve(self.time)) {
            let mut indexed = Array {
                values: Vec::with_capacity(indices.len()),
                lines: Vec::with_capacity(indices.len()),
            };
            for (i, &index) in indices.values.iter().enumerate() {
                let Some(&value) = usize::try_from(index)
                    .ok()
                    .and_then(|k| values.values.get(k))
                else {
                    return Err(syntax(
                        indices.line(i, line),
                        format!(
                            "{what}:indices[{i}] = {index} of BasisCurves {} names no value \
                             ({} values)",
                            self.name,
                            values.len()
                        ),
                    ));
                };
                indexed.values.push(value);
                indexed.lines.push(indices.lines[i]);
            }
            values = indexed;
        }
        let (interpolation, interpolation_line) =
            interpolation.unwrap_or_else(|| (fallback.to_owned(), line));
        let (needed, per) = match interpolation.as_str() {
            "constant" => (1, "one"),
            "uniform" => (self.counts.len(), "one per curve"),
            "vertex" | "varying" => (self.points, "one per point"),
            other => {
                return Err(syntax(
                    interpolation_line,
                    format!(
                        "{what} of BasisCurves {} has interpolation \"{}\" (allowed: constant, \
                         uniform, varying, vertex)",
                        self.name,
                        super::text::shorten(other)
                    ),
                ));
            }
        };
        if values.len() != needed {
            return Err(syntax(
                line,
                format!(
                    "{what} of BasisCurves {} has {} values, but interpolation \"{interpolation}\" \
                     needs {needed} ({per})",
                    self.name,
                    values.len()
                ),
            ));
        }
        if needed == self.points {
            return Ok(Some(values));
        }
        let mut expanded = Array {
            values: Vec::with_capacity(self.points),
            lines: Vec::with_capacity(self.points),
        };
        for (curve, &count) in self.counts.iter().enumerate() {
            let k = if needed == 1 { 0 } else { curve };
            for _ in 0..count {
                expanded.values.push(values.values[k]);
                expanded.lines.push(values.lines[k]);
            }
        }
        Ok(Some(expanded))
    }
}
