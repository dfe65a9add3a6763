//! USD binary crate files (`.usdc`) through the `openusd` crate: `BasisCurves` here
//! ([`read_usdc`]), `Mesh` prims in `usd_mesh.rs`. Text layers never reach the crate: one parser
//! per encoding, and the project's (`usda_parse.rs`) reads every text layer, curves
//! ([`read_usda`](super::read_usda), which [`read_usd_curves`] calls for text) and meshes alike:
//! it reads any time code ([`read_usda_at`](super::read_usda_at), interpolating samples), and its
//! errors name the line of the value at fault. Both encodings read the same curves.
//!
//! Every `def` prim of the type, in namespace order, is read and joined; the layer's `upAxis`
//! and `metersPerUnit` are applied first (USD's fallbacks: `Y` and 0.01, centimetres), then the
//! reader's [`ImportAxes`](super::ImportAxes). Each attribute is read at the default time: its
//! default value, or else its earliest time sample. Only the layer is read: prim transforms are
//! not applied and composition arcs are not followed (flatten such a stage first:
//! `usdcat --flatten`).
//!
//! Curves: `linear` curves with wrap `nonperiodic` or `pinned`; `points`; `curveVertexCounts`;
//! widths from `primvars:widths` or else `widths`, and colours from `primvars:displayColor`
//! (interpolation `constant`, `uniform`, `varying` or `vertex`, indexed or not), kept only when
//! every prim has them. `cubic` curves (USD's fallback type) are refused with the prim's path:
//! their control points are not on the curve, and reading them as a polyline would change the
//! groom silently.
//!
//! Robustness (curves here and meshes in `usd_mesh.rs`): errors name the file, the prim or
//! attribute path, and the byte offset where the project's checks know it (the crate reports
//! none). A crate file is checked before the crate reads it (`usdc_check.rs`: header, table of
//! contents, section sizes, and every count it would allocate from, against the file's length).
//! Every call into the crate runs under
//! `std::panic::catch_unwind`, and a panic (the crate indexes its tables unchecked and has
//! `todo!()`s for old versions and chunked compression) becomes a [`FormatError`]; the panic's
//! message still reaches the panic hook (standard error). The reader needs a build that unwinds
//! on panic, as the workspace's profiles do.

use std::path::Path;

use glam::Vec3;
use openusd::sdf::{self, Value};

use super::curves::{Curves, CurvesBuilder};
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::usd_attrs::{Units, check_finite, counts, required, token_attribute};
use super::usd_layer::{
    Encoding, Layer, as_floats, as_ints, as_points, sniff, type_name, usd_error,
};
use super::{read_file, read_usda};

/// Reads the `BasisCurves` of a binary USD crate file (`.usdc`) from its bytes, at the default
/// time. Points and widths are converted to metres, +Y up by the layer's `metersPerUnit` and
/// `upAxis`, then by `options.axes`. The data is called [`FormatError::IN_MEMORY`].
pub fn read_usdc(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    read_crate_curves(bytes, options).map_err(FormatError::in_memory)
}

/// Reads the `BasisCurves` of a binary USD crate file; errors name the file. See [`read_usdc`].
pub fn read_usdc_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read_crate_curves(bytes, options))
}

/// Reads the `BasisCurves` of a USD file of either encoding (`.usd`), chosen by its first bytes:
/// `#usda` text with [`read_usda`], `PXR-USDC` binary with [`read_usdc`].
pub fn read_usd_curves(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    match sniff(bytes).map_err(FormatError::in_memory)? {
        Encoding::Text => read_usda(bytes, options),
        Encoding::Crate => read_usdc(bytes, options),
    }
}

/// Reads the `BasisCurves` of a USD file of either encoding; errors name the file. See
/// [`read_usd_curves`].
pub fn read_usd_curves_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    let path = path.as_ref();
    read_usd_curves(&read_bytes(path)?, options).map_err(|e| e.in_file(path))
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, FormatError> {
    std::fs::read(path).map_err(|error| {
        FormatError::from(FormatErrorKind::Io {
            message: error.to_string(),
        })
        .in_file(path)
    })
}

