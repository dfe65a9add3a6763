//! Tessellation of NURBS surfaces into triangle meshes with normals from the partial derivatives.

use glam::Vec3;

use crate::error::{HairError, Result};
use crate::mesh::TriangleMesh;

use super::sampler::CurveSampler;
use super::surface::{NurbsSurface, unit_cross};

impl NurbsSurface {
    /// Tessellates the surface into a triangle mesh with `segments_u × segments_v` quads (two
    /// counter-clockwise triangles each, seen from the `S_u × S_v` side) over evenly spaced
    /// parameters.
    ///
    /// Vertices are a grid, u-fastest: vertex `a + samples_u · b` is at parameters `(u_a, v_b)`,
    /// with `samples = segments + 1` (both ends) in an open direction and `samples = segments` in a
    /// periodic one, whose last quad wraps to the first sample: seam vertices are *not* duplicated,
    /// as the mesh has no texture coordinates that would need them, and shared vertices keep it
    /// watertight. So there are `samples_u × samples_v` vertices and `2 · segments_u · segments_v`
    /// triangles. Normals are the unit `S_u × S_v` from the partials;
    /// where that vanishes (a pole), the limit normal of [`NurbsSurface::normal`], and where that
    /// fails too, the area-weighted average of the adjacent triangle normals (zero if all are
    /// degenerate).
    ///
    /// Errors: `segments_u` / `segments_v` below 1 in an open direction or below 3 in a periodic one;
    /// more vertices than `u32` indices can address.
    pub fn tessellate(&self, segments_u: usize, segments_v: usize) -> Result<TriangleMesh> {
        let samples_u = sample_count("segments_u", segments_u, self.is_closed_u())?;
        let samples_v = sample_count("segments_v", segments_v, self.is_closed_v())?;
        let vertex_count = samples_u
            .checked_mul(samples_v)
            .filter(|&count| u32::try_from(count).is_ok())
            .ok_or_else(|| {
                HairError::invalid(
                    "segments_u",
                    format!("{segments_u} × {segments_v} segments"),
                    "at most u32::MAX vertices",
                )
            })?;
        let sampler_u = CurveSampler::new(self.knots_u(), samples_u)?;
        let sampler_v = CurveSampler::new(self.knots_v(), samples_v)?;

        let mut positions = Vec::with_capacity(vertex_count);
        let mut normals = Vec::with_capacity(vertex_count);
        let mut degenerate = Vec::new();
        for b in 0..samples_v {
            let row_v = sampler_v.basis_at(b);
            for a in 0..samples_u {
                let (point, partial_u, partial_v) =
                    self.evaluate_from_basis(sampler_u.basis_at(a), row_v);
                let normal = unit_cross(partial_u, partial_v)
                    .or_else(|| {
                        self.limit_normal(sampler_u.parameters()[a], sampler_v.parameters()[b])
                    })
                    .unwrap_or_else(|| {
                        degenerate.push(positions.len());
                        Vec3::ZERO
                    });
                positions.push(point);
                normals.push(normal);
            }
        }

        let index = |a: usize, b: usize| (a % samples_u + samples_u * (b % samples_v)) as u32;
        let mut triangles = Vec::with_capacity(2 * segments_u * segments_v);
        for b in 0..segments_v {
            for a in 0..segments_u {
                let corner = index(a, b);
                let next_u = index(a + 1, b);
                let next_uv = index(a + 1, b + 1);
                let next_v = index(a, b + 1);
                triangles.push([corner, next_u, next_uv]);
                triangles.push([corner, next_uv, next_v]);
            }
        }

        let mut mesh = TriangleMesh {
            positions,
            normals: Vec::new(),
            triangles,
        };
        if degenerate.is_empty() {
            mesh.normals = normals;
        } else {
            mesh.compute_vertex_normals();
            for i in degenerate {
                normals[i] = mesh.normals[i];
            }
            mesh.normals = normals;
        }
        Ok(mesh)
    }
}

