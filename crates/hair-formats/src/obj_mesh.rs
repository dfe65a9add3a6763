//! Wavefront OBJ triangle meshes, read with `tobj`: every object of the file joined into one
//! [`TriangleMesh`], polygons split into triangle fans, points and lines left aside, materials not
//! loaded. Normals are the file's where every vertex has one, else computed from the triangles.
//! `tobj` reports no line numbers, so its errors name none.

use std::path::Path;

use glam::Vec3;

use super::curves::vector_text;
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::text::lines;
use super::{finish_mesh, read_file};
use hair_core::mesh::TriangleMesh;

/// Reads the triangles of an OBJ file from its bytes (metres before `options.axes`). The mesh
/// passes [`TriangleMesh::validate`], has triangles and unit normals. The data is called
/// [`FormatError::IN_MEMORY`].
pub fn read_obj_mesh(bytes: &[u8], options: &ImportOptions) -> Result<TriangleMesh, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads the triangles of an OBJ file; errors name the file. See [`read_obj_mesh`].
pub fn read_obj_mesh_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<TriangleMesh, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

/// Checks the `v` records before `tobj` reads them, to name the line of a non-finite one (`tobj`
/// reads `nan` and `inf` as numbers, and renumbers vertices). Malformed records are left to
/// `tobj`.
fn check_vertices(bytes: &[u8], options: &ImportOptions) -> Result<(), FormatErrorKind> {
    let mut vertex = 0usize;
    for line in lines(bytes) {
        let Ok((line, text)) = line else {
            continue;
        };
        let mut tokens = text.split_whitespace();
        if tokens.next() != Some("v") {
            continue;
        }
        vertex += 1;
        let mut xyz = [0.0f32; 3];
        for (slot, token) in xyz.iter_mut().zip(tokens) {
            *slot = token.parse().unwrap_or(0.0);
        }
        let p = Vec3::from_array(xyz);
        let scaled = options.axes.point(p);
        if !scaled.is_finite() {
            let value = if p.is_finite() {
                format!("{} (after scaling to metres)", vector_text(scaled))
            } else {
                vector_text(p)
            };
            return Err(FormatErrorKind::NonFinite {
                element: format!("OBJ vertex {vertex}"),
                what: "position",
                value,
                location: Location::Line(line),
            });
        }
    }
    Ok(())
}

fn read(bytes: &[u8], options: &ImportOptions) -> Result<TriangleMesh, FormatErrorKind> {
    options.axes.validate()?;
    check_vertices(bytes, options)?;
    let axes = &options.axes;
    // The update fills the fields behind tobj's `merging` and `reordering` features, should another
    // crate of the workspace enable them.
    #[allow(clippy::needless_update)]
    let load = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj_buf(&mut &bytes[..], &load, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|error| FormatErrorKind::Obj(error.to_string()))?;
    let mut mesh = TriangleMesh::default();
    let mut with_normals = true;
    for model in &models {
        let part = &model.mesh;
        let base = mesh.positions.len();
        let count = part.positions.len() / 3;
        let new_total = base as u64 + count as u64;
        if u32::try_from(new_total).is_err() {
            return Err(FormatErrorKind::Mesh(
                hair_core::mesh::MeshError::TooManyVertices {
                    vertex_count: new_total as usize,
                },
            ));
        }
        for (i, p) in part.positions.chunks_exact(3).enumerate() {
            let p = Vec3::new(p[0], p[1], p[2]);
            let scaled = axes.point(p);
            if !scaled.is_finite() {
                return Err(FormatErrorKind::NonFinite {
                    element: format!("vertex {} of object `{}`", i, model.name),
                    what: "position",
                    value: vector_text(p),
                    location: Location::Unknown,
                });
            }
            mesh.positions.push(scaled);
        }
        with_normals &= part.normals.len() == part.positions.len();
        if with_normals {
            mesh.normals.extend(
                part.normals
                    .chunks_exact(3)
                    .map(|n| axes.direction(Vec3::new(n[0], n[1], n[2]))),
            );
        }
        for corners in part.indices.chunks_exact(3) {
            let mut triangle = [0u32; 3];
            for (slot, &index) in triangle.iter_mut().zip(corners) {
                // Out-of-range indices stay out of range and are caught by the mesh check.
                *slot = (base as u64 + u64::from(index)).min(u64::from(u32::MAX)) as u32;
            }
            if axes.reverses_winding() {
                triangle.swap(1, 2);
            }
            mesh.triangles.push(triangle);
        }
    }
    if !with_normals || mesh.normals.iter().any(|n| !n.is_finite()) {
        mesh.normals.clear();
    }
    finish_mesh(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obj::ObjWriter;

    /// A closed tetrahedron with outward windings and vertex normals (hair-core's mesh test's).
    fn tetrahedron() -> TriangleMesh {
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            normals: Vec::new(),
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        };
        mesh.compute_vertex_normals();
        mesh
    }

    #[test]
    fn a_written_mesh_reads_back() {
        for with_normals in [true, false] {
            let mut mesh = tetrahedron();
            if !with_normals {
                mesh.normals.clear();
            }
            let mut writer = ObjWriter::new(Vec::new());
            writer.mesh(&mesh).unwrap();
            let bytes = writer.finish().unwrap();
            let read = read_obj_mesh(&bytes, &ImportOptions::default()).unwrap();
            // tobj renumbers vertices in order of first use: compare the corners.
            let corners = |m: &TriangleMesh, normals: &[Vec3]| -> Vec<[(Vec3, Vec3); 3]> {
                m.triangles
                    .iter()
                    .map(|t| t.map(|i| (m.positions[i as usize], normals[i as usize])))
                    .collect()
            };
            let expected = tetrahedron();
            let (read_corners, expected_corners) = (
                corners(&read, &read.normals),
                corners(&expected, &expected.normals),
            );
            for (a, b) in read_corners
                .iter()
                .flatten()
                .zip(expected_corners.iter().flatten())
            {
                assert_eq!(a.0, b.0);
                assert!(a.1.distance(b.1) < 1e-6, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn quads_become_triangles_and_points_need_faces() {
        let quad = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
        let mesh = read_obj_mesh(quad, &ImportOptions::default()).unwrap();
        assert_eq!(mesh.triangle_count(), 2);
        assert!(mesh.normals.iter().all(|n| *n == Vec3::Z));
        let error = read_obj_mesh(b"v 0 0 0\nv 1 0 0\nl 1 2\n", &Default::default()).unwrap_err();
        assert_eq!(error.to_string(), "<memory>: the mesh has no triangles");
    }

    #[test]
    fn a_nan_vertex_names_its_line() {
        let text = b"v 0 0 0\nv 1 0 0\n# comment\nv 0 nan 0\nf 1 2 3\n";
        let error = read_obj_mesh(text, &Default::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: OBJ vertex 3 at line 4: position [0, NaN, 0] is not finite"
        );
    }

    #[test]
    fn a_bad_face_is_a_tobj_error() {
        let error = read_obj_mesh(b"v 0 0 0\nf 1 2 3\n", &Default::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: OBJ: face vertex index out of bounds"
        );
    }
}
