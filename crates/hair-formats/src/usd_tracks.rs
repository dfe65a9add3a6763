//! The `Mesh` prims of a USD layer with every time sample, and the transform ops above them,
//! from either encoding, for the mesh sequence reader (`usd_sequence.rs`): a text layer through
//! the project's parser (`usda_parse.rs`, keeping every sample), a binary crate file through the
//! `openusd` crate (`usd_layer.rs`).

use std::collections::HashMap;

use glam::Vec3;
use openusd::sdf::{self, Value};

use super::error::{FormatErrorKind, Location};
use super::usd_attrs::{Units, token_attribute};
use super::usd_layer::{Layer, as_ints, as_numbers, as_points, type_name, usd_error};
use super::usd_xform::{Op, OpStack, Timed};
use super::usda_parse::parse_layer_sequence;
use super::usda_prims::{PrimKind, XformPrim};
use super::usda_values::{Array, Attr, Sample};

/// One `Mesh` prim over time, from either encoding.
pub(crate) struct MeshTrack {
    /// The prim's path (`/body/skin`).
    pub(crate) path: String,
    /// The line of the prim's name (text), or `None` (a crate file names no lines).
    pub(crate) line: Option<usize>,
    pub(crate) points: Timed<Array<Vec3>>,
    pub(crate) counts: Timed<Array<i64>>,
    pub(crate) indices: Timed<Array<i64>>,
    /// `orientation` (uniform) and its line (text).
    pub(crate) orientation: (String, Option<usize>),
    /// The transforms of the prim's ancestors that have one, outermost first, then its own.
    pub(crate) stacks: Vec<OpStack>,
}

/// A layer's meshes over time.
pub(crate) struct Tracks {
    pub(crate) units: Units,
    pub(crate) time_codes_per_second: f64,
    pub(crate) meshes: Vec<MeshTrack>,
}

/// USD's fallback when a layer names no rate [time codes per second].
const DEFAULT_TIME_CODES_PER_SECOND: f64 = 24.0;

/// An attribute of a text layer over time.
fn timed<T: Sample>(attr: Option<Attr<T>>) -> Option<Timed<T>> {
    attr.map(|attr| Timed::new(attr.default.flatten(), attr.samples))
}

/// The paths from the outermost ancestor of `path` (`/a/b/c`) to itself: `/a`, `/a/b`, `/a/b/c`.
pub(crate) fn chain(path: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, c) in path.char_indices().skip(1) {
        if c == '/' {
            out.push(path[..i].to_owned());
        }
    }
    out.push(path.to_owned());
    out
}

/// A prim's ops in `xformOpOrder` order, from the order's entries and the values of each op's
/// attribute (`values(attribute)`, `None` when not authored); errors name `element`.
fn op_stack(
    path: &str,
    line: Option<usize>,
    order: &[String],
    mut values: impl FnMut(&str) -> Result<Option<Timed<Vec<f64>>>, FormatErrorKind>,
) -> Result<OpStack, FormatErrorKind> {
    let location = line.map_or(Location::Unknown, Location::Line);
    let error = |message: String| FormatErrorKind::Usd {
        element: format!("{path}.xformOpOrder"),
        message,
        location,
    };
    let mut stack = OpStack {
        path: path.to_owned(),
        line,
        reset: false,
        ops: Vec::new(),
    };
    for (i, entry) in order.iter().enumerate() {
        if entry == "!resetXformStack!" {
            if i != 0 {
                return Err(error(format!(
                    "has \"!resetXformStack!\" at entry {i}; it may only come first"
                )));
            }
            stack.reset = true;
            continue;
        }
        let attribute = entry.strip_prefix("!invert!").unwrap_or(entry);
        let timed = match values(attribute)? {
            Some(timed) => timed,
            None if attribute.starts_with("xformOp:") => {
                return Err(error(format!(
                    "names \"{entry}\", but the prim has no attribute {attribute}"
                )));
            }
            // Not an op at all: `Op::new` says so.
            None => Timed::new(None, Vec::new()),
        };
        stack.ops.push(Op::new(entry, timed).map_err(error)?);
    }
    Ok(stack)
}

