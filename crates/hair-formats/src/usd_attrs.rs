//! What the USD readers of crate files (through the `openusd` crate) share: the layer's units
//! and up axis ([`Units`], which text meshes use too), and attribute values read, type-checked
//! and counted, with errors that name the prim or attribute path.

use glam::Vec3;
use openusd::sdf::{self, Value};

use super::curves::vector_text;
use super::error::{FormatErrorKind, Location};
use super::options::{ImportAxes, UpAxis};
use super::usd_layer::{Layer, type_name, usd_error};

/// The layer's units and axes: a point [file units] to the reader's input [m, +Y up].
pub(crate) struct Units {
    meters_per_unit: f64,
    up: ImportAxes,
}

impl Units {
    pub(crate) fn of(layer: &mut Layer) -> Result<Self, FormatErrorKind> {
        let root = sdf::Path::abs_root();
        let up = match layer.token(&root, "upAxis")?.as_deref() {
            None | Some("Y") => UpAxis::Y,
            Some("Z") => UpAxis::Z,
            Some(other) => {
                return Err(usd_error(
                    "layer",
                    format!(
                        "upAxis \"{}\" (allowed: \"Y\", \"Z\")",
                        super::text::shorten(other)
                    ),
                ));
            }
        };
        let meters_per_unit = match layer.field(&root, "metersPerUnit")? {
            None => 0.01,
            Some(Value::Double(m)) => m,
            Some(Value::Float(m)) => f64::from(m),
            Some(other) => {
                return Err(usd_error(
                    "layer",
                    format!("metersPerUnit is a {}, not a number", type_name(&other)),
                ));
            }
        };
        if !(meters_per_unit.is_finite() && meters_per_unit > 0.0) {
            return Err(usd_error(
                "layer",
                format!("metersPerUnit = {meters_per_unit} (allowed: a finite number > 0)"),
            ));
        }
        Ok(Units::new(up, meters_per_unit))
    }

    /// The units of a layer with `upAxis` `up` and `metersPerUnit` `meters_per_unit` (checked).
    pub(crate) fn new(up: UpAxis, meters_per_unit: f64) -> Self {
        Units {
            meters_per_unit,
            up: ImportAxes {
                up,
                ..ImportAxes::default()
            },
        }
    }

    /// A point in metres, +Y up (scaled in f64: 10 cm is 0.1 m exactly).
    pub(crate) fn point(&self, p: Vec3) -> Vec3 {
        self.up
            .point((p.as_dvec3() * self.meters_per_unit).as_vec3())
    }

    pub(crate) fn length(&self, l: f32) -> f32 {
        (f64::from(l) * self.meters_per_unit) as f32
    }
}

/// The value of a required attribute, converted by `convert`; errors name the attribute.
pub(crate) fn required<T>(
    layer: &mut Layer,
    prim: &sdf::Path,
    name: &str,
    expected: &str,
    convert: fn(&Value) -> Option<T>,
) -> Result<T, FormatErrorKind> {
    let Some((path, value)) = layer.attribute(prim, name)? else {
        return Err(usd_error(prim, format!("has no {name} value")));
    };
    convert(&value).ok_or_else(|| {
        usd_error(
            &path,
            format!("is a {}, expected {expected}", type_name(&value)),
        )
    })
}

/// The value of a token attribute (`type`, `wrap`, `orientation`), or `fallback`.
pub(crate) fn token_attribute(
    layer: &mut Layer,
    prim: &sdf::Path,
    name: &str,
    fallback: &str,
) -> Result<String, FormatErrorKind> {
    Ok(match layer.attribute(prim, name)? {
        Some((_, Value::Token(t))) => t.as_str().to_owned(),
        Some((_, Value::String(s))) => s,
        Some((path, other)) => {
            return Err(usd_error(
                &path,
                format!("is a {}, expected a token", type_name(&other)),
            ));
        }
        None => fallback.to_owned(),
    })
}

/// Checked non-negative counts that must add up to `total` (`points` or indices).
pub(crate) fn counts(
    prim: &sdf::Path,
    name: &str,
    values: &[i64],
    total: usize,
    of: &str,
) -> Result<Vec<usize>, FormatErrorKind> {
    let mut sum: u128 = 0;
    let mut out = Vec::with_capacity(values.len());
    for (i, &count) in values.iter().enumerate() {
        let Ok(count) = usize::try_from(count) else {
            return Err(usd_error(
                prim,
                format!("{name}[{i}] is negative ({count})"),
            ));
        };
        sum += count as u128;
        out.push(count);
    }
    if sum != total as u128 {
        return Err(usd_error(
            prim,
            format!("the {name} add up to {sum}, but the prim has {total} {of}"),
        ));
    }
    Ok(out)
}

/// The first non-finite point of `points`, as an error about `element(j)`.
pub(crate) fn check_finite(
    points: &[Vec3],
    element: impl Fn(usize) -> String,
) -> Result<(), FormatErrorKind> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(j) => Err(FormatErrorKind::NonFinite {
            element: element(j),
            what: "position",
            value: vector_text(points[j]),
            location: Location::Unknown,
        }),
        None => Ok(()),
    }
}
