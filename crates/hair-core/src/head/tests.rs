//! Tests of the procedural head: mesh topology and accuracy, scalp, part line and roots.

use std::collections::HashMap;
use std::sync::OnceLock;

use glam::{DVec3, Vec3};

use super::shape::{
    self, CRANIUM_CENTRE, CRANIUM_SEMI_AXES, NECK_AXIS_Z, NECK_BOTTOM_Y, NECK_RADIUS,
};
use super::*;
use crate::error::HairError;

fn default_head() -> &'static Head {
    static HEAD: OnceLock<Head> = OnceLock::new();
    HEAD.get_or_init(|| Head::procedural(&HeadParams::default()).unwrap())
}

/// Signed volume [m³] of a closed mesh: Σ a · (b × c) / 6 (positive for outward winding).
fn signed_volume(mesh: &TriangleMesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Distance along the ray from the origin in unit `direction` to the mesh, and the triangle hit
/// (Möller–Trumbore over every triangle; the farthest hit, though a star-shaped mesh has one).
fn ray_hit(mesh: &TriangleMesh, direction: DVec3) -> Option<(f64, usize)> {
    let mut best: Option<(f64, usize)> = None;
    for (index, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let p = direction.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-18 {
            continue;
        }
        let s = -a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = direction.dot(q) / det;
        if u < -1e-9 || v < -1e-9 || u + v > 1.0 + 1e-9 {
            continue;
        }
        let distance = e2.dot(q) / det;
        if distance > 0.0 && best.is_none_or(|(b, _)| distance > b) {
            best = Some((distance, index));
        }
    }
    best
}

fn fibonacci_directions(count: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
            let ring = (1.0 - y * y).sqrt();
            let angle = golden * i as f64;
            DVec3::new(ring * angle.sin(), y, ring * angle.cos())
        })
        .collect()
}

/// Chord bound of triangle `index` [m]: a circular arc of chord h that turns by α departs from the
/// chord by its sagitta h/2 · tan(α/4) ≈ h α / 8. With h the longest edge and α the largest angle
/// between the exact vertex normals, twice that bounds the triangle's distance to a smooth surface
/// (the factor 2 covers the curvature varying across the triangle).
fn triangle_chord_bound(mesh: &TriangleMesh, index: usize) -> f64 {
    let t = mesh.triangles[index].map(|i| i as usize);
    let mut bound = 0.0f64;
    for k in 0..3 {
        let (i, j) = (t[k], t[(k + 1) % 3]);
        let h = f64::from(mesh.positions[i].distance(mesh.positions[j]));
        let turn = f64::from(mesh.normals[i].angle_between(mesh.normals[j]));
        bound = bound.max(h * turn / 8.0);
    }
    let longest = (0..3)
        .map(|k| mesh.positions[t[k]].distance(mesh.positions[t[(k + 1) % 3]]))
        .fold(0.0f32, f32::max);
    let turn = (0..3)
        .map(|k| mesh.normals[t[k]].angle_between(mesh.normals[t[(k + 1) % 3]]))
        .fold(0.0f32, f32::max);
    2.0 * bound.max(f64::from(longest * turn) / 8.0)
}

/// Over rays from the centre: the largest gap [m] between mesh and analytic surface, and the largest
/// ratio of that gap to the hit triangle's chord bound measured along the ray (÷ cos(normal, ray)).
fn chord_error(mesh: &TriangleMesh) -> (f64, f64) {
    let mut worst = (0.0f64, 0.0f64);
    for d in fibonacci_directions(400) {
        let (exact, normal) = shape::surface_point(d);
        let (hit, triangle) = ray_hit(mesh, d).expect("every ray leaves a closed star-shaped mesh");
        let error = (hit - exact.length()).abs();
        let bound = triangle_chord_bound(mesh, triangle) / normal.dot(d) + 1e-7;
        worst = (worst.0.max(error), worst.1.max(error / bound));
    }
    worst
}

#[test]
fn mesh_is_closed_and_consistently_wound() {
    let mesh = &default_head().mesh;
    assert_eq!(mesh.vertex_count(), 96 * 63 + 2);
    assert_eq!(mesh.triangle_count(), 2 * 96 * 63);
    // Each directed edge once, and its reverse once: every edge is shared by exactly two triangles
    // that traverse it in opposite directions (consistent winding).
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for (index, t) in mesh.triangles.iter().enumerate() {
        assert!(
            mesh.triangle_normal(index) != Vec3::ZERO,
            "degenerate triangle {index}"
        );
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &count) in &edges {
        assert_eq!(count, 1, "edge {a}->{b} used {count} times");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}->{b} has no twin");
    }
    // Euler characteristic of a sphere: V - E + F = 2.
    let euler =
        mesh.vertex_count() as i64 - (edges.len() / 2) as i64 + mesh.triangle_count() as i64;
    assert_eq!(euler, 2);
}

