//! Roots attached to a body: each root's closest triangle and its barycentric coordinates there,
//! so that a root rides the body's surface wherever the body moves or deforms, and how far the
//! roots lay from the surface when they were attached (a groom made for another body, or in other
//! units, shows up there first).

use glam::Vec3;
use hair_core::TriangleMesh;
use serde::{Deserialize, Serialize};

use crate::body::CollisionBody;
use crate::error::{CollideError, Result};

/// Where one root is attached.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RootAttachment {
    /// The body triangle the root is attached to (its index in the body's mesh).
    pub triangle: u32,
    /// Barycentric coordinates of the attachment point on that triangle (non-negative, sum 1).
    pub barycentric: Vec3,
    /// Signed distance from the root to the surface when attached [m]: positive outside.
    pub signed_distance: f32,
}

impl RootAttachment {
    /// The attachment point on `mesh` [m]: the barycentric combination of the triangle's vertices,
    /// so it follows any motion or deformation of the mesh (same triangles, moved vertices).
    pub fn point_on(&self, mesh: &TriangleMesh) -> Vec3 {
        let [a, b, c] = mesh.triangles[self.triangle as usize].map(|i| mesh.positions[i as usize]);
        a * self.barycentric.x + b * self.barycentric.y + c * self.barycentric.z
    }
}

/// How far a set of roots lay from the surface they were attached to [m] (absolute distances).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct AttachmentReport {
    /// Roots attached.
    pub roots: usize,
    /// Mean distance [m].
    pub mean: f32,
    /// Median distance [m].
    pub median: f32,
    /// 95th percentile [m].
    pub p95: f32,
    /// Largest distance [m].
    pub max: f32,
    /// Roots inside the body (negative signed distance; only meaningful for closed meshes).
    pub inside: usize,
}

/// Attaches every root (world [m]) to the closest point of `body`'s surface (as posed now):
/// triangle, barycentric coordinates and signed distance, through the body's triangle tree.
/// Fails, naming the root, on a non-finite root.
pub fn attach_roots(
    body: &CollisionBody,
    roots: &[Vec3],
) -> Result<(Vec<RootAttachment>, AttachmentReport)> {
    let triangles = body.local_triangles();
    let mut attachments = Vec::with_capacity(roots.len());
    for (index, &root) in roots.iter().enumerate() {
        let surface = body
            .closest_local_surface_point(body.to_local(root))
            .ok_or(CollideError::NonFinite {
                what: "root",
                index,
            })?;
        let [a, b, c] = triangles[surface.triangle as usize].vertices;
        attachments.push(RootAttachment {
            triangle: surface.triangle,
            barycentric: barycentric(surface.point, a, b, c),
            signed_distance: surface.signed_distance,
        });
    }
    let report = report(&attachments);
    Ok((attachments, report))
}

/// The distances' summary of `attachments`.
fn report(attachments: &[RootAttachment]) -> AttachmentReport {
    if attachments.is_empty() {
        return AttachmentReport::default();
    }
    let mut distances: Vec<f32> = attachments
        .iter()
        .map(|a| a.signed_distance.abs())
        .collect();
    distances.sort_by(f32::total_cmp);
    let at = |q: f32| distances[((distances.len() - 1) as f32 * q).round() as usize];
    AttachmentReport {
        roots: distances.len(),
        mean: distances.iter().sum::<f32>() / distances.len() as f32,
        median: at(0.5),
        p95: at(0.95),
        max: at(1.0),
        inside: attachments
            .iter()
            .filter(|a| a.signed_distance < 0.0)
            .count(),
    }
}

