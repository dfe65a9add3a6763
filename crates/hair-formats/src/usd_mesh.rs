//! USD `Mesh` prims, text `.usda` and binary `.usdc`, read as one [`TriangleMesh`]: every
//! `def Mesh` of the layer in namespace order (parents first), its `points`, `faceVertexCounts`
//! and `faceVertexIndices`, each polygon split into a fan of triangles from its first corner;
//! `orientation = "leftHanded"` reverses the windings. Each prim's points go through its
//! transform ops and its ancestors' (`xformOpOrder`, as `usd_xform.rs` composes them) at the
//! default time, a mirroring transform reversing the windings too; then the layer's `upAxis` and
//! `metersPerUnit`, then the reader's [`ImportAxes`](super::ImportAxes). Normals are computed from
//! the triangles (authored normals and primvars are not read) and composition arcs are not
//! followed. The same meshes over time: `usd_sequence.rs`.
//!
//! One parser per encoding: a text layer goes through the project's parser (`usda_mesh.rs`, as
//! text curves do), a binary crate file through the `openusd` crate behind the checks described
//! in `usd_crate.rs`. Both give their prims' values to the same join here, so the two encodings
//! of a mesh read the same, with the same messages; text errors add the line.

use std::collections::HashMap;
use std::path::Path;

use glam::DMat4;
use openusd::sdf;

use hair_core::mesh::{MeshError, TriangleMesh};

use super::curves::vector_text;
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::{ImportAxes, ImportOptions};
use super::usd_attrs::{Units, required, token_attribute};
use super::usd_layer::{Encoding, Layer, as_ints, as_points, sniff};
use super::usd_tracks::{chain, crate_stack};
use super::usd_xform::{OpStack, world};
use super::usda_mesh::{MeshValues, text_meshes};
use super::usda_values::Array;
use super::{finish_mesh, read_file};

/// Reads the `Mesh` prims of a USD file of either encoding (text `#usda` or binary `PXR-USDC`,
/// by its first bytes) as one triangle mesh [m, +Y up], at the default time, each through its
/// transform ops and its ancestors'. The mesh passes
/// [`TriangleMesh::validate`], has triangles and unit normals. The data is called
/// [`FormatError::IN_MEMORY`].
pub fn read_usd_mesh(bytes: &[u8], options: &ImportOptions) -> Result<TriangleMesh, FormatError> {
    read_mesh(bytes, options).map_err(FormatError::in_memory)
}

/// Reads the `Mesh` prims of a USD file (`.usda`, `.usdc` or `.usd`); errors name the file. See
/// [`read_usd_mesh`].
pub fn read_usd_mesh_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<TriangleMesh, FormatError> {
    read_file(path.as_ref(), |bytes| read_mesh(bytes, options))
}

fn read_mesh(bytes: &[u8], options: &ImportOptions) -> Result<TriangleMesh, FormatErrorKind> {
    options.axes.validate()?;
    let mut mesh = TriangleMesh::default();
    let mut found = false;
    match sniff(bytes)? {
        Encoding::Text => {
            let (units, stacks, prims) = text_meshes(bytes)?;
            for prim in prims {
                found = true;
                let mut prim = prim?;
                let chain: Vec<OpStack> = chain(&prim.path)
                    .iter()
                    .filter_map(|p| stacks.get(p).cloned())
                    .collect();
                let mirrored = place(&mut prim, &chain)?;
                add_prim(&mut mesh, &units, &options.axes, prim, mirrored)?;
            }
        }
        Encoding::Crate => {
            let mut layer = Layer::open(bytes)?;
            let units = Units::of(&mut layer)?;
            let mut stacks: HashMap<sdf::Path, Option<OpStack>> = HashMap::new();
            for path in layer.prims()? {
                if !layer.is_defined(&path, "Mesh")? {
                    continue;
                }
                found = true;
                let points = required(&mut layer, &path, "points", "a point3f[]", as_points)?;
                let counts = required(&mut layer, &path, "faceVertexCounts", "an int[]", as_ints)?;
                let indices =
                    required(&mut layer, &path, "faceVertexIndices", "an int[]", as_ints)?;
                let orientation = token_attribute(&mut layer, &path, "orientation", "rightHanded")?;
                let mut values = MeshValues {
                    path: path.to_string(),
                    line: None,
                    points: Array::from_values(points),
                    counts: Array::from_values(counts),
                    indices: Array::from_values(indices),
                    orientation: (orientation, None),
                };
                let mut chain = Vec::new();
                let mut ancestors: Vec<sdf::Path> = path.ancestors_below_root().collect();
                ancestors.reverse();
                for prim in ancestors {
                    if !stacks.contains_key(&prim) {
                        let stack = crate_stack(&mut layer, &prim)?;
                        stacks.insert(prim.clone(), stack);
                    }
                    if let Some(Some(stack)) = stacks.get(&prim) {
                        chain.push(stack.clone());
                    }
                }
                let mirrored = place(&mut values, &chain)?;
                add_prim(&mut mesh, &units, &options.axes, values, mirrored)?;
            }
        }
    }
    if !found {
        return Err(FormatErrorKind::Usd {
            element: "layer".into(),
            message: "has no Mesh prim (`def Mesh`)".into(),
            location: Location::Unknown,
        });
    }
    finish_mesh(mesh)
}

