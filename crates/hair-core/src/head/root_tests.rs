//! Tests of the scalp roots: exact count, placement on the scalp, order, spacing and frames.

use std::sync::OnceLock;

use super::*;

fn head() -> &'static Head {
    static HEAD: OnceLock<Head> = OnceLock::new();
    HEAD.get_or_init(|| Head::procedural(&HeadParams::default()).unwrap())
}

/// Distance from each root to its nearest neighbour [m] (brute force over all pairs).
fn nearest_neighbour_distances(roots: &[ScalpRoot]) -> Vec<f32> {
    roots
        .iter()
        .enumerate()
        .map(|(i, a)| {
            roots
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, b)| a.position.distance(b.position))
                .fold(f32::INFINITY, f32::min)
        })
        .collect()
}

/// Area [m²] of the mesh triangles whose centroid is on the scalp.
fn scalp_area(head: &Head) -> f32 {
    let mesh = &head.mesh;
    mesh.triangles
        .iter()
        .map(|t| t.map(|i| mesh.positions[i as usize]))
        .filter(|[a, b, c]| head.is_scalp((*a + *b + *c) / 3.0))
        .map(|[a, b, c]| 0.5 * (b - a).cross(c - a).length())
        .sum()
}

#[test]
fn exact_count_on_the_scalp_and_on_the_surface() {
    let head = head();
    for count in [1, 2, 3, 7, 50, 333, 2000] {
        let roots = head.scalp_roots(count).unwrap();
        assert_eq!(roots.len(), count);
        assert_eq!(roots[0].position, head.crown());
        assert_eq!(roots[0].crown_distance, 0.0);
        for (i, root) in roots.iter().enumerate() {
            assert!(
                head.is_scalp(root.position),
                "{count}: root {i} at {}",
                root.position
            );
            let (surface, normal) = head.surface_point(root.position);
            assert!(surface.distance(root.position) < 1e-5);
            assert!(normal.dot(root.normal) > 1.0 - 1e-6);
        }
        // Ordered crown to hairline.
        assert!(
            roots
                .windows(2)
                .all(|w| w[0].crown_distance <= w[1].crown_distance)
        );
    }
}

#[test]
fn spacing_is_roughly_even() {
    // Rings h apart with roots h apart along them: nearest-neighbour distances within a factor of 1.5
    // of each other, and their mean near √(scalp area / count) (a square lattice; a hexagonal one
    // would give 1.07 times that).
    let head = head();
    for count in [200, 2000] {
        let roots = head.scalp_roots(count).unwrap();
        let distances = nearest_neighbour_distances(&roots);
        let min = distances.iter().copied().fold(f32::INFINITY, f32::min);
        let max = distances.iter().copied().fold(0.0, f32::max);
        let mean = distances.iter().sum::<f32>() / count as f32;
        assert!(max / min < 1.5, "{count}: {min} m .. {max} m");
        let area = scalp_area(head);
        let lattice = (area / count as f32).sqrt();
        assert!(
            (mean / lattice - 1.0).abs() < 0.2,
            "{count}: mean {mean} m vs {lattice} m"
        );
    }
}

#[test]
fn root_frames_are_unit_tangent_and_right_handed() {
    let head = head();
    let roots = head.scalp_roots(1000).unwrap();
    for root in &roots {
        assert!((root.normal.length() - 1.0).abs() < 1e-5);
        assert!((root.comb_direction.length() - 1.0).abs() < 1e-5);
        assert!((root.across.length() - 1.0).abs() < 1e-5);
        assert!(root.comb_direction.dot(root.normal).abs() < 1e-4);
        assert!(root.across.dot(root.normal).abs() < 1e-4);
        assert!((root.comb_direction.cross(root.normal) - root.across).length() < 1e-5);
        let frame = root.frame();
        assert!((frame.normal.cross(frame.binormal) - frame.tangent).length() < 1e-5);
        assert!((head.part_distance(root.position) - root.part_distance).abs() < 1e-7);
    }
    assert_eq!(roots, head.scalp_roots(1000).unwrap(), "deterministic");
}

#[test]
fn hair_lies_away_from_the_part_and_down_the_sides_and_back() {
    let head = head();
    let offset = head.params.part_offset;
    let crown = head.crown();
    let roots = head.scalp_roots(1000).unwrap();
    let mut near_part = 0;
    for root in &roots {
        let p = root.position;
        if p.z > crown.z + 0.03 && root.part_distance < 0.02 {
            near_part += 1;
            assert_eq!(root.comb_direction.x > 0.0, p.x >= offset, "at {p}");
        }
        // Where the scalp is steeper than 45° the hair runs down, and never forwards there.
        if root.normal.y < std::f32::consts::FRAC_1_SQRT_2 {
            assert!(
                root.comb_direction.y < 0.0,
                "at {p}: {}",
                root.comb_direction
            );
        }
        if p.z < crown.z - 0.03 {
            // Behind the crown, away from it.
            assert!(root.comb_direction.dot(p - crown) > 0.0, "at {p}");
        }
    }
    assert!(near_part > 10);
}

#[test]
fn near_face_roots_frame_the_face() {
    let head = head();
    let roots = head.scalp_roots(2000).unwrap();
    let near: Vec<&ScalpRoot> = roots.iter().filter(|r| r.near_face).collect();
    assert!(near.len() > 50 && near.len() < 1000, "{}", near.len());
    for root in &near {
        assert!(root.position.z > -0.03, "{}", root.position);
    }
    // The roots right at the forehead hairline are near the face; the crown is not.
    assert!(!roots[0].near_face);
    let front = roots
        .iter()
        .max_by(|a, b| a.position.z.total_cmp(&b.position.z))
        .unwrap();
    assert!(front.near_face);
}
