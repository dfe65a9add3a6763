//! Angle-weighted pseudonormals of a triangle mesh (Bærentzen & Aanæs 2005) and its edge
//! structure: what signs the distance to a body ([`crate::surface`]).
//!
//! The pseudonormal of a face is its normal; of an edge, the sum of its faces' normals; of a
//! vertex, the sum of its faces' normals weighted by the face angles at the vertex.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Vec3;
use hair_core::TriangleMesh;

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
    pub fn update(&mut self, triangles: &[[u32; 3]], positions: &[Vec3]) {
        self.vertex.clear();
        self.vertex.resize(positions.len(), Vec3::ZERO);
        self.edge.iter_mut().for_each(|e| *e = Vec3::ZERO);
        for (indices, ids) in triangles.iter().zip(self.triangle_edges.iter()) {
            let p = indices.map(|i| positions[i as usize]);
            let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            for k in 0..3 {
                self.edge[ids[k] as usize] += normal;
                // Angle at vertex k.
                let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
                let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
                let angle = e1.dot(e2).clamp(-1.0, 1.0).acos();
                self.vertex[indices[k] as usize] += normal * angle;
            }
        }
        for n in self.vertex.iter_mut().chain(self.edge.iter_mut()) {
            *n = n.normalize_or_zero();
        }
    }
}
