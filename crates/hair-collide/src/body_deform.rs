//! A deforming body's next instant from its last one ([`CollisionBody::deformed`]): the same
//! triangles over new vertex positions, the triangle tree refitted instead of built again, the
//! pseudonormals found on demand on the edge structure already found. What changes each frame costs
//! a pass over the triangles; what only depends on the topology is kept, and an instant no longer
//! needed lends its memory to the next ([`CollisionBody::deformed_reusing`]).

use std::sync::{Arc, OnceLock};

use crate::body::{BodyShape, CollisionBody, check_vertex_values};
use crate::error::Result;
use crate::geometry::Triangle;
use crate::triangle_groups::{TriangleGroups, leaf_order};
use crate::volume::Pss;
use glam::Vec3;
use parry3d::partitioning::Bvh;
use rayon::prelude::*;

/// Triangles per task of the pass over the triangles.
const TRIANGLES_PER_TASK: usize = 2048;

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
        self.deformed_reusing(positions, velocities, None)
    }

    /// [`CollisionBody::deformed`], written into the memory of `spare`, an earlier instant of
    /// this body that is no longer needed: its triangles and its tree are overwritten instead
    /// of allocated and copied (a 20k-triangle tree is 1.6 MB). A spare that something else
    /// still holds (a clone of it lives on), or that is not an instant of this body's mesh, is
    /// dropped and the memory allocated. The result is the same either way.
    pub fn deformed_reusing(
        &self,
        positions: &[Vec3],
        velocities: Vec<Vec3>,
        spare: Option<CollisionBody>,
    ) -> Result<Self> {
        let shape = &self.shape;
        let vertex_count = shape.pseudonormals.vertex_count;
        check_vertex_values("deformed positions", positions, vertex_count)?;
        check_vertex_values("vertex velocities", &velocities, vertex_count)?;
        let spare = spare
            .and_then(|spare| Arc::try_unwrap(spare.shape).ok())
            .filter(|spare| {
                Arc::ptr_eq(&spare.indices, &shape.indices)
                    && spare.triangles.len() == shape.triangles.len()
            });
        let (mut triangles, mut bvh) = match spare {
            Some(spare) => (spare.triangles, spare.bvh),
            None => (
                vec![Triangle::new(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO); shape.triangles.len()],
                shape.bvh.clone(),
            ),
        };
        let center = shape.bound.center;
        let order = shape.leaf_order.get_or_init(|| leaf_order(&shape.bvh));
        // The tree and the fit read the positions, as the triangles do: the two sides take
        // about as long.
        let (deformation, radius_squared) = rayon::join(
            || {
                refit(&mut bvh, &shape.groups, &shape.indices, order, positions);
                shape.deformation.as_ref().map(|d| d.at(positions))
            },
            || write_triangles(&mut triangles, &shape.indices, positions, center),
        );
        // Found when a closest point needs one: most are never read in a frame.
        let pseudonormals = shape.pseudonormals.on_demand();
        let bound = Pss {
            center,
            radius: radius_squared.sqrt(),
        };
        let deformed = BodyShape {
            indices: shape.indices.clone(),
            triangles,
            bound,
            bvh,
            groups: shape.groups.clone(),
            leaf_order: shape.leaf_order.clone(),
            pseudonormals,
            field: OnceLock::new(),
            vertex_velocities: velocities,
            deformation,
        };
        Ok(self.with_shape(Arc::new(deformed)))
    }
}

/// The leaves of `bvh` (one per group of `groups`) moved to their triangles over `positions`,
/// in the tree's memory `order` ([`leaf_order`]), and the tree refitted.
fn refit(
    bvh: &mut Bvh,
    groups: &TriangleGroups,
    indices: &[[u32; 3]],
    order: &[u32],
    positions: &[Vec3],
) {
    for &group in order {
        if let Some(aabb) = groups.aabb_over(group, indices, positions) {
            bvh.update_partially_if_present(aabb, group, 0.0);
        }
    }
    bvh.refit_without_opt();
}