#[test]
fn volume_is_positive_and_about_cranium_plus_neck() {
    // Reference: the cranium ellipsoid (4/3 π a b c) plus the neck cylinder from the neck's bottom up
    // to the cranium's lowest point (π R² h). The jaw, nose and fillets add to it, the part of the
    // neck cylinder's ends inside the ellipsoid's curved bottom is counted twice: ±15 %.
    let volume = signed_volume(&default_head().mesh);
    let a = CRANIUM_SEMI_AXES;
    let ellipsoid = 4.0 / 3.0 * std::f64::consts::PI * a.x * a.y * a.z;
    let neck_height = (CRANIUM_CENTRE.y - a.y) - NECK_BOTTOM_Y;
    let neck = std::f64::consts::PI * NECK_RADIUS * NECK_RADIUS * neck_height;
    let reference = ellipsoid + neck;
    assert!(volume > 0.0);
    assert!(
        (volume / reference - 1.0).abs() < 0.15,
        "volume {volume} m³ vs {reference} m³"
    );
}

#[test]
fn vertex_normals_point_outwards_and_agree_with_the_faces() {
    let mut mesh = default_head().mesh.clone();
    let exact = mesh.normals.clone();
    for (p, n) in mesh.positions.iter().zip(&exact) {
        assert!((n.length() - 1.0).abs() < 1e-5);
        assert!(p.dot(*n) > 0.0, "normal {n} at {p} points inwards");
    }
    // The exact normals agree with area-weighted face normals to within the tessellation's angle.
    mesh.compute_vertex_normals();
    for (i, (a, b)) in exact.iter().zip(&mesh.normals).enumerate() {
        assert!(a.dot(*b) > 0.97, "vertex {i}: {a} vs {b}");
    }
}

#[test]
fn surface_points_lie_on_the_mesh_within_the_chord_error() {
    // Along every ray the mesh is within its hit triangle's chord bound of the exact surface point,
    // and at the default resolution within 1.5 mm everywhere (the worst place is the nose's tip,
    // about 1 mm; elsewhere a few tenths of a millimetre).
    let mesh = &default_head().mesh;
    let (error, ratio) = chord_error(mesh);
    assert!(ratio <= 1.0, "error exceeds the chord bound {ratio} times");
    assert!(error < 1.5e-3, "chord error {error} m");
    // The vertices are surface points themselves.
    let head = default_head();
    for p in mesh.positions.iter().step_by(37) {
        let (q, _) = head.surface_point(*p);
        assert!(q.distance(*p) < 1e-5);
    }
}

#[test]
fn chord_error_shrinks_quadratically_with_resolution() {
    // Doubling both band counts halves the edges, so the error falls about fourfold (≥ 3×).
    let coarse = Head::procedural(&HeadParams {
        latitude_bands: 32,
        longitude_bands: 48,
        ..HeadParams::default()
    })
    .unwrap();
    let (coarse_error, coarse_ratio) = chord_error(&coarse.mesh);
    let (fine_error, _) = chord_error(&default_head().mesh);
    assert!(coarse_ratio <= 1.0, "{coarse_ratio}");
    assert!(
        fine_error * 3.0 < coarse_error,
        "{coarse_error} m -> {fine_error} m"
    );
}

#[test]
fn surface_point_is_exact_and_its_normal_is_the_surface_normal() {
    let head = default_head();
    for d in fibonacci_directions(200) {
        let (p, n) = head.surface_point(d.as_vec3() * 3.0);
        assert!(((p.length() as f64) - shape::radius_sample(d).radius).abs() < 1e-6);
        // Points a small step away along the surface stay in the tangent plane to second order.
        let tangent = n.any_orthonormal_vector();
        let (q, _) = head.surface_point(p + tangent * 1e-3);
        assert!((q - p).dot(n).abs() < 1e-4, "{d:?}");
    }
    // Bad directions do not panic or give NaN.
    for bad in [Vec3::ZERO, Vec3::NAN, Vec3::INFINITY] {
        let (p, n) = head.surface_point(bad);
        assert!(p.is_finite() && n.is_finite());
    }
}

#[test]
fn scalp_covers_the_top_and_back_but_not_face_or_neck() {
    let head = default_head();
    assert!(head.is_scalp(Vec3::Y));
    assert!(head.is_scalp(Vec3::new(0.0, 0.2, -1.0))); // back of the head
    assert!(head.is_scalp(Vec3::new(1.0, 0.6, 0.0))); // above the ear
    assert!(!head.is_scalp(Vec3::Z)); // face
    assert!(!head.is_scalp(Vec3::new(0.0, -1.0, 0.3))); // under the chin
    assert!(!head.is_scalp(Vec3::NEG_Y)); // neck bottom
    assert!(!head.is_scalp(Vec3::new(0.0, -1.0, -0.1))); // neck
    assert!(!head.is_scalp(Vec3::ZERO) && !head.is_scalp(Vec3::NAN));
    // The hairline is high at the forehead, lower at the ears, low at the nape.
    assert!((head.hairline_height(0.0) - 0.07).abs() < 1e-6);
    assert!((head.hairline_height(std::f32::consts::FRAC_PI_2) - 0.025).abs() < 1e-6);
    assert!((head.hairline_height(std::f32::consts::PI) + 0.07).abs() < 1e-6);
    for p in head.hairline() {
        let height = head.hairline_height(p.x.atan2(p.z));
        assert!((p.y - height).abs() < 1e-4);
        assert!(head.surface_point(*p).0.distance(*p) < 1e-5);
    }
}

