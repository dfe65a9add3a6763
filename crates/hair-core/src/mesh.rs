//! Indexed triangle meshes with vertex normals: the head, collision bodies, tessellated surfaces.

use glam::Vec3;

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
mod tests {
    use super::*;

    #[test]
    fn tetrahedron_normals_point_outwards() {
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            normals: Vec::new(),
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        };
        mesh.compute_vertex_normals();
        let centre = Vec3::splat(0.25);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!((*p - centre).dot(*n) > 0.0);
        }
        assert_eq!(mesh.triangle_normal(3), Vec3::ONE.normalize());
    }
}