/// Moves a prim's points by its transform and its ancestors' (`stacks`, outermost first) at the
/// default time (each op's default, or else its earliest sample); returns whether the transform
/// mirrors (a negative determinant), which reverses the windings.
fn place(prim: &mut MeshValues, stacks: &[OpStack]) -> Result<bool, FormatErrorKind> {
    let world = world(stacks, None).map_err(|(attribute, message, line)| FormatErrorKind::Usd {
        element: attribute,
        message,
        location: line.map_or(Location::Unknown, Location::Line),
    })?;
    if world != DMat4::IDENTITY {
        for p in &mut prim.points.values {
            *p = world.transform_point3(p.as_dvec3()).as_vec3();
        }
    }
    Ok(world.determinant() < 0.0)
}

/// Adds one prim's polygons to `mesh` as triangles, its points converted by `units`, then `axes`;
/// `mirrored` (a transform with a negative determinant) reverses the windings, as the prim's
/// orientation does.
pub(crate) fn add_prim(
    mesh: &mut TriangleMesh,
    units: &Units,
    axes: &ImportAxes,
    prim: MeshValues,
    mirrored: bool,
) -> Result<(), FormatErrorKind> {
    let (orientation, orientation_line) = &prim.orientation;
    let left_handed = match orientation.as_str() {
        "rightHanded" => false,
        "leftHanded" => true,
        other => {
            let message = format!(
                "has orientation \"{}\" (allowed: rightHanded, leftHanded)",
                super::text::shorten(other)
            );
            return Err(prim.error(
                message,
                orientation_line.map_or(Location::Unknown, Location::Line),
            ));
        }
    };
    let points = &prim.points.values;
    let (raw_counts, indices) = (&prim.counts.values, &prim.indices.values);
    let mut counts = Vec::with_capacity(raw_counts.len());
    let mut sum: u128 = 0;
    for (i, &count) in raw_counts.iter().enumerate() {
        let Ok(count) = usize::try_from(count) else {
            let message = format!("faceVertexCounts[{i}] is negative ({count})");
            return Err(prim.error(message, prim.at(&prim.counts, i)));
        };
        sum += count as u128;
        counts.push(count);
    }
    if sum != indices.len() as u128 {
        let message = format!(
            "the faceVertexCounts add up to {sum}, but the prim has {} faceVertexIndices",
            indices.len()
        );
        return Err(prim.error(message, prim.at(&prim.counts, 0)));
    }
    if let Some(j) = points.iter().position(|p| !p.is_finite()) {
        return Err(FormatErrorKind::NonFinite {
            element: format!("{} point {j}", prim.path),
            what: "position",
            value: vector_text(points[j]),
            location: prim.at(&prim.points, j),
        });
    }
    let base = mesh.positions.len();
    let total = base as u64 + points.len() as u64;
    if u32::try_from(total).is_err() {
        return Err(FormatErrorKind::Mesh(MeshError::TooManyVertices {
            vertex_count: total as usize,
        }));
    }
    for (j, &p) in points.iter().enumerate() {
        let scaled = axes.point(units.point(p));
        if !scaled.is_finite() {
            return Err(FormatErrorKind::NonFinite {
                element: format!("{} point {j}", prim.path),
                what: "position",
                value: format!("{} (after scaling to metres)", vector_text(scaled)),
                location: prim.at(&prim.points, j),
            });
        }
        mesh.positions.push(scaled);
    }
    let mut start = 0usize;
    for (face, &count) in counts.iter().enumerate() {
        let corners = &indices[start..start + count];
        start += count;
        if count < 3 {
            let message = format!("face {face} has {count} vertices (a face needs 3 or more)");
            return Err(prim.error(message, prim.at(&prim.counts, face)));
        }
        let mut vertex = Vec::with_capacity(count);
        for (k, &index) in corners.iter().enumerate() {
            match usize::try_from(index).ok().filter(|&i| i < points.len()) {
                Some(i) => vertex.push((base + i) as u32),
                None => {
                    let at = start - count + k;
                    let message = format!(
                        "faceVertexIndices[{at}] = {index} (face {face}) names no point ({} \
                         points)",
                        points.len()
                    );
                    return Err(prim.error(message, prim.at(&prim.indices, at)));
                }
            }
        }
        for k in 1..count - 1 {
            let mut triangle = [vertex[0], vertex[k], vertex[k + 1]];
            if (left_handed != mirrored) != axes.reverses_winding() {
                triangle.swap(1, 2);
            }
            mesh.triangles.push(triangle);
        }
    }
    Ok(())
}
