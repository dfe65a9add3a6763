//! Indexed triangle meshes with vertex normals: the head, collision bodies, tessellated surfaces,
//! and the one check every consumer of a mesh (OBJ writer, collision bodies, lines of sight, the
//! renderer's head) runs on it: [`TriangleMesh::validate`].

use glam::Vec3;
use thiserror::Error;

use crate::transform::RigidTransform;

/// What makes a triangle mesh unusable, as found by [`TriangleMesh::validate`] and
/// [`TriangleMesh::validate_surface`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    /// More vertices than `u32` triangle indices can address.
    #[error("the mesh has {vertex_count} vertices, more than u32 indices can address")]
    TooManyVertices {
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// Normals are present but not one per vertex.
    #[error(
        "the mesh has {normal_count} normals for {vertex_count} vertices (expected as many, or none)"
    )]
    NormalCount {
        /// Number of normals.
        normal_count: usize,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A vertex position has a NaN or infinite coordinate.
    #[error("mesh vertex {vertex} is not finite: {position}")]
    NonFinitePosition {
        /// Index of the vertex.
        vertex: usize,
        /// Its position [m].
        position: Vec3,
    },
    /// A vertex normal has a NaN or infinite coordinate.
    #[error("mesh normal {vertex} is not finite: {normal}")]
    NonFiniteNormal {
        /// Index of the vertex (and of its normal).
        vertex: usize,
        /// The normal.
        normal: Vec3,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "triangle {triangle} refers to vertex {vertex}, but the mesh has {vertex_count} vertices"
    )]
    VertexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The out-of-range vertex index.
        vertex: u32,
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// The mesh has no triangles (where a surface is needed).
    #[error("the mesh has no triangles")]
    NoTriangles,
    /// Every triangle has zero area, so the mesh has no surface (where one is needed).
    #[error("all {triangle_count} triangles of the mesh have zero area")]
    Degenerate {
        /// Number of triangles (all degenerate).
        triangle_count: usize,
    },
}

