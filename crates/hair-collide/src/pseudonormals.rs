//! Angle-weighted pseudonormals of a triangle mesh (Bærentzen & Aanæs 2005) and its edge
//! structure: what signs the distance to a body ([`crate::surface`]).
//!
//! The pseudonormal of a face is its normal; of an edge, the sum of its faces' normals; of a
//! vertex, the sum of its faces' normals weighted by the face angles at the vertex.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Vec3;
use hair_core::TriangleMesh;

use crate::geometry::Triangle;
use rayon::prelude::*;

/// Pseudonormals of a mesh in its local frame, and its edge structure. A rigid body keeps
/// them all; a deforming body's instant finds the one a closest point needs when it needs it
/// ([`Pseudonormals::on_demand`]), the same sums in the same order, so the same bits.
#[derive(Debug, Clone, Default)]
pub(crate) struct Pseudonormals {
    /// Unit angle-weighted pseudonormal per vertex (zero for unused vertices); empty on demand.
    vertex: Vec<Vec3>,
    /// Unit pseudonormal per edge; empty on demand.
    edge: Vec<Vec3>,
    /// The mesh's vertex count.
    pub vertex_count: usize,
    /// Per triangle, the edge id of its edges `k → k + 1` (shared by a deforming body's
    /// instants).
    pub triangle_edges: Arc<[[u32; 3]]>,
    /// The triangles around each vertex and edge (shared by a deforming body's instants).
    rings: Arc<Rings>,
    /// Whether every edge has exactly two triangles that traverse it in opposite directions.
    pub closed: bool,
}

/// The triangles around each vertex and each edge, in triangle order (compressed rows).
#[derive(Debug, Default)]
struct Rings {
    /// Per vertex, where its corners start in `vertex_corners` (one more entry than vertices).
    vertex_offsets: Vec<u32>,
    /// The corners `(triangle, k)` at each vertex.
    vertex_corners: Vec<(u32, u8)>,
    /// Per edge, where its triangles start in `edge_faces` (one more entry than edges).
    edge_offsets: Vec<u32>,
    /// The triangles along each edge.
    edge_faces: Vec<u32>,
}

impl Rings {
    /// The rings of `triangles` over `vertex_count` vertices, whose edge ids are
    /// `triangle_edges` (of `edge_count` edges).
    fn of(
        triangles: &[[u32; 3]],
        triangle_edges: &[[u32; 3]],
        vertex_count: usize,
        edge_count: usize,
    ) -> Self {
        let mut vertex_offsets = vec![0u32; vertex_count + 1];
        let mut edge_offsets = vec![0u32; edge_count + 1];
        for (indices, ids) in triangles.iter().zip(triangle_edges) {
            for k in 0..3 {
                vertex_offsets[indices[k] as usize + 1] += 1;
                edge_offsets[ids[k] as usize + 1] += 1;
            }
        }
        for offsets in [&mut vertex_offsets, &mut edge_offsets] {
            for i in 1..offsets.len() {
                offsets[i] += offsets[i - 1];
            }
        }
        let mut vertex_corners = vec![(0, 0); triangles.len() * 3];
        let mut edge_faces = vec![0; triangles.len() * 3];
        let (mut vertex_next, mut edge_next) = (vertex_offsets.clone(), edge_offsets.clone());
        for (t, (indices, ids)) in triangles.iter().zip(triangle_edges).enumerate() {
            for k in 0..3 {
                let v = indices[k] as usize;
                vertex_corners[vertex_next[v] as usize] = (t as u32, k as u8);
                vertex_next[v] += 1;
                let e = ids[k] as usize;
                edge_faces[edge_next[e] as usize] = t as u32;
                edge_next[e] += 1;
            }
        }
        Rings {
            vertex_offsets,
            vertex_corners,
            edge_offsets,
            edge_faces,
        }
    }
}

