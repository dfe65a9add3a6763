//! Signed distance to a body: the closest surface point through the triangle tree, signed with
//! angle-weighted pseudonormals (Bærentzen & Aanæs 2005), exact for closed meshes.
//!
//! The pseudonormal of a face is its normal; of an edge, the sum of its faces' normals; of a
//! vertex, the sum of its faces' normals weighted by the face angles at the vertex. For a closed,
//! consistently wound mesh, a point `p` whose closest surface point `q` lies on feature `f` is
//! outside exactly when `(p − q) · n_f > 0`, whichever feature `q` lies on. Open meshes (the
//! Ratboy body) get the same rule, which reads "in front of / behind the nearest surface".

use std::collections::HashMap;

use glam::Vec3;
use hair_core::TriangleMesh;

use crate::body::CollisionBody;
use crate::closest::{TriangleFeature, closest_point_on_triangle};

/// Pseudonormals of a mesh in its local frame, and its edge structure.
#[derive(Debug, Clone, Default)]
pub(crate) struct Pseudonormals {
    /// Unit angle-weighted pseudonormal per vertex (zero for unused vertices).
    pub vertex: Vec<Vec3>,
    /// Unit pseudonormal per edge.
    pub edge: Vec<Vec3>,
    /// Per triangle, the edge id of its edges `k → k + 1`.
    pub triangle_edges: Vec<[u32; 3]>,
    /// Whether every edge has exactly two triangles that traverse it in opposite directions.
    pub closed: bool,
}

impl Pseudonormals {
    /// Computes the pseudonormals of `mesh` (indices already validated).
    pub fn of(mesh: &TriangleMesh) -> Self {
        let mut vertex = vec![Vec3::ZERO; mesh.positions.len()];
        let mut edge_ids: HashMap<(u32, u32), u32> = HashMap::new();
        // Per edge: accumulated normal, and uses in the direction (min → max) and reverse.
        let mut edge_sums: Vec<Vec3> = Vec::new();
        let mut edge_uses: Vec<(u32, u32)> = Vec::new();
        let mut triangle_edges = Vec::with_capacity(mesh.triangles.len());
        for indices in &mesh.triangles {
            let p = indices.map(|i| mesh.positions[i as usize]);
            let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let mut ids = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (indices[k], indices[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                let next = edge_sums.len() as u32;
                let id = *edge_ids.entry(key).or_insert(next);
                if id == next {
                    edge_sums.push(Vec3::ZERO);
                    edge_uses.push((0, 0));
                }
                edge_sums[id as usize] += normal;
                if a < b {
                    edge_uses[id as usize].0 += 1;
                } else {
                    edge_uses[id as usize].1 += 1;
                }
                ids[k] = id;
                // Angle at vertex k.
                let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
                let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
                let angle = e1.dot(e2).clamp(-1.0, 1.0).acos();
                vertex[indices[k] as usize] += normal * angle;
            }
            triangle_edges.push(ids);
        }
        let closed = !edge_uses.is_empty() && edge_uses.iter().all(|&uses| uses == (1, 1));
        Pseudonormals {
            vertex: vertex.into_iter().map(Vec3::normalize_or_zero).collect(),
            edge: edge_sums.into_iter().map(Vec3::normalize_or_zero).collect(),
            triangle_edges,
            closed,
        }
    }
}

/// The closest point of a body's surface to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// The closest surface point \[m\] (world).
    pub point: Vec3,
    /// Unit outward pseudonormal of the feature `point` lies on (world).
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
        self.pseudonormals.closed
    }

    /// The surface point closest to `p` \[m\], with its pseudonormal and signed distance; `None`
    /// when `p` is not finite. Best-first descent of the triangle tree, exact per triangle.
    pub fn closest_surface_point(&self, p: Vec3) -> Option<SurfacePoint> {
        if !p.is_finite() {
            return None;
        }
        let triangles = self.triangles();
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
        let local_normal = match feature {
            TriangleFeature::Face => None,
            TriangleFeature::Edge(k) => Some(
                self.pseudonormals.edge
                    [self.pseudonormals.triangle_edges[triangle as usize][k as usize] as usize],
            ),
            TriangleFeature::Vertex(k) => {
                Some(self.pseudonormals.vertex[self.triangle_vertex(triangle, k) as usize])
            }
        };
        let normal = match local_normal {
            Some(n) => self.pose().0 * n,
            None => triangles[triangle as usize].normal,
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
