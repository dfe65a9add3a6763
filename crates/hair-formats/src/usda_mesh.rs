//! USD text (`.usda`) `Mesh` prims through the project's parser (`usda_parse.rs`), the same that
//! reads text curves: each `def Mesh`'s `points`, `faceVertexCounts`, `faceVertexIndices` and
//! `orientation` at the default time (the default value, or else the earliest time sample), for
//! the join in `usd_mesh.rs`; and what both encodings hand to that join ([`MeshValues`]).

use std::collections::HashMap;

use glam::Vec3;

use super::error::{FormatErrorKind, Location};
use super::usd_attrs::Units;
use super::usd_tracks::text_stack;
use super::usd_xform::OpStack;
use super::usda_parse::parse_layer;
use super::usda_prims::{MeshPrim, PrimKind};
use super::usda_values::Array;

/// One `Mesh` prim's values at the default time, from either encoding (the crate file's reader
/// in `usd_mesh.rs` fills one too).
pub(crate) struct MeshValues {
    /// The prim's path (`/body/head`).
    pub(crate) path: String,
    /// The line of the prim's name (text), or `None` (a crate file names no lines).
    pub(crate) line: Option<usize>,
    /// `points` [file units], with their lines (text).
    pub(crate) points: Array<Vec3>,
    /// `faceVertexCounts`, with their lines (text).
    pub(crate) counts: Array<i64>,
    /// `faceVertexIndices`, with their lines (text).
    pub(crate) indices: Array<i64>,
    /// `orientation` (`rightHanded` when not authored) and its line (text).
    pub(crate) orientation: (String, Option<usize>),
}

impl MeshValues {
    /// Where value `i` of `array` is: its line in a text layer, unknown in a crate file.
    pub(crate) fn at<T>(&self, array: &Array<T>, i: usize) -> Location {
        self.line.map_or(Location::Unknown, |prim| {
            Location::Line(array.line(i, prim))
        })
    }

    /// An error about the prim at `location`.
    pub(crate) fn error(&self, message: String, location: Location) -> FormatErrorKind {
        FormatErrorKind::Usd {
            element: self.path.clone(),
            message,
            location,
        }
    }
}

/// The layer's units, the transforms of its prims by path, and its `Mesh` prims' values, in
/// namespace order; each prim is an error when it lacks one of the three arrays.
#[allow(clippy::type_complexity)]
pub(crate) fn text_meshes(
    bytes: &[u8],
) -> Result<
    (
        Units,
        HashMap<String, OpStack>,
        impl Iterator<Item = Result<MeshValues, FormatErrorKind>>,
    ),
    FormatErrorKind,
> {
    let text = super::text::utf8_text(bytes)?;
    let layer = parse_layer(text, None, PrimKind::Mesh)?;
    let units = Units::new(layer.up, layer.meters_per_unit);
    let mut stacks = HashMap::new();
    for xform in layer.xforms {
        let stack = text_stack(xform)?;
        stacks.insert(stack.path.clone(), stack);
    }
    Ok((units, stacks, layer.meshes.into_iter().map(values)))
}

/// A prim's values at the default time.
fn values(prim: MeshPrim) -> Result<MeshValues, FormatErrorKind> {
    let missing = |name: &str| FormatErrorKind::Usd {
        element: prim.path.clone(),
        message: format!("has no {name} value"),
        location: Location::Line(prim.line),
    };
    let points = prim
        .points
        .and_then(|attr| attr.resolve(None))
        .ok_or_else(|| missing("points"))?;
    let counts = prim
        .face_vertex_counts
        .and_then(|attr| attr.resolve(None))
        .ok_or_else(|| missing("faceVertexCounts"))?;
    let indices = prim
        .face_vertex_indices
        .and_then(|attr| attr.resolve(None))
        .ok_or_else(|| missing("faceVertexIndices"))?;
    let orientation = match prim.orientation {
        Some(attr) => {
            let line = attr.line;
            (
                attr.resolve(None)
                    .unwrap_or_else(|| "rightHanded".to_owned()),
                Some(line),
            )
        }
        None => ("rightHanded".to_owned(), None),
    };
    Ok(MeshValues {
        path: prim.path,
        line: Some(prim.line),
        points,
        counts,
        indices,
        orientation,
    })
}