/// Samples along one direction for `segments` quads: `segments + 1` when open (at least 1
/// segment), `segments` when periodic (at least 3, so no quad folds onto itself).
fn sample_count(name: &'static str, segments: usize, periodic: bool) -> Result<usize> {
    if periodic {
        if segments < 3 {
            return Err(HairError::invalid(
                name,
                segments,
                "at least 3 around a periodic direction",
            ));
        }
        Ok(segments)
    } else {
        if segments < 1 {
            return Err(HairError::invalid(name, segments, "at least 1"));
        }
        segments
            .checked_add(1)
            .ok_or_else(|| HairError::invalid(name, segments, "fewer than usize::MAX"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::KnotVector;
    use crate::nurbs::test_support::{close, cylinder};

    #[test]
    fn tessellating_an_open_surface() {
        // Open × open: (s_u + 1)(s_v + 1) vertices, 2 s_u s_v triangles; vertices lie on the
        // surface at (a / s_u, b / s_v); the cylinder's normals are radial (outwards).
        let (surface, _) = cylinder(Vec3::ZERO, 0.3, 2.0);
        let mesh = surface.tessellate(3, 16).unwrap();
        assert_eq!(mesh.vertex_count(), 4 * 17);
        assert_eq!(mesh.triangle_count(), 2 * 3 * 16);
        assert_eq!(mesh.normals.len(), mesh.vertex_count());
        for b in 0..=16 {
            for a in 0..=3 {
                let k = a + 4 * b;
                let expected = surface.point(a as f32 / 3.0, b as f32 / 16.0);
                assert!(close(mesh.positions[k], expected, 2.0));
                let radial = Vec3::new(expected.x, 0.0, expected.z) / 0.3;
                assert!(close(mesh.normals[k], radial, 1.0));
            }
        }
        // Counter-clockwise: every triangle's normal agrees with its vertices' normals.
        for t in 0..mesh.triangle_count() {
            let face = mesh.triangle_normal(t);
            for &i in &mesh.triangles[t] {
                assert!(face.dot(mesh.normals[i as usize]) > 0.0);
            }
        }
    }

    #[test]
    fn tessellating_a_periodic_tube() {
        // A cluster-like tube: 5 rings of 4 control points (clamped cubic along u, periodic cubic
        // around v). Periodic v: s_v samples, no duplicated seam: (s_u + 1)·s_v vertices,
        // 2 s_u s_v triangles, all vertex positions distinct, the mesh closed around v (each
        // u-edge of the grid shared by exactly two triangles except along the open ends).
        let mut points = Vec::new();
        for j in 0..4 {
            let angle = j as f32 * std::f32::consts::FRAC_PI_2;
            for i in 0..5 {
                let ring_radius = 0.1 - 0.015 * i as f32;
                // u runs down (−Y) and v turns counter-clockwise about +Y (clockwise about the
                // tube's direction), so that S_u × S_v points out: (−Y) × (−Z) = +X at angle 0.
                let direction = Vec3::new(angle.cos(), 0.0, -angle.sin());
                points.push(Vec3::new(0.0, -0.2 * i as f32, 0.0) + ring_radius * direction);
            }
        }
        let knots_u = KnotVector::clamped_uniform(5, 3).unwrap();
        let knots_v = KnotVector::periodic_uniform(4, 3).unwrap();
        let surface = NurbsSurface::new(knots_u, knots_v, points).unwrap();
        assert!(surface.is_closed_v() && !surface.is_closed_u());
        let mesh = surface.tessellate(6, 8).unwrap();
        assert_eq!(mesh.vertex_count(), 7 * 8);
        assert_eq!(mesh.triangle_count(), 2 * 6 * 8);
        for (i, a) in mesh.positions.iter().enumerate() {
            for b in &mesh.positions[i + 1..] {
                assert!((*a - *b).length() > 1e-4);
            }
        }
        let mut edge_uses = std::collections::HashMap::new();
        for triangle in &mesh.triangles {
            for k in 0..3 {
                let (a, b) = (triangle[k], triangle[(k + 1) % 3]);
                *edge_uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let boundary = edge_uses.values().filter(|&&uses| uses == 1).count();
        assert_eq!(boundary, 2 * 8, "only the two end rings are open");
        assert!(edge_uses.values().all(|&uses| uses <= 2));
        // Normals point away from the axis and agree with the winding.
        for (point, normal) in mesh.positions.iter().zip(&mesh.normals) {
            assert!(Vec3::new(point.x, 0.0, point.z).dot(*normal) > 0.0);
        }
        for t in 0..mesh.triangle_count() {
            let face = mesh.triangle_normal(t);
            for &i in &mesh.triangles[t] {
                assert!(face.dot(mesh.normals[i as usize]) > 0.0);
            }
        }
    }

    #[test]
    fn a_cone_apex_gets_the_limit_normal() {
        // A cone: the top row of control points collapses to the apex Y, S(u, v) =
        // (1 − u) C(v) + u Y with C the circle of radius r = 0.5 in y = 0 (turning about −Y), so
        // S_v = (1 − u) C′(v) vanishes at u = 1. The cone's normal is constant along a generator:
        // n(v) ∝ h·ρ(v) + r·Y with ρ = C(v)/r the radial unit vector and h = 1, so the limit normal
        // at the apex equals it exactly. Tolerance: near the apex S_v = δ C′ (δ = 10⁻³) is summed
        // from terms whose Σ N′ = 0 only to roundoff ε Σ|N′| |Y|, a relative error ≈ 10⁻⁴; 1e-3.
        let (mut surface, circle) = cylinder(Vec3::ZERO, 0.5, 1.0);
        let mut points = surface.control_points().to_vec();
        for k in (1..points.len()).step_by(2) {
            points[k] = Vec3::Y;
        }
        surface.set_control_points(&points).unwrap();
        let mesh = surface.tessellate(2, 12).unwrap();
        for b in 0..=12 {
            let v = b as f32 / 12.0;
            let radial = circle.point(v) / 0.5;
            let expected = (radial + 0.5 * Vec3::Y).normalize();
            for a in 0..3 {
                let normal = mesh.normals[a + 3 * b];
                assert!(
                    (normal - expected).length() <= 1e-3,
                    "({a}, {b}): {normal} vs {expected}"
                );
            }
            assert!((surface.normal(1.0, v) - expected).length() <= 1e-3);
        }
        // A surface collapsed to a point has no normal at all: zero, never NaN.
        let point = NurbsSurface::clamped(vec![Vec3::X; 4], 2, 2, 1, 1).unwrap();
        assert_eq!(point.normal(0.5, 0.5), Vec3::ZERO);
        let mesh = point.tessellate(1, 1).unwrap();
        assert!(mesh.normals.iter().all(|n| *n == Vec3::ZERO));
    }

    #[test]
    fn bad_segment_counts_are_rejected() {
        let what = |error: HairError| match error {
            HairError::InvalidParameter { name, .. } => name,
            other => panic!("unexpected {other}"),
        };
        let surface = NurbsSurface::clamped(vec![Vec3::ZERO; 6], 3, 2, 2, 1).unwrap();
        assert_eq!(what(surface.tessellate(0, 4).unwrap_err()), "segments_u");
        let tube = NurbsSurface::new(
            KnotVector::clamped_uniform(2, 1).unwrap(),
            KnotVector::periodic_uniform(4, 2).unwrap(),
            vec![Vec3::X; 8],
        )
        .unwrap();
        assert_eq!(what(tube.tessellate(1, 2).unwrap_err()), "segments_v");
    }
}