#[test]
fn part_line_runs_from_the_forehead_hairline_to_the_crown() {
    let head = default_head();
    let part = head.part_line();
    let offset = head.params.part_offset;
    for p in part {
        assert!((p.x - offset).abs() < 1e-4, "{p}");
        assert!(head.surface_point(*p).0.distance(*p) < 1e-5);
        assert!(head.part_distance(*p) < 1e-6);
    }
    let (front, back) = (part[0], part[part.len() - 1]);
    assert!(front.z > 0.05, "starts at the forehead: {front}");
    assert!((front.y - head.hairline_height(front.x.atan2(front.z))).abs() < 1e-4);
    assert_eq!(back, head.crown());
    assert!(head.crown().z < 0.0 && head.is_scalp(head.crown()));
    // Away from the part the distance grows: 2 cm to the side on the top is about 2 cm.
    let (top, _) = head.surface_point(Vec3::new(offset - 0.02, 0.1, 0.01));
    let distance = head.part_distance(top);
    assert!((distance - 0.02).abs() < 0.003, "{distance}");
}

#[test]
fn inner_box_is_inside_the_head() {
    let head = default_head();
    let (low, high) = head.inner_box();
    assert!(low.cmplt(high).all());
    let steps = 8;
    for i in 0..=steps {
        for j in 0..=steps {
            for k in 0..=steps {
                let t = Vec3::new(i as f32, j as f32, k as f32) / steps as f32;
                let p = low + (high - low) * t;
                let surface = head.surface_point(p).0;
                assert!(p.length() < surface.length(), "{p} outside");
            }
        }
    }
    // "Slightly smaller than the cranium": it spans more than half the cranium's width and height.
    let size = high - low;
    assert!(size.x > 0.075 && size.y > 0.1 && size.z > 0.1, "{size}");
}

#[test]
fn occluder_boxes_are_inside_the_head() {
    let head = default_head();
    let boxes = head.occluder_boxes();
    assert_eq!(boxes.len(), 5);
    for (low, high) in boxes {
        assert!(low.cmplt(high).all());
        let steps = 8;
        for i in 0..=steps {
            for j in 0..=steps {
                for k in 0..=steps {
                    let t = Vec3::new(i as f32, j as f32, k as f32) / steps as f32;
                    let p = low + (high - low) * t;
                    // The head is star-shaped about the origin: inside means nearer the origin
                    // than the surface point in the same direction.
                    let surface = head.surface_point(p).0;
                    assert!(
                        p.length() < surface.length(),
                        "{p} of {low}..{high} outside"
                    );
                }
            }
        }
    }
}

#[test]
fn bad_parameters_are_errors() {
    let error = Head::procedural(&HeadParams {
        part_offset: 0.3,
        ..HeadParams::default()
    })
    .unwrap_err();
    assert!(error.to_string().contains("part_offset"), "{error}");
    for count in [0, MAX_ROOT_COUNT + 1] {
        let error = default_head().scalp_roots(count).unwrap_err();
        assert!(matches!(
            error,
            HairError::InvalidParameter {
                name: "root count",
                ..
            }
        ));
    }
}

#[test]
fn neck_is_a_vertical_cylinder() {
    let (p, n) = shape::surface_point(DVec3::new(0.0, -1.0, -0.4));
    assert!(
        ((p.x).hypot(p.z - NECK_AXIS_Z) - NECK_RADIUS).abs() < 1e-6,
        "{p}"
    );
    assert!(n.y.abs() < 1e-4, "{n}");
}

/// A mesh from a file takes the head's place: its occluder boxes are the ones given, the largest
/// is the inner box, and a bad box or an empty mesh is refused.
#[test]
fn a_head_from_a_mesh_keeps_its_mesh_and_boxes() {
    let procedural = Head::procedural(&HeadParams::default()).unwrap();
    assert!(procedural.is_procedural());
    let small = (Vec3::splat(-0.01), Vec3::splat(0.01));
    let large = (Vec3::splat(-0.03), Vec3::splat(0.02));
    let head = Head::from_mesh(procedural.mesh.clone(), vec![small, large]).unwrap();
    assert!(!head.is_procedural());
    assert_eq!(head.occluder_boxes(), vec![small, large]);
    assert_eq!(head.inner_box(), large);
    assert_eq!(head.mesh, procedural.mesh);
    let inverted = (Vec3::splat(0.01), Vec3::splat(-0.01));
    let error = Head::from_mesh(procedural.mesh.clone(), vec![inverted]).unwrap_err();
    assert!(error.to_string().contains("occluder box"), "{error}");
    let error = Head::from_mesh(crate::TriangleMesh::default(), Vec::new()).unwrap_err();
    assert!(error.to_string().contains("body mesh"), "{error}");
}
