//! Angle-weighted pseudonormals of a triangle mesh (Bærentzen & Aanæs 2005) and its edge
//! structure: what signs the distance to a body ([`crate::surface`]).
//!
//! The pseudonormal of a face is its normal; of an edge, the sum of its faces' normals; of a
//! vertex, the sum of its faces' normals weighted by the face angles at the vertex.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Vec3;
use hair_core::TriangleMesh;
use rayon::prelude::*;

/// Pseudonormals of a mesh in its local frame, and its edge structure.
#[derive(Debug, Clone, Default)]
pub(crate) struct Pseudonormals {
    /// Unit angle-weighted pseudonormal per vertex (zero for unused vertices).
    pub vertex: Vec<Vec3>,
    /// Unit pseudonormal per edge.
    pub edge: Vec<Vec3>,
    /// Per triangle, the edge id of its edges `k → k + 1` (shared by a deforming body's
    /// instants).
    pub triangle_edges: Arc<[[u32; 3]]>,
    /// Whether every edge has exactly two triangles that traverse it in opposite directions.
    pub closed: bool,
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
        let mut pseudonormals = Pseudonormals {
            vertex: Vec::new(),
            edge: vec![Vec3::ZERO; edge_uses.len()],
            triangle_edges: triangle_edges.into(),
            closed,
        };
        pseudonormals.update(&mesh.triangles, &mesh.positions);
        pseudonormals
    }

    /// Recomputes the pseudonormals for the same triangles `triangles` (the ones the edge
    /// structure was built from) over new vertex positions `positions` [m]: a deforming body.
    /// The triangles' normals and corner angles are found side by side (the same values
    /// whatever the thread count), then summed onto the vertices and edges in triangle order.
    pub fn update(&mut self, triangles: &[[u32; 3]], positions: &[Vec3]) {
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