/// The meshes of a text layer, with every sample.
pub(crate) fn text_tracks(bytes: &[u8]) -> Result<Tracks, FormatErrorKind> {
    let text = super::text::utf8_text(bytes)?;
    let layer = parse_layer_sequence(text, PrimKind::Mesh)?;
    let units = Units::new(layer.up, layer.meters_per_unit);
    let mut stacks = HashMap::new();
    for xform in layer.xforms {
        let stack = text_stack(xform)?;
        stacks.insert(stack.path.clone(), stack);
    }
    let mut meshes = Vec::with_capacity(layer.meshes.len());
    for prim in layer.meshes {
        let missing = |name: &str| FormatErrorKind::Usd {
            element: prim.path.clone(),
            message: format!("has no {name} value"),
            location: Location::Line(prim.line),
        };
        let points = timed(prim.points).ok_or_else(|| missing("points"))?;
        let counts = timed(prim.face_vertex_counts).ok_or_else(|| missing("faceVertexCounts"))?;
        let indices =
            timed(prim.face_vertex_indices).ok_or_else(|| missing("faceVertexIndices"))?;
        let orientation = match prim.orientation {
            Some(attr) => {
                let line = attr.line;
                let value = attr
                    .default
                    .flatten()
                    .or_else(|| attr.samples.into_iter().find_map(|(_, v)| v));
                (value.unwrap_or_else(|| "rightHanded".into()), Some(line))
            }
            None => ("rightHanded".to_owned(), None),
        };
        let stacks = chain(&prim.path)
            .iter()
            .filter_map(|p| stacks.get(p).cloned())
            .collect();
        meshes.push(MeshTrack {
            path: prim.path,
            line: Some(prim.line),
            points,
            counts,
            indices,
            orientation,
            stacks,
        });
    }
    Ok(Tracks {
        units,
        time_codes_per_second: layer
            .time_codes_per_second
            .or(layer.frames_per_second)
            .unwrap_or(DEFAULT_TIME_CODES_PER_SECOND),
        meshes,
    })
}

/// A text prim's transform.
pub(crate) fn text_stack(xform: XformPrim) -> Result<OpStack, FormatErrorKind> {
    let XformPrim {
        path,
        line,
        order,
        ops,
    } = xform;
    let order = order.map(|attr| {
        let line = attr.line;
        let value = attr
            .default
            .clone()
            .flatten()
            .or_else(|| attr.kept_samples().into_iter().find_map(|(_, v)| v));
        (value.map(|a| a.values).unwrap_or_default(), line)
    });
    let (order, order_line) = order.unwrap_or((Vec::new(), line));
    op_stack(&path, Some(order_line), &order, |attribute| {
        let Some(index) = ops.iter().position(|(name, _)| name == attribute) else {
            return Ok(None);
        };
        // An op may be named twice (`xformOp:translate:pivot` and its `!invert!`).
        Ok(ops[index].1.as_ref().map(|attr| {
            let numbers = |a: &Option<Array<f64>>| a.as_ref().map(|a| a.values.clone());
            Timed::new(
                attr.default.as_ref().and_then(numbers),
                attr.kept_samples()
                    .iter()
                    .map(|(t, v)| (*t, numbers(v)))
                    .collect(),
            )
        }))
    })
}

/// Attribute `name` of `prim` in a crate file over time, converted by `convert`; `None` when not
/// authored. Errors name the attribute and the time code.
fn crate_timed<T: Clone>(
    layer: &mut Layer,
    prim: &sdf::Path,
    name: &str,
    expected: &str,
    convert: fn(&Value) -> Option<T>,
) -> Result<Option<Timed<T>>, FormatErrorKind> {
    let Some((path, default, samples)) = layer.attribute_samples(prim, name)? else {
        return Ok(None);
    };
    let value = |value: Value, when: &str| match value {
        Value::ValueBlock => Ok(None),
        value => convert(&value).map(Some).ok_or_else(|| {
            usd_error(
                &path,
                format!("{when}is a {}, expected {expected}", type_name(&value)),
            )
        }),
    };
    let default = match default {
        Some(v) => value(v, "")?,
        None => None,
    };
    let mut converted = Vec::with_capacity(samples.len());
    for (t, v) in samples {
        converted.push((t, value(v, &format!("at time code {t} "))?));
    }
    if default.is_none() && converted.is_empty() {
        return Ok(None);
    }
    Ok(Some(Timed::new(default, converted)))
}

