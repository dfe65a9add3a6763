//! Line of sight past a rigid body: whether a viewer at an eye point sees a point of the hair or
//! the body (the head) is in the way. A parry3d `TriMesh` of the body's mesh answers the ray
//! casts; the accuracy metrics use it to count only the hair a viewer can see.

use glam::{Quat, Vec3};
use hair_core::TriangleMesh;
use parry3d::query::{Ray, RayCast};
use parry3d::shape::TriMesh;

use crate::error::{CollideError, Result, require_pose};

/// A rigid, posed triangle mesh that blocks lines of sight.
#[derive(Debug, Clone)]
pub struct LineOfSight {
    mesh: TriMesh,
    rotation: Quat,
    translation: Vec3,
}

impl LineOfSight {
    /// A blocker from `mesh`, given in its own frame \[m\], at the identity pose. Errors
    /// ([`CollideError::Mesh`]) on a mesh that fails [`TriangleMesh::validate_surface`]: no
    /// triangles or only zero-area ones, a triangle indexing past the vertices, a position or
    /// normal not finite, normals not one per vertex.
    pub fn new(mesh: &TriangleMesh) -> Result<Self> {
        mesh.validate_surface()?;
        let trimesh =
            TriMesh::new(mesh.positions.clone(), mesh.triangles.clone()).map_err(|error| {
                CollideError::InvalidParameter {
                    name: "mesh",
                    value: error.to_string(),
                    allowed: "a mesh with at least one triangle",
                }
            })?;
        Ok(LineOfSight {
            mesh: trimesh,
            rotation: Quat::IDENTITY,
            translation: Vec3::ZERO,
        })
    }

    /// Places the blocker: world = `rotation` · local + `translation` \[m\]. Errors on a
    /// non-finite or zero rotation or a non-finite translation, leaving the pose unchanged.
    pub fn set_pose(&mut self, rotation: Quat, translation: Vec3) -> Result<()> {
        self.rotation = require_pose(rotation, translation)?;
        self.translation = translation;
        Ok(())
    }

    /// Whether `point` \[m, world\] can be seen from `eye`: the open segment from the eye to the
    /// point, less its last `margin` metres, crosses no triangle of the body. The margin lets hair
    /// lying on the surface (roots on the scalp) count as seen; a point deeper inside the body
    /// than `margin` is hidden. Non-finite input is never visible.
    pub fn is_visible(&self, eye: Vec3, point: Vec3, margin: f32) -> bool {
        if !(eye.is_finite() && point.is_finite() && margin.is_finite()) {
            return false;
        }
        let inverse = self.rotation.conjugate();
        let origin = inverse * (eye - self.translation);
        let target = inverse * (point - self.translation);
        let direction = target - origin;
        let length = direction.length();
        if length <= margin {
            return true;
        }
        // Time of impact in units of `direction`: the point is at 1.
        let reach = 1.0 - margin.max(0.0) / length;
        !self
            .mesh
            .intersects_local_ray(&Ray::new(origin, direction), reach)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube [-1, 1]³ as 12 counter-clockwise triangles.
    fn cube() -> TriangleMesh {
        let positions: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                )
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles = quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
            .collect();
        TriangleMesh {
            positions,
            normals: Vec::new(),
            triangles,
        }
    }

    #[test]
    fn the_cube_hides_what_is_behind_it_and_not_what_is_beside_it() {
        let sight = LineOfSight::new(&cube()).unwrap();
        let eye = Vec3::new(0.0, 0.0, 5.0);
        // Straight through the cube: hidden.
        assert!(!sight.is_visible(eye, Vec3::new(0.0, 0.0, -3.0), 0.0));
        // In front of the cube: seen.
        assert!(sight.is_visible(eye, Vec3::new(0.0, 0.0, 2.0), 0.0));
        // Past the cube's edge (x = 1.2 at z = −3 is seen along a line with x = 0.15·(5 − z),
        // which is 0.6 at z = 1 and 0.9 at z = −1, inside the cube's x range): hidden.
        assert!(!sight.is_visible(eye, Vec3::new(1.2, 0.0, -3.0), 0.0));
        // Well beside it: the line x = 0.375·(5 − z) is 1.5 at z = 1, outside: seen.
        assert!(sight.is_visible(eye, Vec3::new(3.0, 0.0, -3.0), 0.0));
        // A point on the far face is hidden, one on the near face is seen with a margin.
        assert!(!sight.is_visible(eye, Vec3::new(0.0, 0.0, -1.0), 1e-3));
        assert!(sight.is_visible(eye, Vec3::new(0.0, 0.0, 1.0), 1e-3));
    }

    #[test]
    fn the_pose_moves_the_blocker() {
        let mut sight = LineOfSight::new(&cube()).unwrap();
        sight
            .set_pose(Quat::IDENTITY, Vec3::new(10.0, 0.0, 0.0))
            .unwrap();
        let eye = Vec3::new(0.0, 0.0, 5.0);
        assert!(sight.is_visible(eye, Vec3::new(0.0, 0.0, -3.0), 0.0));
        assert!(!sight.is_visible(Vec3::new(10.0, 0.0, 5.0), Vec3::new(10.0, 0.0, -3.0), 0.0));
        assert!(
            sight
                .set_pose(Quat::from_xyzw(0.0, 0.0, 0.0, 0.0), Vec3::ZERO)
                .is_err()
        );
        assert!(!sight.is_visible(eye, Vec3::NAN, 0.0));
    }

    #[test]
    fn a_broken_mesh_is_a_named_error() {
        let mut mesh = cube();
        mesh.triangles.push([0, 1, 99]);
        let error = LineOfSight::new(&mesh).unwrap_err();
        assert!(error.to_string().contains("vertex 99"), "{error}");
        let empty = TriangleMesh::default();
        assert_eq!(
            LineOfSight::new(&empty).unwrap_err(),
            CollideError::Mesh(hair_core::mesh::MeshError::NoTriangles)
        );
        let mut mesh = cube();
        mesh.positions[5].z = f32::NAN;
        let error = LineOfSight::new(&mesh).unwrap_err();
        assert!(
            error.to_string().contains("vertex 5 is not finite"),
            "{error}"
        );
    }
}
