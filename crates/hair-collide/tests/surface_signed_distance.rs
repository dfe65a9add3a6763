//! Signed distance to a body: against the closed form on a sphere mesh (|p − c| − R, within the
//! tessellation's sagitta) and against parry3d's pseudonormal-oriented `TriMesh` on the procedural
//! head, posed anywhere. The procedural head is checked to be closed and consistently wound.

mod support;

use glam::{Quat, Vec3};
use hair_collide::CollisionBody;
use hair_core::{HeadParams, head::Head};
use support::{ParrySignedDistance, Rng, uv_sphere};

#[test]
fn sphere_signed_distance_matches_the_closed_form() {
    let (center, radius) = (Vec3::new(0.1, -0.2, 0.05), 0.1);
    let (rings, sectors) = (48, 96);
    let mesh = uv_sphere(center, radius, rings, sectors);
    let body = CollisionBody::from_mesh(&mesh).unwrap();
    assert!(body.is_closed());
    // The mesh lies between the sphere and the sphere shrunk by the sagitta of its largest
    // edge's arc: R(1 − cos(π/rings)) ≥ R(1 − cos(π/sectors)) (equal angular steps).
    let sagitta = radius * (1.0 - (std::f32::consts::PI / rings as f32).cos());
    let mut rng = Rng::new(7);
    for _ in 0..4000 {
        let p = center + rng.direction() * rng.range(0.0, 2.0 * radius);
        let exact = p.distance(center) - radius;
        let computed = body.signed_distance(p).unwrap();
        // f32 rounding at 0.3 m: a few ulps.
        assert!(
            computed >= exact - 1e-6 && computed <= exact + sagitta + 1e-6,
            "p {p}: {computed} vs closed form {exact} (sagitta {sagitta})"
        );
    }
}

#[test]
fn head_signed_distance_matches_parry_in_any_pose() {
    let head = Head::procedural(&HeadParams::default()).unwrap();
    let mut body = CollisionBody::from_mesh(&head.mesh).unwrap();
    assert!(
        body.is_closed(),
        "the procedural head must be a closed, consistently wound mesh"
    );
    let reference = ParrySignedDistance::new(&head.mesh);
    let (low, high) = head.mesh.bounds().unwrap();
    let mut rng = Rng::new(11);
    let mut inside = 0;
    for pose in 0..3 {
        let rotation = if pose == 0 {
            Quat::IDENTITY
        } else {
            rng.rotation()
        };
        let translation = rng.vec3(0.3);
        body.set_pose(rotation, translation).unwrap();
        for _ in 0..1500 {
            let local = low - Vec3::splat(0.03)
                + (high - low + Vec3::splat(0.06)) * Vec3::new(rng.unit(), rng.unit(), rng.unit());
            let world = rotation * local + translation;
            let expected = reference.at(local);
            let computed = body.signed_distance(world).unwrap();
            // Same closest point up to the pose's rounding (a few ulps of 0.5 m).
            assert!(
                (computed - expected).abs() < 2e-6,
                "local {local}: {computed} vs parry {expected}"
            );
            inside += usize::from(expected < 0.0);
        }
    }
    assert!(
        inside > 500,
        "the sample must probe the inside too ({inside})"
    );
    assert_eq!(body.signed_distance(Vec3::NAN), None);
}
