//! A body's distance field against the exact closest-point search: every bound it gives is a
//! lower bound on the true distance with the true sign (a certificate), it is within `2h√3` of
//! the distance wherever it can be (so it clears what it should), an open mesh gets distances
//! without signs, and a volume the field clears touches no triangle (brute force).

mod support;

use glam::Vec3;
use hair_collide::geometry::Rectangle;
use hair_collide::volume::{Lss, Pss, Rss};
use hair_collide::{CollisionBody, DistanceField, SweptSphere};
use support::{Rng, uv_sphere};

/// f32 rounding of distances at 0.3 m, a few ulps (the field's own allowance is 1 µm).
const ROUNDING: f32 = 2.0e-6;

fn sphere_body() -> (CollisionBody, Vec3, f32) {
    let (center, radius) = (Vec3::new(0.02, -0.01, 0.03), 0.05);
    let body = CollisionBody::from_mesh(&uv_sphere(center, radius, 24, 48)).unwrap();
    (body, center, radius)
}

/// Random points from deep inside the sphere to past the grid's edge.
fn points(rng: &mut Rng, center: Vec3, radius: f32, count: usize) -> Vec<Vec3> {
    (0..count)
        .map(|_| center + rng.direction() * rng.range(0.0, 2.5 * radius))
        .collect()
}

#[test]
fn a_closed_body_gets_certified_signed_bounds_within_two_cell_diagonals() {
    let (body, center, radius) = sphere_body();
    let cell = 2.0e-3;
    let field = DistanceField::of(&body, cell);
    assert!(field.is_signed());
    assert_eq!(field.cell(), cell);
    assert!(field.seed_count() > 0);
    let mut rng = Rng::new(3);
    let (mut inside, mut outside) = (0, 0);
    for p in points(&mut rng, center, radius, 6000) {
        let exact = body.signed_distance(p).unwrap();
        let (bound, sign) = field.bound(p);
        assert!(
            bound <= exact.abs() + ROUNDING,
            "p {p}: bound {bound} above the distance {exact}"
        );
        if bound > 0.0 {
            assert_eq!(
                sign,
                exact.signum(),
                "p {p}: bound {bound}, distance {exact}"
            );
            if sign < 0.0 {
                inside += 1;
            } else {
                outside += 1;
            }
        }
        let (low, high) = field.grid_bounds();
        if p.clamp(low, high) != p {
            // Beyond the grid the bound is the distance to the body's bounds only.
            continue;
        }
        // Each corner v holds at least |d(v)| − h√3 (exact on the seeds; off them d(v) ≤ e(v) + T
        // through the nearest seed), and the nearest corner is within h√3/2 of p:
        // bound ≥ |d(p)| − 2·|p − v| − h√3 ≥ |d(p)| − 2h√3.
        assert!(
            bound >= exact.abs() - 2.0 * cell * 3.0f32.sqrt() - ROUNDING,
            "p {p}: bound {bound} too loose for the distance {exact}"
        );
    }
    assert!(
        inside > 100 && outside > 1000,
        "{inside} inside, {outside} outside"
    );
    // Far, huge and non-finite points sample nothing and bound nothing inside, without a panic
    // (a huge coordinate's cell index saturates).
    for p in [
        Vec3::splat(1.0e30),
        Vec3::new(center.x, center.y, 1.0e30),
        Vec3::splat(-1.0e30),
        Vec3::splat(f32::NAN),
        Vec3::new(f32::INFINITY, 0.0, 0.0),
    ] {
        assert_eq!(field.sample(p), None, "{p}");
        assert!(field.bound(p).1 >= 0.0, "{p}");
    }
}

#[test]
fn an_open_body_gets_distances_without_signs() {
    let (center, radius) = (Vec3::ZERO, 0.05);
    let mut mesh = uv_sphere(center, radius, 24, 48);
    // Drop the lower half: a bowl, open along its rim.
    let positions = mesh.positions.clone();
    mesh.triangles
        .retain(|t| t.iter().map(|&i| positions[i as usize].y).sum::<f32>() > 0.0);
    let body = CollisionBody::from_mesh(&mesh).unwrap();
    assert!(!body.is_closed());
    let field = DistanceField::of(&body, 2.0e-3);
    assert!(!field.is_signed());
    let mut rng = Rng::new(5);
    for p in points(&mut rng, center, radius, 3000) {
        let exact = body.signed_distance(p).unwrap().abs();
        let (bound, sign) = field.bound(p);
        assert!(bound <= exact + ROUNDING, "p {p}: {bound} > {exact}");
        // Unsigned: no point is certified outside or inside (an open mesh has no inside).
        assert_eq!(sign, 0.0, "p {p} got a sign");
        assert!(field.outside_clearance(p, 0.0).is_none());
    }
}

fn random_volume(rng: &mut Rng, center: Vec3, radius: f32) -> SweptSphere {
    let at = center + rng.direction() * rng.range(0.5 * radius, 1.6 * radius);
    let r = rng.range(0.0, 0.01);
    match rng.below(3) {
        0 => Pss {
            center: at,
            radius: r,
        }
        .into(),
        1 => Lss {
            start: at,
            end: at + rng.direction() * rng.range(0.0, 0.03),
            radius: r,
        }
        .into(),
        _ => {
            let u = rng.direction();
            let v = u.any_orthonormal_vector();
            Rss {
                rectangle: Rectangle {
                    center: at,
                    axes: [u, v],
                    half_extents: [rng.range(0.0, 0.02), rng.range(0.0, 0.01)],
                },
                radius: r,
            }
            .into()
        }
    }
}

/// The field clears a volume only when the exhaustive test finds no triangle it touches, and it
/// clears every one in its grid that is more than `4h√3` away: each sample's bound is within
/// `2h√3` of its distance, and its cover (half a sub-segment, half a sub-rectangle's diagonal)
/// under a cell's diagonal.
#[test]
fn a_cleared_volume_touches_no_triangle() {
    let (body, center, radius) = sphere_body();
    let field = body.distance_field();
    let mut rng = Rng::new(9);
    let (mut cleared, mut far) = (0, 0);
    for _ in 0..3000 {
        let volume = random_volume(&mut rng, center, radius);
        let gap = body
            .local_triangles()
            .iter()
            .map(|t| volume.triangle_distance(t))
            .fold(f32::MAX, f32::min);
        let touches = body
            .local_triangles()
            .iter()
            .any(|t| volume.intersects_triangle(t));
        let clears = field.clears(&volume, 1.0e-6);
        assert!(
            !(clears && touches),
            "{volume:?} cleared but touches (gap {gap})"
        );
        let (low, high) = field.grid_bounds();
        let aabb = volume.aabb(0.0);
        let in_grid = aabb.mins.cmpge(low).all() && aabb.maxs.cmple(high).all();
        if in_grid && gap > 4.0 * field.cell() * 3.0f32.sqrt() {
            far += 1;
            cleared += usize::from(clears);
        }
    }
    assert!(far > 300, "{far} far volumes");
    assert_eq!(cleared, far, "far volumes the field did not clear");
}
