//! Collision bodies (head, neck, shoulders, a character mesh): world-space triangles, a PSS at
//! the top level (§5.2) and a parry3d `Bvh` over the triangles, refitted when the body moves.
//!
//! parry's `TriMesh` also carries a triangle BVH, but it cannot be moved without rebuilding; this
//! keeps the local mesh and refits a `Bvh` of triangle AABBs on every [`CollisionBody::set_pose`].

use glam::{Quat, Vec3};
use hair_core::TriangleMesh;
use parry3d::bounding_volume::Aabb;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

use crate::error::{Result, require_pose};
use crate::fit::enclosing_ball;
use crate::geometry::Triangle;
use crate::surface::Pseudonormals;
use crate::volume::Pss;

/// A rigid triangle mesh that hair collides with.
pub struct CollisionBody {
    local_positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    local_bound: Pss,
    rotation: Quat,
    translation: Vec3,
    triangles: Vec<Triangle>,
    bound: Pss,
    bvh: Bvh,
    workspace: BvhWorkspace,
    pub(crate) pseudonormals: Pseudonormals,
}

impl std::fmt::Debug for CollisionBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionBody")
            .field("triangle_count", &self.indices.len())
            .field("bound", &self.bound)
            .field("rotation", &self.rotation)
            .field("translation", &self.translation)
            .finish_non_exhaustive()
    }
}

impl Clone for CollisionBody {
    /// A copy with its own (empty) refit workspace.
    fn clone(&self) -> Self {
        Self {
            local_positions: self.local_positions.clone(),
            indices: self.indices.clone(),
            local_bound: self.local_bound,
            rotation: self.rotation,
            translation: self.translation,
            triangles: self.triangles.clone(),
            bound: self.bound,
            bvh: self.bvh.clone(),
            workspace: BvhWorkspace::default(),
            pseudonormals: self.pseudonormals.clone(),
        }
    }
}

fn triangle_aabb(triangle: &Triangle) -> Aabb {
    let [a, b, c] = triangle.vertices;
    Aabb::new(a.min(b).min(c), a.max(b).max(c))
}

impl CollisionBody {
    /// A body from a mesh given in its own (local) frame \[m\], placed at the identity pose.
    ///
    /// Errors ([`CollideError::Mesh`](crate::CollideError::Mesh)) on a mesh that fails
    /// [`TriangleMesh::validate_surface`]: no triangles or only zero-area ones, a triangle indexing
    /// past the vertices, a position or normal not finite, normals not one per vertex. Normals of
    /// the mesh are not otherwise read: triangle normals come from the counter-clockwise winding.
    pub fn from_mesh(mesh: &TriangleMesh) -> Result<Self> {
        mesh.validate_surface()?;
        // Bound only the vertices that triangles use: unused vertices cannot be touched.
        let mut used = vec![false; mesh.positions.len()];
        for indices in &mesh.triangles {
            for &i in indices {
                used[i as usize] = true;
            }
        }
        let used_positions: Vec<Vec3> = mesh
            .positions
            .iter()
            .zip(&used)
            .filter(|(_, u)| **u)
            .map(|(p, _)| *p)
            .collect();
        let local_bound = enclosing_ball(&used_positions).unwrap_or(Pss {
            center: Vec3::ZERO,
            radius: 0.0,
        });
        let triangles: Vec<Triangle> = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                Triangle::new(a, b, c)
            })
            .collect();
        let bvh = Bvh::from_iter(
            BvhBuildStrategy::Binned,
            triangles.iter().map(triangle_aabb).enumerate(),
        );
        let pseudonormals = Pseudonormals::of(mesh);
        Ok(Self {
            pseudonormals,
            local_positions: mesh.positions.clone(),
            indices: mesh.triangles.clone(),
            local_bound,
            rotation: Quat::IDENTITY,
            translation: Vec3::ZERO,
            triangles,
            bound: local_bound,
            bvh,
            workspace: BvhWorkspace::default(),
        })
    }

    /// Places the body: world = `rotation` · local + `translation` \[m\]. Recomputes the world
    /// triangles and refits the triangle tree (no rebuild). `rotation` is normalised; errors on a
    /// non-finite or zero rotation or a non-finite translation, leaving the pose unchanged.
    ///
    /// Placing it where it already is costs nothing (the solvers pose their bodies before and
    /// after every step, and a still head keeps its pose).
    pub fn set_pose(&mut self, rotation: Quat, translation: Vec3) -> Result<()> {
        let rotation = require_pose(rotation, translation)?;
        if rotation == self.rotation && translation == self.translation {
            // The triangles and the tree were computed for exactly this pose.
            return Ok(());
        }
        self.rotation = rotation;
        self.translation = translation;
        let to_world = |p: Vec3| rotation * p + translation;
        for (triangle, indices) in self.triangles.iter_mut().zip(&self.indices) {
            let [a, b, c] = indices.map(|i| to_world(self.local_positions[i as usize]));
            *triangle = Triangle::new(a, b, c);
        }
        for (leaf, triangle) in self.triangles.iter().enumerate() {
            self.bvh
                .insert_or_update_partially(triangle_aabb(triangle), leaf as u32, 0.0);
        }
        self.bvh.refit(&mut self.workspace);
        let center = to_world(self.local_bound.center);
        // The rotated ball is the same ball; pad for the rounding of the transform.
        let slack = 64.0 * f32::EPSILON * (center.abs().max_element() + self.local_bound.radius);
        self.bound = Pss {
            center,
            radius: self.local_bound.radius + slack,
        };
        Ok(())
    }

    /// The current pose `(rotation, translation)`.
    pub fn pose(&self) -> (Quat, Vec3) {
        (self.rotation, self.translation)
    }

    /// World-space triangles with their unit normals, indexed by triangle id.
    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// The mesh vertex index of corner `k` (0..3) of triangle `triangle`.
    pub(crate) fn triangle_vertex(&self, triangle: u32, k: u8) -> u32 {
        self.indices[triangle as usize][k as usize]
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The top-level PSS \[m\] enclosing the whole body in world space (§5.3: "the point swept
    /// sphere for the head at the top level").
    pub fn bounding_volume(&self) -> Pss {
        self.bound
    }

    /// The underlying parry3d triangle tree (leaf data = triangle id).
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> TriangleMesh {
        TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
            ..TriangleMesh::default()
        }
    }

    /// Posing where the body already is skips the work; posing away and back gives the first
    /// pose's triangles exactly (they are always computed from the local mesh).
    #[test]
    fn posing_away_and_back_restores_the_triangles() {
        let mut body = CollisionBody::from_mesh(&tetrahedron()).unwrap();
        let rotation = Quat::from_rotation_y(0.7);
        let translation = Vec3::new(0.1, -0.2, 0.3);
        body.set_pose(rotation, translation).unwrap();
        let first: Vec<[Vec3; 3]> = body.triangles().iter().map(|t| t.vertices).collect();
        body.set_pose(rotation, translation).unwrap();
        let again: Vec<[Vec3; 3]> = body.triangles().iter().map(|t| t.vertices).collect();
        assert_eq!(first, again);
        body.set_pose(Quat::IDENTITY, Vec3::ZERO).unwrap();
        assert_eq!(body.triangles()[0].vertices, [Vec3::ZERO, Vec3::Y, Vec3::X]);
        body.set_pose(rotation, translation).unwrap();
        let back: Vec<[Vec3; 3]> = body.triangles().iter().map(|t| t.vertices).collect();
        assert_eq!(first, back);
        assert_eq!(body.pose(), (rotation.normalize(), translation));
    }
}
