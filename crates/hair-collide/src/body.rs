//! Collision bodies (head, neck, shoulders, a character mesh): a triangle mesh in its own frame
//! with a parry3d `Bvh` over its triangles and a PSS at the top level (§5.2), and the pose that
//! places it in the world.
//!
//! The mesh, its tree and its pseudonormals never change once built: they are kept in the body's
//! own frame and shared (an `Arc`) by every copy of the body, so a crowd of characters on one
//! head holds that head once. Moving a body only changes its pose: queries bring their points
//! into the body's frame instead of the body into the world's, and cost nothing when it moves.

use std::sync::{Arc, OnceLock};

use glam::{Quat, Vec3};
use hair_core::TriangleMesh;
use parry3d::partitioning::Bvh;

use crate::distance_field::{DEFAULT_CELL, DistanceField};
use crate::error::{CollideError, Result, require_pose};
use crate::fit::enclosing_ball;
use crate::geometry::Triangle;
use crate::pseudonormals::Pseudonormals;
use crate::rest_field::Deformation;
use crate::triangle_groups::{TriangleGroups, grouped_tree};
use crate::volume::Pss;

/// What a body is in its own frame: built once by [`CollisionBody::from_mesh`], never changed,
/// shared by the body's copies.
#[derive(Debug)]
pub(crate) struct BodyShape {
    /// Per triangle, its three vertex indices into the mesh (shared by a deforming body's
    /// instants: the topology does not change).
    pub indices: Arc<[[u32; 3]]>,
    /// The triangles with their unit normals \[m\] (body frame), indexed by triangle id.
    pub triangles: Vec<Triangle>,
    /// The ball around the vertices that triangles use \[m\] (body frame).
    pub bound: Pss,
    /// The triangle tree (leaf data = group id of `groups`), over unpadded boxes of the
    /// groups' triangles.
    pub bvh: Bvh,
    /// The triangles of each leaf of `bvh` (`triangle_groups.rs`), shared by a deforming
    /// body's instants.
    pub groups: Arc<TriangleGroups>,
    /// The group ids in the order their leaves lie in the tree's memory, found when a
    /// deforming body first refits the tree and shared by its instants (whose trees are copies
    /// of one layout): a refit that walks the leaves in this order writes the tree front to
    /// back instead of at random.
    pub leaf_order: Arc<OnceLock<Vec<u32>>>,
    /// Angle-weighted pseudonormals (body frame) and the edge structure.
    pub pseudonormals: Pseudonormals,
    /// The distance field (body frame), built on first use.
    pub field: OnceLock<DistanceField>,
    /// A deforming body's vertex velocities \[m/s\] (body frame), one per vertex; empty for a
    /// body that only moves rigidly.
    pub vertex_velocities: Vec<Vec3>,
    /// Where a deforming body reads its rest mesh's field (`moving_field.rs`).
    pub deformation: Option<Deformation>,
}

impl BodyShape {
    /// This shape reading `deformation` (its field, a fresh one, unbuilt).
    pub(crate) fn with_deformation(&self, deformation: Option<Deformation>) -> BodyShape {
        BodyShape {
            indices: self.indices.clone(),
            triangles: self.triangles.clone(),
            bound: self.bound,
            bvh: self.bvh.clone(),
            groups: self.groups.clone(),
            leaf_order: self.leaf_order.clone(),
            pseudonormals: self.pseudonormals.clone(),
            field: OnceLock::new(),
            vertex_velocities: self.vertex_velocities.clone(),
            deformation,
        }
    }
}

/// A rigid triangle mesh that hair collides with, placed in the world by a pose.
///
/// Cloning is cheap (the mesh, its tree and its pseudonormals are shared); each clone has its
/// own pose.
#[derive(Clone)]
pub struct CollisionBody {
    pub(crate) shape: Arc<BodyShape>,
    rotation: Quat,
    translation: Vec3,
    bound: Pss,
}

impl std::fmt::Debug for CollisionBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionBody")
            .field("triangle_count", &self.shape.indices.len())
            .field("bound", &self.bound)
            .field("rotation", &self.rotation)
            .field("translation", &self.translation)
            .finish_non_exhaustive()
    }
}

