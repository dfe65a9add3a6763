//! Signed distance to a body: the closest surface point through the triangle tree, signed with
//! the mesh's angle-weighted pseudonormals (Bærentzen & Aanæs 2005), exact for closed meshes.
//!
//! For a closed, consistently wound mesh, a point `p` whose closest surface point `q` lies on
//! feature `f` is outside exactly when `(p − q) · n_f > 0`, whichever feature `q` lies on. Open
//! meshes (the Ratboy body) get the same rule, which reads "in front of / behind the nearest
//! surface".

use glam::Vec3;

use crate::body::CollisionBody;
use crate::closest::{TriangleFeature, closest_point_on_triangle};

/// The closest point of a body's surface to a query point, in the query's frame (the world for
/// [`CollisionBody::closest_surface_point`], the body's own for
/// [`CollisionBody::closest_local_surface_point`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// The closest surface point \[m\].
    pub point: Vec3,
    /// Unit outward pseudonormal of the feature `point` lies on.
    pub normal: Vec3,
    /// Signed distance \[m\]: positive outside, negative inside (`|p − point|` with the sign of
    /// `(p − point) · normal`).
    pub signed_distance: f32,
    /// The triangle `point` lies on.
    pub triangle: u32,
}

impl CollisionBody {
    /// Whether the mesh is closed and consistently wound (every edge shared by exactly two
    /// triangles that run along it in opposite directions): then the signed distance is exact.
    pub fn is_closed(&self) -> bool {
        self.shape.pseudonormals.closed
    }

    /// The surface point closest to `p` \[m\] (world), with its pseudonormal and signed distance;
    /// `None` when `p` is not finite. `p` is brought into the body's frame, where a best-first
    /// descent of the triangle tree finds the closest point, exact per triangle.
    pub fn closest_surface_point(&self, p: Vec3) -> Option<SurfacePoint> {
        if !p.is_finite() {
            return None;
        }
        let local = self.to_local(p);
        let found = self.closest_local_surface_point(local)?;
        Some(SurfacePoint {
            point: self.to_world(found.point),
            normal: self.pose().0 * found.normal,
            ..found
        })
    }

    /// [`closest_surface_point`](Self::closest_surface_point) of a point `p` \[m\] given in the
    /// body's own frame, answered in that frame.
    pub fn closest_local_surface_point(&self, p: Vec3) -> Option<SurfacePoint> {
        if !p.is_finite() {
            return None;
        }
        let triangles = self.local_triangles();
        let (triangle, (_, (point, feature))) = self.bvh().find_best(
            f32::MAX,
            |node, _| {
                let aabb = node.aabb();
                p.clamp(aabb.mins, aabb.maxs).distance(p)
            },
            |leaf, _| {
                let (q, feature) = closest_point_on_triangle(p, &triangles[leaf as usize]);
                Some((q.distance(p), (q, feature)))
            },
        )?;
        let pseudonormals = &self.shape.pseudonormals;
        let normal = match feature {
            TriangleFeature::Face => triangles[triangle as usize].normal,
            TriangleFeature::Edge(k) => {
                pseudonormals.edge
                    [pseudonormals.triangle_edges[triangle as usize][k as usize] as usize]
            }
            TriangleFeature::Vertex(k) => {
                pseudonormals.vertex[self.triangle_vertex(triangle, k) as usize]
            }
        };
        let offset = p - point;
        let distance = offset.length();
        let signed_distance = if offset.dot(normal) < 0.0 {
            -distance
        } else {
            distance
        };
        Some(SurfacePoint {
            point,
            normal,
            signed_distance,
            triangle,
        })
    }

    /// Signed distance \[m\] from `p` to the surface (negative inside); `None` for a non-finite
    /// point.
    pub fn signed_distance(&self, p: Vec3) -> Option<f32> {
        self.closest_surface_point(p).map(|s| s.signed_distance)
    }
}