/// The meshes of a binary crate file, with every sample.
pub(crate) fn crate_tracks(bytes: &[u8]) -> Result<Tracks, FormatErrorKind> {
    let mut layer = Layer::open(bytes)?;
    let units = Units::of(&mut layer)?;
    let root = sdf::Path::abs_root();
    let mut rate = None;
    for field in ["timeCodesPerSecond", "framesPerSecond"] {
        let value = match layer.field(&root, field)? {
            None => continue,
            Some(Value::Double(r)) => r,
            Some(Value::Float(r)) => f64::from(r),
            Some(other) => {
                let message = format!("{field} is a {}, not a number", type_name(&other));
                return Err(usd_error("layer", message));
            }
        };
        if !(value.is_finite() && value > 0.0) {
            let message = format!("{field} = {value} (allowed: a finite number > 0)");
            return Err(usd_error("layer", message));
        }
        rate = rate.or(Some(value));
    }
    let mut stacks: HashMap<sdf::Path, Option<OpStack>> = HashMap::new();
    let mut meshes = Vec::new();
    for path in layer.prims()? {
        if !layer.is_defined(&path, "Mesh")? {
            continue;
        }
        let missing = |name: &str| usd_error(&path, format!("has no {name} value"));
        let points = crate_timed(&mut layer, &path, "points", "a point3f[]", |v| {
            as_points(v).map(Array::from_values)
        })?
        .ok_or_else(|| missing("points"))?;
        let counts = crate_timed(&mut layer, &path, "faceVertexCounts", "an int[]", |v| {
            as_ints(v).map(Array::from_values)
        })?
        .ok_or_else(|| missing("faceVertexCounts"))?;
        let indices = crate_timed(&mut layer, &path, "faceVertexIndices", "an int[]", |v| {
            as_ints(v).map(Array::from_values)
        })?
        .ok_or_else(|| missing("faceVertexIndices"))?;
        let orientation = token_attribute(&mut layer, &path, "orientation", "rightHanded")?;
        let mut chain: Vec<sdf::Path> = path.ancestors_below_root().collect();
        chain.reverse();
        let mut mesh_stacks = Vec::new();
        for prim in chain {
            if !stacks.contains_key(&prim) {
                let stack = crate_stack(&mut layer, &prim)?;
                stacks.insert(prim.clone(), stack);
            }
            if let Some(Some(stack)) = stacks.get(&prim) {
                mesh_stacks.push(stack.clone());
            }
        }
        meshes.push(MeshTrack {
            path: path.to_string(),
            line: None,
            points,
            counts,
            indices,
            orientation: (orientation, None),
            stacks: mesh_stacks,
        });
    }
    Ok(Tracks {
        units,
        time_codes_per_second: rate.unwrap_or(DEFAULT_TIME_CODES_PER_SECOND),
        meshes,
    })
}

/// A crate prim's transform; `None` when it has no `xformOpOrder`.
pub(crate) fn crate_stack(
    layer: &mut Layer,
    prim: &sdf::Path,
) -> Result<Option<OpStack>, FormatErrorKind> {
    let Some((path, value)) = layer.attribute(prim, "xformOpOrder")? else {
        return Ok(None);
    };
    let order: Vec<String> = match value {
        Value::TokenVec(tokens) => tokens.iter().map(|t| t.as_str().to_owned()).collect(),
        Value::StringVec(strings) => strings,
        other => {
            let message = format!("is a {}, expected a token[]", type_name(&other));
            return Err(usd_error(&path, message));
        }
    };
    let stack = op_stack(prim.as_str(), None, &order, |attribute| {
        crate_timed(
            layer,
            prim,
            attribute,
            "a number, vector, quaternion or matrix4d",
            as_numbers,
        )
    })?;
    Ok(Some(stack))
}

#[cfg(test)]
mod tests {
    use super::chain;

    #[test]
    fn a_chain_runs_from_the_outermost_ancestor() {
        assert_eq!(chain("/a/b/c"), ["/a", "/a/b", "/a/b/c"]);
        assert_eq!(chain("/a"), ["/a"]);
    }
}