/// Barycentric coordinates of `p` (on the triangle's plane) in the triangle `a, b, c`; the first
/// vertex's alone for a degenerate triangle.
fn barycentric(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
    let (d20, d21) = (ap.dot(ab), ap.dot(ac));
    let denominator = d00 * d11 - d01 * d01;
    if denominator <= 0.0 {
        return Vec3::X;
    }
    let v = (d11 * d20 - d01 * d21) / denominator;
    let w = (d00 * d21 - d01 * d20) / denominator;
    Vec3::new(1.0 - v - w, v, w)
}

/// Checks per-vertex values `values` (`what`, for the error): one per vertex of `count`, each
/// finite.
pub(crate) fn check_vertex_values(what: &'static str, values: &[Vec3], count: usize) -> Result<()> {
    if values.len() != count {
        return Err(CollideError::SizeMismatch {
            what,
            actual: values.len(),
            expected: count,
        });
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(CollideError::NonFinite { what, index }),
        None => Ok(()),
    }
}

/// The ball `local` (body frame) placed by the pose: the same ball, padded for the rounding of
/// the transform.
fn posed_bound(local: Pss, rotation: Quat, translation: Vec3) -> Pss {
    let center = rotation * local.center + translation;
    let slack = 64.0 * f32::EPSILON * (center.abs().max_element() + local.radius);
    Pss {
        center,
        radius: local.radius + slack,
    }
}

impl DistanceField {
    /// The field of `body` (its own frame) with cells of at least `cell` \[m\] (larger where the
    /// body would need more than [`MAX_VERTICES`](crate::distance_field::MAX_VERTICES)
    /// vertices). Signed when the body is closed.
    ///
    /// Cost: one closest-point search per vertex near the surface, and a linear pass over the
    /// grid (the 12k-triangle procedural head at 2 mm: about 0.3 s in a release build).
    pub fn of(body: &CollisionBody, cell: f32) -> Self {
        Self::of_reaching(body, cell, crate::distance_field::EXACT_REACH)
    }