/// Writes the triangles of `indices` over `positions` into `triangles`; returns the largest
/// squared distance of a corner from `center` \[m²\].
fn write_triangles(
    triangles: &mut [Triangle],
    indices: &[[u32; 3]],
    positions: &[Vec3],
    center: Vec3,
) -> f32 {
    triangles
        .par_chunks_mut(TRIANGLES_PER_TASK)
        .zip(indices.par_chunks(TRIANGLES_PER_TASK))
        .map(|(out, indices)| {
            let mut reach = 0.0f32;
            for (out, corners) in out.iter_mut().zip(indices) {
                let [a, b, c] = corners.map(|i| positions[i as usize]);
                *out = Triangle::new(a, b, c);
                reach = reach.max(
                    a.distance_squared(center)
                        .max(b.distance_squared(center))
                        .max(c.distance_squared(center)),
                );
            }
            reach
        })
        .reduce(|| 0.0, f32::max)
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

    /// A body's triangles (corners, normal), bounding ball and closest points (signed
    /// distance, triangle) at 200 points: plain values to compare.
    type Answers = (Vec<[Vec3; 4]>, (Vec3, f32), Vec<(f32, u32)>);

    /// The [`Answers`] of `body`.
    fn answers(body: &CollisionBody) -> Answers {
        let triangles = body
            .local_triangles()
            .iter()
            .map(|t| [t.vertices[0], t.vertices[1], t.vertices[2], t.normal])
            .collect();
        let ball = body.local_bounding_volume();
        let closest = (0..200)
            .map(|k| {
                let t = k as f32 * 0.1;
                let p = Vec3::new(
                    0.12 * t.sin(),
                    0.15 * (0.7 * t).cos(),
                    0.1 * (1.3 * t).sin(),
                );
                let found = body.closest_local_surface_point(p).unwrap();
                (found.signed_distance, found.triangle)
            })
            .collect();
        (triangles, (ball.center, ball.radius), closest)
    }

    #[test]
    fn an_instant_made_in_a_spares_memory_is_the_instant_made_afresh_and_a_held_spare_is_left_alone()
     {
        let (rest, moved, velocities) = deformed_head();
        let afresh = rest.deformed(&moved.positions, velocities.clone()).unwrap();
        // A spare nothing else holds: an earlier instant of the same body, its memory reused.
        let shrunk: Vec<Vec3> = moved.positions.iter().map(|p| *p * 0.9).collect();
        let earlier = rest.deformed(&shrunk, velocities.clone()).unwrap();
        let memory = earlier.local_triangles().as_ptr();
        let reused = rest
            .deformed_reusing(&moved.positions, velocities.clone(), Some(earlier))
            .unwrap();
        assert_eq!(
            reused.local_triangles().as_ptr(),
            memory,
            "the spare's memory"
        );
        assert_eq!(answers(&reused), answers(&afresh));
        // A spare still held elsewhere keeps its triangles: the memory is allocated instead.
        let held = rest.deformed(&moved.positions, velocities.clone()).unwrap();
        let copy = held.clone();
        let before = answers(&copy);
        let squashed: Vec<Vec3> = moved.positions.iter().map(|p| *p * 1.1).collect();
        let other = rest
            .deformed_reusing(&squashed, velocities.clone(), Some(held))
            .unwrap();
        assert_eq!(answers(&copy), before);
        assert_ne!(
            other.local_triangles().as_ptr(),
            copy.local_triangles().as_ptr()
        );
        assert_eq!(
            answers(&other),
            answers(&rest.deformed(&squashed, velocities.clone()).unwrap())
        );
        // A spare of another mesh is not used.
        let stranger = CollisionBody::from_moving_mesh(&moved, velocities.clone()).unwrap();
        let third = rest
            .deformed_reusing(&moved.positions, velocities, Some(stranger))
            .unwrap();
        assert_eq!(answers(&third), answers(&afresh));
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
