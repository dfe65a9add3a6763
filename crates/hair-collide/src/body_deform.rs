//! A deforming body's next instant from its last one ([`CollisionBody::deformed`]): the same
//! triangles over new vertex positions, the triangle tree refitted instead of built again, the
//! pseudonormals found on demand on the edge structure already found. What changes each frame costs
//! a pass over the triangles; what only depends on the topology is kept.

use std::sync::{Arc, OnceLock};

use crate::body::{BodyShape, CollisionBody, check_vertex_values, triangle_aabb};
use crate::error::Result;
use crate::geometry::Triangle;
use crate::volume::Pss;
use glam::Vec3;
use rayon::prelude::*;

impl CollisionBody {
    /// This body's triangles over `positions` [m] (its own frame, one per vertex of the mesh it
    /// was built from), the vertices moving at `velocities` [m/s] besides the pose's motion:
    /// what [`CollisionBody::from_moving_mesh`] builds from the deformed mesh, but with the
    /// triangle tree refitted (its topology kept: queries stay exact, the tree's quality drops
    /// only as far as the deformation reorders the triangles) and the edge structure kept. The
    /// pose is this body's; the bounding ball keeps its centre and grows to the farthest vertex.
    /// The topology (triangle indices, edge structure) is shared with this body, not copied.
    /// A body reading a rest field ([`CollisionBody::reading_rest_field`]) keeps reading it,
    /// fitted to the new positions.
    ///
    /// Errors on a count that is not the mesh's vertices or a position or velocity that is not
    /// finite.
    pub fn deformed(&self, positions: &[Vec3], velocities: Vec<Vec3>) -> Result<Self> {
        let shape = &self.shape;
        let vertex_count = shape.pseudonormals.vertex_count;
        check_vertex_values("deformed positions", positions, vertex_count)?;
        check_vertex_values("vertex velocities", &velocities, vertex_count)?;
        let triangles: Vec<Triangle> = shape
            .indices
            .par_iter()
            .with_min_len(1024)
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                Triangle::new(a, b, c)
            })
            .collect();
        let mut bvh = shape.bvh.clone();
        for (id, triangle) in triangles.iter().enumerate() {
            bvh.update_partially_if_present(triangle_aabb(triangle), id as u32, 0.0);
        }
        bvh.refit_without_opt();
        // Found when a closest point needs one: most are never read in a frame.
        let pseudonormals = shape.pseudonormals.on_demand();
        let center = shape.bound.center;
        // The vertices that triangles use: each triangle's corners.
        let radius = triangles
            .par_iter()
            .with_min_len(1024)
            .map(|t| {
                let [a, b, c] = t.vertices.map(|v| v.distance_squared(center));
                a.max(b).max(c)
            })
            .reduce(|| 0.0f32, f32::max)
            .sqrt();
        let bound = Pss { center, radius };
        let deformation = shape.deformation.as_ref().map(|d| d.at(&triangles));
        let deformed = BodyShape {
            indices: shape.indices.clone(),
            triangles,
            bound,
            bvh,
            pseudonormals,
            field: OnceLock::new(),
            vertex_velocities: velocities,
            deformation,
        };
        Ok(self.with_shape(Arc::new(deformed)))
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use hair_core::{Head, HeadParams, TriangleMesh};

    use crate::body::CollisionBody;

    /// The procedural head stretched 8 % up, squeezed across and bulged: a deformation that
    /// moves every triangle, with a made-up velocity per vertex.
    fn deformed_head() -> (CollisionBody, TriangleMesh, Vec<Vec3>) {
        let mesh = Head::procedural(&HeadParams::default()).unwrap().mesh;
        let body = CollisionBody::from_mesh(&mesh).unwrap();
        let mut moved = mesh.clone();
        for p in &mut moved.positions {
            *p =
                Vec3::new(p.x * 0.96, p.y * 1.08, p.z * 0.97) + Vec3::Z * 0.01 * (p.y * 20.0).sin();
        }
        let velocities = moved
            .positions
            .iter()
            .map(|p| Vec3::new(p.y, -p.x, 0.5 * p.z))
            .collect();
        (body, moved, velocities)
    }

    #[test]
    fn a_refitted_body_answers_as_the_body_built_from_the_deformed_mesh() {
        let (rest, moved, velocities) = deformed_head();
        let refitted = rest.deformed(&moved.positions, velocities.clone()).unwrap();
        let built = CollisionBody::from_moving_mesh(&moved, velocities).unwrap();
        assert_eq!(refitted.is_closed(), built.is_closed());
        assert!(refitted.is_deforming());
        // The same triangles and pseudonormals, searched through two trees: the closest
        // distance is the same number (each triangle's is computed the same way); where two
        // triangles tie, either may be reported, so positions and velocities compare within
        // rounding.
        let (mut checked, mut ties) = (0, 0);
        for i in 0..20 {
            for j in 0..20 {
                for k in 0..10 {
                    let p = Vec3::new(
                        -0.15 + 0.3 * i as f32 / 19.0,
                        -0.2 + 0.4 * j as f32 / 19.0,
                        -0.15 + 0.3 * k as f32 / 9.0,
                    );
                    let (a, b) = (
                        refitted.closest_local_surface_point(p).unwrap(),
                        built.closest_local_surface_point(p).unwrap(),
                    );
                    assert_eq!(a.signed_distance, b.signed_distance, "at {p}");
                    // The reported point lies on the deformed surface either way.
                    let on = built.closest_local_surface_point(a.point).unwrap();
                    assert!(on.signed_distance.abs() <= 1e-6, "at {p}: {on:?}");
                    if a.point.distance(b.point) > 1e-6 {
                        // A tie: two points of the surface at the same distance.
                        ties += 1;
                        checked += 1;
                        continue;
                    }
                    let (va, vb) = (
                        refitted.deformation_velocity(p),
                        built.deformation_velocity(p),
                    );
                    assert!(va.distance(vb) <= 1e-5, "at {p}: {va} and {vb}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 4000);
        assert!(ties <= 40, "{ties} ties of 4000");
        // The bounding ball holds every deformed vertex.
        let ball = refitted.local_bounding_volume();
        for p in &moved.positions {
            assert!(
                p.distance(ball.center) <= ball.radius * (1.0 + 1e-6),
                "{p} outside"
            );
        }
    }

    #[test]
    fn a_deformation_of_another_size_or_not_finite_is_refused() {
        let (rest, moved, velocities) = deformed_head();
        let short = &moved.positions[1..];
        let error = rest
            .deformed(short, velocities.clone())
            .unwrap_err()
            .to_string();
        assert!(error.contains("deformed positions"), "{error}");
        let mut bad = moved.positions.clone();
        bad[7] = Vec3::NAN;
        let error = rest.deformed(&bad, velocities).unwrap_err().to_string();
        assert!(
            error.contains("deformed positions") && error.contains('7'),
            "{error}"
        );
    }
}