    /// [`DistanceField::of`] with every point within `exact_reach` \[m\] of the surface (at
    /// least [`EXACT_REACH`](crate::distance_field::EXACT_REACH)) in an exact cell: more
    /// seeds, for volumes of larger radius.
    pub fn of_reaching(body: &CollisionBody, cell: f32, exact_reach: f32) -> Self {
        DistanceField::of_surface(
            body.local_triangles(),
            body.is_closed(),
            |p| {
                body.closest_local_surface_point(p)
                    .map(|surface| (surface.signed_distance, surface.triangle))
            },
            cell,
            exact_reach,
        )
    }
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
        let bound = enclosing_ball(&used_positions).unwrap_or(Pss {
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
        let (groups, bvh) = grouped_tree(&triangles);
        let shape = BodyShape {
            pseudonormals: Pseudonormals::of(mesh),
            indices: mesh.triangles.as_slice().into(),
            triangles,
            bound,
            bvh,
            groups: Arc::new(groups),
            leaf_order: Arc::default(),
            field: OnceLock::new(),
            vertex_velocities: Vec::new(),
            deformation: None,
        };
        Ok(Self {
            shape: Arc::new(shape),
            rotation: Quat::IDENTITY,
            translation: Vec3::ZERO,
            bound,
        })
    }

    /// A deforming body at one instant: `mesh` as [`CollisionBody::from_mesh`] builds it, whose
    /// vertices move at `velocities` \[m/s\] (body frame, one per vertex) besides the pose's
    /// motion. Response and projection add the surface's own velocity where a node touches it
    /// ([`CollisionBody::deformation_velocity`]). Errors on a count that is not the vertices' or
    /// a velocity that is not finite.
    pub fn from_moving_mesh(mesh: &TriangleMesh, velocities: Vec<Vec3>) -> Result<Self> {
        check_vertex_values("vertex velocities", &velocities, mesh.positions.len())?;
        let mut body = Self::from_mesh(mesh)?;
        Arc::get_mut(&mut body.shape)
            .expect("a body just built holds its shape alone")
            .vertex_velocities = velocities;
        Ok(body)
    }

    /// The velocity \[m/s\] (world) of the deforming surface nearest `p` \[m\] besides the
    /// pose's motion: the closest point's barycentric blend of its triangle's vertex velocities,
    /// turned by the pose. Zero for a rigid body (no vertex velocities) and for a non-finite
    /// point.
    pub fn deformation_velocity(&self, p: Vec3) -> Vec3 {
        self.deformation_velocity_at(p, None)
    }

    /// [`CollisionBody::deformation_velocity`], the closest point's search starting from
    /// triangle `near` (the same answer, found sooner where `near` is close to `p`).
    pub(crate) fn deformation_velocity_near(&self, p: Vec3, near: u32) -> Vec3 {
        self.deformation_velocity_at(p, Some(near))
    }

    /// The velocity of [`CollisionBody::deformation_velocity`], the search from `near`.
    fn deformation_velocity_at(&self, p: Vec3, near: Option<u32>) -> Vec3 {
        let velocities = &self.shape.vertex_velocities;
        if velocities.is_empty() {
            return Vec3::ZERO;
        }
        let Some(surface) = self.closest_local_surface_point_near(self.to_local(p), near) else {
            return Vec3::ZERO;
        };
        let t = surface.triangle as usize;
        let [a, b, c] = self.shape.triangles[t].vertices;
        let weights = barycentric(surface.point, a, b, c);
        let [i, j, k] = self.shape.indices[t].map(|v| velocities[v as usize]);
        self.rotation * (i * weights.x + j * weights.y + k * weights.z)
    }

    /// Whether the body deforms (it has vertex velocities, [`CollisionBody::from_moving_mesh`]).
    pub fn is_deforming(&self) -> bool {
        !self.shape.vertex_velocities.is_empty()
    }

    /// The mean of the vertex velocities \[m/s\] of triangles `ids` (body frame): a touching
    /// segment's surface velocity from the triangles it touches. Zero for a rigid body or no
    /// triangles.
    pub fn local_deformation_velocity_of(&self, ids: &[u32]) -> Vec3 {
        let velocities = &self.shape.vertex_velocities;
        if velocities.is_empty() || ids.is_empty() {
            return Vec3::ZERO;
        }
        let sum: Vec3 = ids
            .iter()
            .flat_map(|&t| self.shape.indices[t as usize])
            .map(|v| velocities[v as usize])
            .sum();
        sum / (3 * ids.len()) as f32
    }

    /// The velocity \[m/s\] (body frame) of the deforming surface at the point of triangle
    /// `triangle` with barycentric `weights` (besides the pose's motion): the blend of its
    /// vertices' velocities. Zero for a rigid body or a triangle out of range.
    pub fn local_deformation_velocity_at(&self, triangle: u32, weights: Vec3) -> Vec3 {
        let velocities = &self.shape.vertex_velocities;
        match self.shape.indices.get(triangle as usize) {
            Some(&[i, j, k]) if !velocities.is_empty() => {
                velocities[i as usize] * weights.x
                    + velocities[j as usize] * weights.y
                    + velocities[k as usize] * weights.z
            }
            _ => Vec3::ZERO,
        }
    }

    /// Places the body: world = `rotation` · local + `translation` \[m\]. Only the pose changes
    /// (constant time, whatever the mesh). `rotation` is normalised; errors on a non-finite or
    /// zero rotation or a non-finite translation, leaving the pose unchanged.
    pub fn set_pose(&mut self, rotation: Quat, translation: Vec3) -> Result<()> {
        let rotation = require_pose(rotation, translation)?;
        self.rotation = rotation;
        self.translation = translation;
        self.bound = posed_bound(self.shape.bound, rotation, translation);
        Ok(())
    }

    /// A body of `shape` at this body's pose.
    pub(crate) fn with_shape(&self, shape: Arc<BodyShape>) -> Self {
        Self {
            bound: posed_bound(shape.bound, self.rotation, self.translation),
            shape,
            rotation: self.rotation,
            translation: self.translation,
        }
    }

    /// The current pose `(rotation, translation)`.
    pub fn pose(&self) -> (Quat, Vec3) {
        (self.rotation, self.translation)
    }

    /// `point` \[m\] (world) in the body's own frame.
    pub fn to_local(&self, point: Vec3) -> Vec3 {
        self.rotation.conjugate() * (point - self.translation)
    }

    /// `point` \[m\] of the body's own frame, in the world.
    pub fn to_world(&self, point: Vec3) -> Vec3 {
        self.rotation * point + self.translation
    }

    /// The triangles with their unit normals in the body's own frame \[m\], indexed by triangle
    /// id (the frame [`query_body`](crate::query_body) works in).
    pub fn local_triangles(&self) -> &[Triangle] {
        &self.shape.triangles
    }

    /// Triangle `id` placed in the world by the current pose; `None` past the last triangle.
    pub fn world_triangle(&self, id: u32) -> Option<Triangle> {
        let [a, b, c] = self.shape.triangles.get(id as usize)?.vertices;
        Some(Triangle::new(
            self.to_world(a),
            self.to_world(b),
            self.to_world(c),
        ))
    }

    /// The mesh vertex index of corner `k` (0..3) of triangle `triangle`.
    pub(crate) fn triangle_vertex(&self, triangle: u32, k: u8) -> u32 {
        self.shape.indices[triangle as usize][k as usize]
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.shape.triangles.len()
    }

    /// The top-level PSS \[m\] enclosing the whole body in world space (§5.3: "the point swept
    /// sphere for the head at the top level").
    pub fn bounding_volume(&self) -> Pss {
        self.bound
    }

    /// The top-level PSS \[m\] in the body's own frame.
    pub fn local_bounding_volume(&self) -> Pss {
        self.shape.bound
    }

    /// The underlying parry3d triangle tree in the body's own frame (leaf data = a group id:
    /// [`CollisionBody::leaf_triangles`] names its triangles).
    pub(crate) fn bvh(&self) -> &Bvh {
        &self.shape.bvh
    }

    /// The triangle ids of leaf `leaf` of [`CollisionBody::bvh`].
    #[inline]
    pub(crate) fn leaf_triangles(&self, leaf: u32) -> &[u32] {
        self.shape.groups.members(leaf)
    }

    /// The body's distance field in its own frame ([`DistanceField`], cells of
    /// [`DEFAULT_CELL`](crate::distance_field::DEFAULT_CELL)): built on the first call (a
    /// closest-point search per grid vertex near the surface), then shared by every copy of the
    /// body.
    pub fn distance_field(&self) -> &DistanceField {
        self.shape
            .field
            .get_or_init(|| DistanceField::of(self, DEFAULT_CELL))
    }

    /// Whether `self` and `other` share one mesh, tree and pseudonormals (one is a clone of the
    /// other): what a crowd's characters on one head do.
    pub fn shares_shape_with(&self, other: &CollisionBody) -> bool {
        Arc::ptr_eq(&self.shape, &other.shape)
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

    /// A pose moves the world triangles and the bound by exactly that rigid transform and leaves
    /// the shared shape alone: a clone keeps its own pose.
    #[test]
    fn a_pose_moves_the_world_triangles_and_copies_share_the_shape() {
        let mut body = CollisionBody::from_mesh(&tetrahedron()).unwrap();
        let copy = body.clone();
        let rotation = Quat::from_rotation_y(0.7);
        let translation = Vec3::new(0.1, -0.2, 0.3);
        body.set_pose(rotation, translation).unwrap();
        assert!(body.shares_shape_with(&copy));
        assert_eq!(copy.pose(), (Quat::IDENTITY, Vec3::ZERO));
        assert_eq!(
            copy.world_triangle(0).unwrap().vertices,
            [Vec3::ZERO, Vec3::Y, Vec3::X]
        );
        for id in 0..4 {
            let local = body.local_triangles()[id as usize];
            let world = body.world_triangle(id).unwrap();
            for k in 0..3 {
                let expected = rotation * local.vertices[k] + translation;
                assert!(world.vertices[k].distance(expected) < 1e-6);
                assert!(body.to_local(world.vertices[k]).distance(local.vertices[k]) < 1e-6);
            }
            assert!((world.normal - rotation * local.normal).length() < 1e-6);
        }
        assert!(body.world_triangle(4).is_none());
        let ball = body.bounding_volume();
        let local_ball = body.local_bounding_volume();
        assert!(
            ball.center
                .distance(rotation * local_ball.center + translation)
                < 1e-6
        );
        // Padded by the rounding slack 64 ε (|centre|∞ + radius), under 64 ε · 2 for this body.
        let slack = ball.radius - local_ball.radius;
        assert!(
            slack > 0.0 && slack <= 128.0 * f32::EPSILON,
            "{ball:?} {local_ball:?}"
        );
        let fresh = CollisionBody::from_mesh(&tetrahedron()).unwrap();
        assert!(!fresh.shares_shape_with(&body));
    }
}