/// Barycentric coordinates of `p` (on the plane of `a, b, c`) with respect to that triangle,
/// clamped to the triangle and renormalised (a closest point lies on it up to rounding); the
/// centroid for a degenerate triangle.
fn barycentric(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
    let (d20, d21) = (ap.dot(ab), ap.dot(ac));
    let denominator = d00 * d11 - d01 * d01;
    if denominator.abs() <= f32::EPSILON * d00 * d11 {
        return Vec3::splat(1.0 / 3.0);
    }
    let v = (d11 * d20 - d01 * d21) / denominator;
    let w = (d00 * d21 - d01 * d20) / denominator;
    let weights = Vec3::new(1.0 - v - w, v, w).max(Vec3::ZERO);
    weights / weights.element_sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    /// A closed octahedron of radius 0.1 m around the origin.
    fn octahedron() -> TriangleMesh {
        let positions = vec![
            Vec3::X * 0.1,
            -Vec3::X * 0.1,
            Vec3::Y * 0.1,
            -Vec3::Y * 0.1,
            Vec3::Z * 0.1,
            -Vec3::Z * 0.1,
        ];
        let triangles = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        let mut mesh = TriangleMesh {
            positions,
            normals: Vec::new(),
            triangles,
        };
        mesh.compute_vertex_normals();
        mesh
    }

    fn points() -> Vec<Vec3> {
        // A deterministic scatter inside and outside the octahedron.
        (0..200)
            .map(|i| {
                let t = i as f32;
                Vec3::new(
                    (t * 0.731).sin(),
                    (t * 1.173).cos(),
                    (t * 0.377).sin() * (t * 0.911).cos(),
                ) * (0.02 + 0.2 * ((t * 0.19).sin().abs()))
            })
            .collect()
    }

    #[test]
    fn attachments_are_the_closest_surface_points_found_by_brute_force() {
        let mesh = octahedron();
        let body = CollisionBody::from_mesh(&mesh).unwrap();
        let roots = points();
        let (attachments, report) = attach_roots(&body, &roots).unwrap();
        for (root, attachment) in roots.iter().zip(&attachments) {
            let on = attachment.point_on(&mesh);
            // The brute-force distance: the least over every triangle.
            let brute = body
                .local_triangles()
                .iter()
                .map(|t| {
                    crate::closest::closest_point_on_triangle(*root, t)
                        .0
                        .distance(*root)
                })
                .fold(f32::INFINITY, f32::min);
            assert!((on.distance(*root) - brute).abs() < 1e-6, "{root}");
            assert!((attachment.signed_distance.abs() - brute).abs() < 1e-6);
            let b = attachment.barycentric;
            assert!(b.min_element() >= 0.0 && (b.element_sum() - 1.0).abs() < 1e-6);
        }
        // Inside points are counted (the octahedron is closed).
        let inside = roots
            .iter()
            .filter(|p| p.x.abs() + p.y.abs() + p.z.abs() < 0.1 - 1e-4)
            .count();
        assert_eq!(report.inside, inside);
        assert!(report.median <= report.p95 && report.p95 <= report.max);
    }

    #[test]
    fn attached_roots_ride_the_moving_body() {
        // Attach on the body at rest, move every vertex rigidly: the attachment point moves with
        // the same rigid motion (barycentric coordinates are invariant under it).
        let mesh = octahedron();
        let body = CollisionBody::from_mesh(&mesh).unwrap();
        let roots = points();
        let (attachments, _) = attach_roots(&body, &roots).unwrap();
        let (rotation, shift) = (Quat::from_rotation_y(0.8), Vec3::new(0.3, -0.1, 0.2));
        let mut moved = mesh.clone();
        for p in &mut moved.positions {
            *p = rotation * *p + shift;
        }
        for attachment in &attachments {
            let expected = rotation * attachment.point_on(&mesh) + shift;
            assert!(attachment.point_on(&moved).distance(expected) < 1e-6);
        }
    }

    #[test]
    fn a_non_finite_root_is_named() {
        let body = CollisionBody::from_mesh(&octahedron()).unwrap();
        let error = attach_roots(&body, &[Vec3::ZERO, Vec3::NAN]).unwrap_err();
        assert!(error.to_string().contains("root at index 1"), "{error}");
    }
}
