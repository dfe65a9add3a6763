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

/// A closest-point search's answer: the triangle, the closest point on it \[m\] and its feature.
type Found = (u32, (Vec3, TriangleFeature));

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
        self.closest_local_surface_point_near(p, None)
    }

    /// [`closest_surface_point`](Self::closest_surface_point) starting from a guess: triangle
    /// `hint` (the one found for this point last time, say) bounds the search by its own
    /// distance, so the tree search only visits what could be closer. The answer is the
    /// unhinted one's distance exactly; where triangles tie, the hint is kept.
    pub(crate) fn closest_surface_point_near(&self, p: Vec3, hint: u32) -> Option<SurfacePoint> {
        if !p.is_finite() {
            return None;
        }
        let found = self.closest_local_surface_point_near(self.to_local(p), Some(hint))?;
        Some(SurfacePoint {
            point: self.to_world(found.point),
            normal: self.pose().0 * found.normal,
            ..found
        })
    }

    /// The triangle closest to `p` \[m\] (body frame) among those within `reach` \[m\] of
    /// it; `None` where none is: the tree search is bounded by `reach`, so a far point costs a
    /// few boxes.
    pub(crate) fn closest_local_triangle_within(&self, p: Vec3, reach: f32) -> Option<u32> {
        if !p.is_finite() {
            return None;
        }
        self.closest_in_tree(p, reach).map(|(triangle, _)| triangle)
    }

    /// The tree search for the triangle closest to `p` (body frame) among those nearer than
    /// `bound` \[m\], with the closest point and its feature.
    fn closest_in_tree(&self, p: Vec3, bound: f32) -> Option<Found> {
        let triangles = self.local_triangles();
        self.bvh()
            .find_best(
                bound,
                |node, _| {
                    let aabb = node.aabb();
                    p.clamp(aabb.mins, aabb.maxs).distance(p)
                },
                |leaf, _| {
                    // The leaf's closest triangle (the first of equals).
                    let mut best: Option<(f32, Found)> = None;
                    for &t in self.leaf_triangles(leaf) {
                        let (q, feature) = closest_point_on_triangle(p, &triangles[t as usize]);
                        let distance = q.distance(p);
                        if best.is_none_or(|(d, _)| distance < d) {
                            best = Some((distance, (t, (q, feature))));
                        }
                    }
                    best
                },
            )
            .map(|(_, (_, found))| found)
    }

    /// The closest surface point to `p` (body frame), the search bounded by triangle `hint`'s
    /// distance where one is given (an index out of range is no hint).
    pub(crate) fn closest_local_surface_point_near(
        &self,
        p: Vec3,
        hint: Option<u32>,
    ) -> Option<SurfacePoint> {
        if !p.is_finite() {
            return None;
        }
        let triangles = self.local_triangles();
        let hinted = hint
            .filter(|&t| (t as usize) < triangles.len())
            .map(|t| (t, closest_point_on_triangle(p, &triangles[t as usize])));
        let bound = hinted.map_or(f32::MAX, |(_, (q, _))| q.distance(p));
        let best = self.closest_in_tree(p, bound);
        let (triangle, (point, feature)) = match (best, hinted) {
            (Some((triangle, found)), _) => (triangle, found),
            (None, Some(hinted)) => hinted,
            (None, None) => return None,
        };
        let pseudonormals = &self.shape.pseudonormals;
        let normal = match feature {
            TriangleFeature::Face => triangles[triangle as usize].normal,
            TriangleFeature::Edge(k) => pseudonormals.edge_normal(
                triangles,
                pseudonormals.triangle_edges[triangle as usize][k as usize],
            ),
            TriangleFeature::Vertex(k) => {
                pseudonormals.vertex_normal(triangles, self.triangle_vertex(triangle, k))
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

#[cfg(test)]
mod tests {
    use glam::{Quat, Vec3};
    use hair_core::{Head, HeadParams};

    use crate::body::CollisionBody;

    #[test]
    fn a_search_started_from_any_triangle_finds_the_same_distance() {
        let mesh = Head::procedural(&HeadParams::default()).unwrap().mesh;
        let mut body = CollisionBody::from_mesh(&mesh).unwrap();
        body.set_pose(Quat::from_rotation_y(0.4), Vec3::new(0.01, 0.02, -0.03))
            .unwrap();
        let triangles = body.triangle_count() as u32;
        for i in 0..400u32 {
            // Points around and inside the head, hints spread over the mesh (near and far).
            let t = i as f32 * 0.618;
            let p = Vec3::new(
                t.sin() * 0.14,
                (t * 1.3).cos() * 0.16,
                (t * 0.7).sin() * 0.13,
            );
            let hint = (i * 7919) % triangles;
            let (a, b) = (
                body.closest_surface_point(p).unwrap(),
                body.closest_surface_point_near(p, hint).unwrap(),
            );
            // The same closest distance: the hint only bounds the search (ties may report
            // another triangle at the same distance).
            assert_eq!(a.signed_distance.abs(), b.signed_distance.abs(), "at {p}");
            assert_eq!(a.signed_distance, b.signed_distance, "sign at {p}");
        }
        // A hint past the triangles is no hint.
        let p = Vec3::new(0.0, 0.2, 0.0);
        assert_eq!(
            body.closest_surface_point(p),
            body.closest_surface_point_near(p, u32::MAX)
        );
    }
}