/// An indexed triangle mesh [m]. Counter-clockwise triangles seen from outside.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions [m].
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position (may be empty when not computed).
    pub normals: Vec<Vec3>,
    /// Triangles as three indices into `positions`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The unit normal of triangle `index` (counter-clockwise winding), or zero for a degenerate one.
    pub fn triangle_normal(&self, index: usize) -> Vec3 {
        let [a, b, c] = self.triangles[index].map(|i| self.positions[i as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// The mesh moved rigidly by `pose`: positions transformed as points [m], normals rotated,
    /// triangles unchanged (a rigid motion keeps the winding).
    pub fn posed(&self, pose: &RigidTransform) -> TriangleMesh {
        TriangleMesh {
            positions: self
                .positions
                .iter()
                .map(|&p| pose.transform_point(p))
                .collect(),
            normals: self
                .normals
                .iter()
                .map(|&n| pose.transform_vector(n))
                .collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// Recomputes `normals` as area-weighted averages of the adjacent triangle normals.
    pub fn compute_vertex_normals(&mut self) {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for triangle in &self.triangles {
            let [a, b, c] = triangle.map(|i| self.positions[i as usize]);
            let weighted = (b - a).cross(c - a);
            for &i in triangle {
                normals[i as usize] += weighted;
            }
        }
        for normal in &mut normals {
            *normal = normal.normalize_or_zero();
        }
        self.normals = normals;
    }

    /// Checks that the mesh is well formed: its vertex count fits `u32` indices, it has one
    /// normal per vertex or none, every position and normal is finite, and every triangle index
    /// names a vertex. A mesh without triangles passes (it draws and writes nothing); use
    /// [`TriangleMesh::validate_surface`] where a surface is needed. Reports the first problem
    /// found, in that order.
    pub fn validate(&self) -> Result<(), MeshError> {
        let vertex_count = self.positions.len();
        if u32::try_from(vertex_count).is_err() {
            return Err(MeshError::TooManyVertices { vertex_count });
        }
        if !self.normals.is_empty() && self.normals.len() != vertex_count {
            return Err(MeshError::NormalCount {
                normal_count: self.normals.len(),
                vertex_count,
            });
        }
        if let Some(vertex) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinitePosition {
                vertex,
                position: self.positions[vertex],
            });
        }
        if let Some(vertex) = self.normals.iter().position(|n| !n.is_finite()) {
            return Err(MeshError::NonFiniteNormal {
                vertex,
                normal: self.normals[vertex],
            });
        }
        for (triangle, indices) in self.triangles.iter().enumerate() {
            if let Some(&vertex) = indices.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(MeshError::VertexOutOfRange {
                    triangle,
                    vertex,
                    vertex_count,
                });
            }
        }
        Ok(())
    }

    /// [`TriangleMesh::validate`], and the mesh has a surface: at least one triangle, and not
    /// all of them of zero area. What a collision body or a line-of-sight blocker needs.
    pub fn validate_surface(&self) -> Result<(), MeshError> {
        self.validate()?;
        if self.triangles.is_empty() {
            return Err(MeshError::NoTriangles);
        }
        if (0..self.triangles.len()).all(|t| self.triangle_normal(t) == Vec3::ZERO) {
            return Err(MeshError::Degenerate {
                triangle_count: self.triangles.len(),
            });
        }
        Ok(())
    }

    /// Axis-aligned bounds `(min, max)` [m]; `None` for an empty mesh.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A posed mesh is the mesh whose normals are recomputed after the motion: a rigid motion
    /// keeps lengths and winding, so normals rotate with it.
    #[test]
    fn posing_moves_points_and_turns_normals() {
        let mesh = tetrahedron();
        let pose = RigidTransform::new(
            glam::Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
            Vec3::new(0.1, -0.2, 0.3),
        );
        let posed = mesh.posed(&pose);
        let mut recomputed = posed.clone();
        recomputed.compute_vertex_normals();
        assert_eq!(posed.triangles, mesh.triangles);
        for (a, b) in posed.normals.iter().zip(&recomputed.normals) {
            assert!(a.distance(*b) < 1e-6, "{a} against {b}");
        }
        assert!(posed.positions[0].distance(pose.translation) < 1e-7);
    }

    #[test]
    fn tetrahedron_normals_point_outwards() {
        let mesh = tetrahedron();
        let centre = Vec3::splat(0.25);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!((*p - centre).dot(*n) > 0.0);
        }
        assert_eq!(mesh.triangle_normal(3), Vec3::ONE.normalize());
    }

    /// A closed tetrahedron with outward windings and vertex normals (shared with other tests).
    pub(crate) fn tetrahedron() -> TriangleMesh {
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            normals: Vec::new(),
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        };
        mesh.compute_vertex_normals();
        mesh
    }

    #[test]
    fn a_well_formed_mesh_passes_and_an_empty_one_has_no_surface() {
        let mesh = tetrahedron();
        assert_eq!(mesh.validate(), Ok(()));
        assert_eq!(mesh.validate_surface(), Ok(()));
        let without_normals = TriangleMesh {
            normals: Vec::new(),
            ..tetrahedron()
        };
        assert_eq!(without_normals.validate_surface(), Ok(()));
        let empty = TriangleMesh::default();
        assert_eq!(empty.validate(), Ok(()));
        assert_eq!(empty.validate_surface(), Err(MeshError::NoTriangles));
        assert_eq!(
            empty.validate_surface().unwrap_err().to_string(),
            "the mesh has no triangles"
        );
    }

    #[test]
    fn a_nan_position_is_named() {
        let mut mesh = tetrahedron();
        mesh.positions[2].y = f32::NAN;
        let error = mesh.validate().unwrap_err();
        assert!(
            matches!(error, MeshError::NonFinitePosition { vertex: 2, .. }),
            "{error:?}"
        );
        assert!(
            error.to_string().contains("vertex 2 is not finite"),
            "{error}"
        );
        mesh.positions[2] = Vec3::new(0.0, f32::INFINITY, 0.0);
        assert!(matches!(
            mesh.validate_surface(),
            Err(MeshError::NonFinitePosition { vertex: 2, .. })
        ));
    }

    #[test]
    fn a_nan_normal_is_named() {
        let mut mesh = tetrahedron();
        mesh.normals[1] = Vec3::new(0.0, 0.0, f32::NAN);
        let error = mesh.validate().unwrap_err();
        assert!(
            matches!(error, MeshError::NonFiniteNormal { vertex: 1, .. }),
            "{error:?}"
        );
        assert!(
            error.to_string().contains("normal 1 is not finite"),
            "{error}"
        );
    }

    #[test]
    fn an_index_past_the_vertices_is_named() {
        let mut mesh = tetrahedron();
        mesh.triangles.push([0, 1, 99]);
        let error = mesh.validate().unwrap_err();
        assert_eq!(
            error,
            MeshError::VertexOutOfRange {
                triangle: 4,
                vertex: 99,
                vertex_count: 4
            }
        );
        assert_eq!(
            error.to_string(),
            "triangle 4 refers to vertex 99, but the mesh has 4 vertices"
        );
    }

    #[test]
    fn normals_must_be_one_per_vertex_or_none() {
        let mut mesh = tetrahedron();
        mesh.normals.pop();
        let error = mesh.validate().unwrap_err();
        assert_eq!(
            error,
            MeshError::NormalCount {
                normal_count: 3,
                vertex_count: 4
            }
        );
        assert!(
            error.to_string().contains("3 normals for 4 vertices"),
            "{error}"
        );
    }

    #[test]
    fn a_mesh_of_zero_area_triangles_has_no_surface() {
        // Three collinear points, and a triangle repeating one vertex.
        let mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X],
            normals: Vec::new(),
            triangles: vec![[0, 1, 2], [0, 0, 1]],
        };
        assert_eq!(
            mesh.validate(),
            Ok(()),
            "well formed, drawable (as nothing)"
        );
        let error = mesh.validate_surface().unwrap_err();
        assert_eq!(error, MeshError::Degenerate { triangle_count: 2 });
        assert!(error.to_string().contains("zero area"), "{error}");
        // One degenerate triangle among good ones is fine.
        let mut mesh = tetrahedron();
        mesh.triangles.push([0, 0, 1]);
        assert_eq!(mesh.validate_surface(), Ok(()));
    }
}
