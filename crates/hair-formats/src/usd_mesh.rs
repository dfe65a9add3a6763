//! USD `Mesh` prims, text `.usda` and binary `.usdc`, read through the `openusd` crate as one
//! [`TriangleMesh`]: every `def Mesh` of the layer in namespace order, its `points`,
//! `faceVertexCounts` and `faceVertexIndices`, each polygon split into a fan of triangles from its
//! first corner; `orientation = "leftHanded"` reverses the windings. The layer's `upAxis` and
//! `metersPerUnit` come first, then the reader's [`ImportAxes`](super::ImportAxes). Normals are
//! computed from the triangles (authored normals and primvars are not read), transforms are not
//! applied and composition arcs are not followed. See `usd_crate.rs` for how the
//! crate is guarded.

use std::path::Path;

use super::curves::vector_text;
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::usd_attrs::{Units, check_finite, counts, required, token_attribute};
use super::usd_layer::{Layer, as_ints, as_points, usd_error};
use super::{finish_mesh, read_file};
use hair_core::mesh::{MeshError, TriangleMesh};

/// Reads the `Mesh` prims of a USD file of either encoding (text `#usda` or binary `PXR-USDC`,
/// by its first bytes) as one triangle mesh [m, +Y up]. The mesh passes
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
    let mut layer = Layer::open(bytes)?;
    let units = Units::of(&mut layer)?;
    let axes = &options.axes;
    let mut mesh = TriangleMesh::default();
    let mut found = false;
    for path in layer.prims()? {
        if !layer.is_defined(&path, "Mesh")? {
            continue;
        }
        found = true;
        let points = required(&mut layer, &path, "points", "a point3f[]", as_points)?;
        let raw_counts = required(&mut layer, &path, "faceVertexCounts", "an int[]", as_ints)?;
        let indices = required(&mut layer, &path, "faceVertexIndices", "an int[]", as_ints)?;
        let orientation = token_attribute(&mut layer, &path, "orientation", "rightHanded")?;
        let left_handed = match orientation.as_str() {
            "rightHanded" => false,
            "leftHanded" => true,
            other => {
                return Err(usd_error(
                    &path,
                    format!(
                        "has orientation \"{}\" (allowed: rightHanded, leftHanded)",
                        super::text::shorten(other)
                    ),
                ));
            }
        };
        let counts = counts(
            &path,
            "faceVertexCounts",
            &raw_counts,
            indices.len(),
            "faceVertexIndices",
        )?;
        check_finite(&points, |j| format!("{path} point {j}"))?;
        let base = mesh.positions.len();
        let total = base as u64 + points.len() as u64;
        if u32::try_from(total).is_err() {
            return Err(FormatErrorKind::Mesh(MeshError::TooManyVertices {
                vertex_count: total as usize,
            }));
        }
        for &p in &points {
            let scaled = axes.point(units.point(p));
            if !scaled.is_finite() {
                return Err(FormatErrorKind::NonFinite {
                    element: format!("{path} point {}", mesh.positions.len() - base),
                    what: "position",
                    value: format!("{} (after scaling to metres)", vector_text(scaled)),
                    location: Location::Unknown,
                });
            }
            mesh.positions.push(scaled);
        }
        let mut start = 0usize;
        for (face, &count) in counts.iter().enumerate() {
            let corners = &indices[start..start + count];
            start += count;
            if count < 3 {
                return Err(usd_error(
                    &path,
                    format!("face {face} has {count} vertices (a face needs 3 or more)"),
                ));
            }
            let mut vertex = Vec::with_capacity(count);
            for (k, &index) in corners.iter().enumerate() {
                match usize::try_from(index).ok().filter(|&i| i < points.len()) {
                    Some(i) => vertex.push((base + i) as u32),
                    None => {
                        return Err(usd_error(
                            &path,
                            format!(
                                "faceVertexIndices[{}] = {index} (face {face}) names no point \
                                 ({} points)",
                                start - count + k,
                                points.len()
                            ),
                        ));
                    }
                }
            }
            for k in 1..count - 1 {
                let mut triangle = [vertex[0], vertex[k], vertex[k + 1]];
                if left_handed != axes.reverses_winding() {
                    triangle.swap(1, 2);
                }
                mesh.triangles.push(triangle);
            }
        }
    }
    if !found {
        return Err(usd_error("layer", "has no Mesh prim (`def Mesh`)"));
    }
    finish_mesh(mesh)
}