fn read_crate_curves(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatErrorKind> {
    options.axes.validate()?;
    // The crate check comes first, so that a text file gets the crate file's wrong-magic error.
    super::usdc_check::check_structure(bytes)?;
    let mut layer = Layer::open(bytes)?;
    let units = Units::of(&mut layer)?;
    let mut prims = Vec::new();
    for path in layer.prims()? {
        if layer.is_defined(&path, "BasisCurves")? {
            prims.push(curves_prim(&mut layer, path)?);
        }
    }
    if prims.is_empty() {
        return Err(usd_error(
            "layer",
            "has no BasisCurves prim (`def BasisCurves`)",
        ));
    }
    let capacity = prims.iter().map(|p| p.points.len()).sum();
    let widths = prims.iter().all(|p| p.widths.is_some());
    let colors = prims.iter().all(|p| p.colors.is_some());
    let mut builder = CurvesBuilder::new(options, capacity, widths, colors);
    let mut curve = 0usize;
    for prim in &prims {
        let mut start = 0usize;
        for &count in &prim.counts {
            let range = start..start + count;
            start = range.end;
            let element =
                |j: usize| format!("{} curve {curve} (of the file), point {j}", prim.path);
            // In range: the counts add up to the points, primvars were expanded to one per point.
            let points = &prim.points[range.clone()];
            check_finite(points, element)?;
            let points: Vec<Vec3> = points.iter().map(|&p| units.point(p)).collect();
            let curve_widths: Vec<f32> = match &prim.widths {
                Some(w) if widths => {
                    let w = &w[range.clone()];
                    if let Some(j) = w.iter().position(|w| !w.is_finite()) {
                        return Err(FormatErrorKind::NonFinite {
                            element: element(j),
                            what: "width",
                            value: w[j].to_string(),
                            location: Location::Unknown,
                        });
                    }
                    w.iter().map(|&w| units.length(w)).collect()
                }
                _ => Vec::new(),
            };
            let curve_colors = match &prim.colors {
                Some(c) if colors => c[range.clone()].to_vec(),
                _ => Vec::new(),
            };
            builder.push(&points, &curve_widths, &curve_colors, |_, _| {
                Location::Unknown
            })?;
            curve += 1;
        }
    }
    builder.finish()
}

/// A `BasisCurves` prim's values, checked, primvars expanded to one per point.
struct CurvesPrim {
    path: sdf::Path,
    counts: Vec<usize>,
    points: Vec<Vec3>,
    widths: Option<Vec<f32>>,
    colors: Option<Vec<Vec3>>,
}

fn curves_prim(layer: &mut Layer, path: sdf::Path) -> Result<CurvesPrim, FormatErrorKind> {
    let curve_type = token_attribute(layer, &path, "type", "cubic")?;
    if curve_type != "linear" {
        let basis = token_attribute(layer, &path, "basis", "bezier")?;
        let shown = super::text::shorten(&curve_type);
        return Err(usd_error(
            &path,
            format!(
                "has type \"{shown}\" (basis \"{}\"); only \"linear\" curves are read (USD's \
                 fallback type is \"cubic\": author `uniform token type = \"linear\"`, or convert \
                 the curves to linear polylines first)",
                super::text::shorten(&basis)
            ),
        ));
    }
    let wrap = token_attribute(layer, &path, "wrap", "nonperiodic")?;
    if !matches!(wrap.as_str(), "nonperiodic" | "pinned") {
        return Err(usd_error(
            &path,
            format!(
                "has wrap \"{}\"; only open curves (\"nonperiodic\", \"pinned\") are read",
                super::text::shorten(&wrap)
            ),
        ));
    }
    let raw_counts = required(layer, &path, "curveVertexCounts", "an int[]", as_ints)?;
    let points = required(layer, &path, "points", "a point3f[]", as_points)?;
    let counts = counts(
        &path,
        "curveVertexCounts",
        &raw_counts,
        points.len(),
        "points",
    )?;
    let shape = Shape {
        prim: &path,
        counts: &counts,
        points: points.len(),
    };
    let widths = if layer.attribute(&path, "primvars:widths")?.is_some() {
        shape.primvar(layer, "primvars:widths", "vertex", as_floats)?
    } else {
        shape.primvar(layer, "widths", "vertex", as_floats)?
    };
    let colors = shape.primvar(layer, "primvars:displayColor", "constant", as_points)?;
    Ok(CurvesPrim {
        path: path.clone(),
        counts,
        points,
        widths,
        colors,
    })
}

/// A prim's curve sizes, to expand primvars to one value per point.
struct Shape<'a> {
    prim: &'a sdf::Path,
    counts: &'a [usize],
    points: usize,
}

impl Shape<'_> {
    /// Primvar `name` (with its `:indices`), one value per point; `None` when not authored.
    fn primvar<T: Copy>(
        &self,
        layer: &mut Layer,
        name: &str,
        fallback: &str,
        convert: fn(&Value) -> Option<Vec<T>>,
    ) -> Result<Option<Vec<T>>, FormatErrorKind> {
        let Some((attr, value)) = layer.attribute(self.prim, name)? else {
            return Ok(None);
        };
        let mut values = convert(&value).ok_or_else(|| {
            usd_error(
                &attr,
                format!("has an unexpected type {}", type_name(&value)),
            )
        })?;
        if let Some((indices_attr, indices)) =
            layer.attribute(self.prim, &format!("{name}:indices"))?
        {
            let indices = as_ints(&indices).ok_or_else(|| {
                usd_error(
                    &indices_attr,
                    format!("is a {}, expected an int[]", type_name(&indices)),
                )
            })?;
            let mut indexed = Vec::with_capacity(indices.len());
            for (i, &index) in indices.iter().enumerate() {
                let value = usize::try_from(index).ok().and_then(|k| values.get(k));
                let Some(&value) = value else {
                    return Err(usd_error(
                        &indices_attr,
                        format!("[{i}] = {index} names no value ({} values)", values.len()),
                    ));
                };
                indexed.push(value);
            }
            values = indexed;
        }
        let interpolation = layer
            .token(&attr, "interpolation")?
            .unwrap_or_else(|| fallback.to_owned());
        let (needed, per) = match interpolation.as_str() {
            "constant" => (1, "one"),
            "uniform" => (self.counts.len(), "one per curve"),
            "vertex" | "varying" => (self.points, "one per point"),
            other => {
                return Err(usd_error(
                    &attr,
                    format!(
                        "has interpolation \"{}\" (allowed: constant, uniform, varying, vertex)",
                        super::text::shorten(other)
                    ),
                ));
            }
        };
        if values.len() != needed {
            return Err(usd_error(
                &attr,
                format!(
                    "has {} values, but interpolation \"{interpolation}\" needs {needed} ({per})",
                    values.len()
                ),
            ));
        }
        if needed == self.points {
            return Ok(Some(values));
        }
        let mut expanded = Vec::with_capacity(self.points);
        for (curve, &count) in self.counts.iter().enumerate() {
            let value = values[if needed == 1 { 0 } else { curve }];
            expanded.extend(std::iter::repeat_n(value, count));
        }
        Ok(Some(expanded))
    }
}