impl Pseudonormals {
    /// Computes the pseudonormals of `mesh` (indices already validated).
    pub fn of(mesh: &TriangleMesh) -> Self {
        let mut edge_ids: HashMap<(u32, u32), u32> = HashMap::new();
        // Per edge: its uses in the direction (min → max) and reverse.
        let mut edge_uses: Vec<(u32, u32)> = Vec::new();
        let mut triangle_edges = Vec::with_capacity(mesh.triangles.len());
        for indices in &mesh.triangles {
            let mut ids = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (indices[k], indices[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                let next = edge_uses.len() as u32;
                let id = *edge_ids.entry(key).or_insert(next);
                if id == next {
                    edge_uses.push((0, 0));
                }
                if a < b {
                    edge_uses[id as usize].0 += 1;
                } else {
                    edge_uses[id as usize].1 += 1;
                }
                ids[k] = id;
            }
            triangle_edges.push(ids);
        }
        let closed = !edge_uses.is_empty() && edge_uses.iter().all(|&uses| uses == (1, 1));
        let rings = Rings::of(
            &mesh.triangles,
            &triangle_edges,
            mesh.positions.len(),
            edge_uses.len(),
        );
        let mut pseudonormals = Pseudonormals {
            vertex: Vec::new(),
            edge: vec![Vec3::ZERO; edge_uses.len()],
            vertex_count: mesh.positions.len(),
            triangle_edges: triangle_edges.into(),
            rings: Arc::new(rings),
            closed,
        };
        pseudonormals.update(&mesh.triangles, &mesh.positions);
        pseudonormals
    }

    /// The same mesh's pseudonormals over other vertex positions, found when asked for
    /// ([`Pseudonormals::edge_normal`], [`Pseudonormals::vertex_normal`]) from the triangles
    /// then: a deforming body's instant, which pays nothing for the many it never reads.
    pub fn on_demand(&self) -> Self {
        Pseudonormals {
            vertex: Vec::new(),
            edge: Vec::new(),
            vertex_count: self.vertex_count,
            triangle_edges: self.triangle_edges.clone(),
            rings: self.rings.clone(),
            closed: self.closed,
        }
    }

    /// The unit pseudonormal of edge `edge` of the mesh whose triangles are `triangles`: the
    /// sum of its faces' normals.
    pub fn edge_normal(&self, triangles: &[Triangle], edge: u32) -> Vec3 {
        if let Some(normal) = self.edge.get(edge as usize) {
            return *normal;
        }
        let rings = &self.rings;
        let range = rings.edge_offsets[edge as usize] as usize
            ..rings.edge_offsets[edge as usize + 1] as usize;
        let mut sum = Vec3::ZERO;
        for &t in &rings.edge_faces[range] {
            sum += triangles[t as usize].normal;
        }
        sum.normalize_or_zero()
    }

    /// The unit angle-weighted pseudonormal of vertex `vertex` of the mesh whose triangles are
    /// `triangles`.
    pub fn vertex_normal(&self, triangles: &[Triangle], vertex: u32) -> Vec3 {
        if let Some(normal) = self.vertex.get(vertex as usize) {
            return *normal;
        }
        let rings = &self.rings;
        let range = rings.vertex_offsets[vertex as usize] as usize
            ..rings.vertex_offsets[vertex as usize + 1] as usize;
        let mut sum = Vec3::ZERO;
        for &(t, k) in &rings.vertex_corners[range] {
            sum += triangle_corners(triangles[t as usize].vertices)[k as usize];
        }
        sum.normalize_or_zero()
    }

    /// Computes every pseudonormal of the triangles `triangles` (the ones the edge structure
    /// was built from) over vertex positions `positions` [m]. The triangles' normals and corner angles are found side by side (the same values
    /// whatever the thread count), then summed onto the vertices and edges in triangle order.
    fn update(&mut self, triangles: &[[u32; 3]], positions: &[Vec3]) {
        let mut corners = vec![[Vec3::ZERO; 4]; triangles.len()];
        corners
            .par_chunks_mut(1024)
            .zip(triangles.par_chunks(1024))
            .for_each(|(corners, triangles)| {
                for (corner, indices) in corners.iter_mut().zip(triangles) {
                    *corner = triangle_corners(indices.map(|i| positions[i as usize]));
                }
            });
        self.vertex.clear();
        self.vertex.resize(positions.len(), Vec3::ZERO);
        self.edge.iter_mut().for_each(|e| *e = Vec3::ZERO);
        for ((indices, ids), corner) in triangles
            .iter()
            .zip(self.triangle_edges.iter())
            .zip(&corners)
        {
            for k in 0..3 {
                self.edge[ids[k] as usize] += corner[3];
                self.vertex[indices[k] as usize] += corner[k];
            }
        }
        for n in self.vertex.iter_mut().chain(self.edge.iter_mut()) {
            *n = n.normalize_or_zero();
        }
    }
}

/// A triangle's unit normal times its angle at each corner, and the unit normal itself.
fn triangle_corners(p: [Vec3; 3]) -> [Vec3; 4] {
    let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    // Unit edges k → k + 1.
    let edges = [0, 1, 2].map(|k| (p[(k + 1) % 3] - p[k]).normalize_or_zero());
    let angle = |k: usize| {
        // Between the edge leaving k and the one arriving at k, reversed.
        let cosine = -edges[k].dot(edges[(k + 2) % 3]);
        acos(cosine.clamp(-1.0, 1.0))
    };
    [
        normal * angle(0),
        normal * angle(1),
        normal * angle(2),
        normal,
    ]
}

/// `acos(x)` for `x` in `[−1, 1]`, within 2·10⁻⁸ rad (below `f32`'s rounding of the angle):
/// Abramowitz & Stegun 4.4.46, `acos(x) = √(1 − x) · Σ aᵢ xⁱ` on `[0, 1]`, and
/// `π − acos(−x)` below 0. Several times cheaper than the library's, for the pseudonormals of a
/// deforming body every frame.
fn acos(x: f32) -> f32 {
    const A: [f64; 8] = [
        1.570_796_305_0,
        -0.214_598_801_6,
        0.088_978_987_4,
        -0.050_174_304_6,
        0.030_891_881_0,
        -0.017_088_125_6,
        0.006_670_090_1,
        -0.001_262_491_1,
    ];
    let a = f64::from(x.abs());
    let poly = A.iter().rev().fold(0.0, |sum, &c| sum * a + c);
    let magnitude = (1.0 - a).sqrt() * poly;
    (if x < 0.0 {
        std::f64::consts::PI - magnitude
    } else {
        magnitude
    }) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial `acos` against the library's at 20,001 points of `[−1, 1]`: within
    /// 2·10⁻⁸ rad (Abramowitz & Stegun's bound) plus the f32 rounding of the answer (half an
    /// ulp of π, 1.2·10⁻⁷).
    #[test]
    fn the_polynomial_arc_cosine_is_the_libraries() {
        for i in 0..=20_000 {
            let x = -1.0 + i as f32 / 10_000.0;
            let exact = f64::from(x).acos();
            let error = (f64::from(acos(x)) - exact).abs();
            assert!(
                error <= 2e-8 + 1.2e-7,
                "acos({x}): {} against {exact}",
                acos(x)
            );
        }
    }

    /// On demand, every vertex's and edge's pseudonormal is the precomputed one, bit for bit
    /// (the same sums in the same order), on the procedural head.
    #[test]
    fn on_demand_pseudonormals_are_the_precomputed_ones() {
        let mesh = hair_core::Head::procedural(&hair_core::HeadParams::default())
            .unwrap()
            .mesh;
        let all = Pseudonormals::of(&mesh);
        let body = crate::CollisionBody::from_mesh(&mesh).unwrap();
        let triangles = body.local_triangles();
        let demand = all.on_demand();
        assert!(demand.vertex.is_empty() && demand.edge.is_empty());
        for v in 0..mesh.positions.len() as u32 {
            assert_eq!(
                demand.vertex_normal(triangles, v),
                all.vertex_normal(triangles, v)
            );
        }
        for e in 0..all.edge.len() as u32 {
            assert_eq!(
                demand.edge_normal(triangles, e),
                all.edge_normal(triangles, e)
            );
        }
    }

    /// A right isosceles triangle's corners: π/2 at the right angle, π/4 at the others.
    #[test]
    fn corner_angles_of_a_right_triangle() {
        let [a, b, c, n] = triangle_corners([Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(n, Vec3::Z);
        let quarter = std::f32::consts::FRAC_PI_4;
        assert!((a - Vec3::Z * 2.0 * quarter).length() < 1e-6, "{a}");
        assert!((b - Vec3::Z * quarter).length() < 1e-6, "{b}");
        assert!((c - Vec3::Z * quarter).length() < 1e-6, "{c}");
    }
}
