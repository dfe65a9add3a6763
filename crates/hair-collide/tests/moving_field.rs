//! A deforming body's field, its rest mesh's read through the deformation
//! (`hair_collide::RestField`), against the exact distances to the deformed mesh: the
//! procedural head (12,096 triangles, 2 mm cells) squashed and stretched, bulged, turned by
//! 20° and moved.
//!
//! - Near the surface, the moved field's distance is the exact closest-point distance to the
//!   deformed mesh within the stretch's share of the distance plus the rest field's own
//!   interpolation error, and its gradient points along the exact normal.
//! - Everywhere around the head, its certified bound never exceeds the exact distance and its
//!   sign is the exact one.
//! - A rigid motion alone is read with no deviation, as exactly as the rest field itself.
//! - A squash and stretch alone (affine) is read through its affine fit: its certified bounds
//!   stay as tight as the rest field's, where the rigid fit's deviation would loosen them.
//! - A body whose mesh is not the rest mesh is refused.

mod support;

use glam::{Quat, Vec3};
use hair_collide::{CollisionBody, RestField};
use hair_core::{Head, HeadParams, TriangleMesh};
use support::Rng;

/// The largest stretch of the deformation below, in the plane of the surface: 8 % up, and the
/// bulge's slope (1 cm · 20 /m = 0.2, so a stretch of √(1 + 0.2²) − 1 = 2 % across it); 10 %
/// in all.
const STRETCH: f32 = 0.10;

/// The rest field's interpolation error [m] near a surface whose faces turn by up to `bend`
/// [rad]: `3θh/4` at cells of `h` = 2 mm (as `tests/field_contacts.rs` derives it).
fn interpolation(bend: f32) -> f32 {
    0.75 * bend * 2.0e-3
}

/// Per triangle of `mesh`, the largest angle [rad] between the normals of two faces that share
/// an edge among the triangles around it (sharing a vertex with it): how sharply the surface
/// turns where a point's closest point lies on it.
fn bends_around(mesh: &TriangleMesh) -> Vec<f32> {
    let edges = support::mesh_edges(mesh);
    let mut at_vertex = vec![0.0f32; mesh.positions.len()];
    for (&(a, b), faces) in &edges {
        if let [f, g] = faces[..] {
            let bend = support::bend_between(mesh, f, g);
            for v in [a, b] {
                at_vertex[v as usize] = at_vertex[v as usize].max(bend);
            }
        }
    }
    // A triangle's neighbourhood: its vertices' edges, and the edges of the triangles on them.
    let mut around = vec![0.0f32; mesh.positions.len()];
    for tri in &mesh.triangles {
        let most = tri
            .iter()
            .map(|&v| at_vertex[v as usize])
            .fold(0.0, f32::max);
        for &v in tri {
            around[v as usize] = around[v as usize].max(most);
        }
    }
    mesh.triangles
        .iter()
        .map(|tri| tri.iter().map(|&v| around[v as usize]).fold(0.0, f32::max))
        .collect()
}

/// The head at rest.
fn rest_mesh() -> TriangleMesh {
    Head::procedural(&HeadParams::default()).unwrap().mesh
}

/// A squash and stretch with a bulge (`body_deform.rs`'s), then a 20° turn about x and a move.
fn deform(p: Vec3, turn: bool) -> Vec3 {
    let stretched =
        Vec3::new(p.x * 0.96, p.y * 1.08, p.z * 0.97) + Vec3::Z * 0.01 * (p.y * 20.0).sin();
    let (rotation, translation) = if turn {
        (Quat::from_rotation_x(0.35), Vec3::new(0.01, -0.02, 0.005))
    } else {
        (Quat::IDENTITY, Vec3::ZERO)
    };
    rotation * stretched + translation
}

/// The rest body, its field, and the body at `positions` reading it.
fn moved_body(rest: &TriangleMesh, positions: &[Vec3]) -> (RestField, CollisionBody) {
    let rest_body = CollisionBody::from_mesh(rest).unwrap();
    let field = RestField::of(&rest_body);
    let velocities = vec![Vec3::ZERO; positions.len()];
    // The first instant built from the mesh, the next one refitted from it: both read the field.
    let first = CollisionBody::from_moving_mesh(rest, velocities.clone())
        .unwrap()
        .reading_rest_field(&field)
        .unwrap();
    let body = first.deformed(positions, velocities).unwrap();
    (field, body)
}

/// Points near the deformed surface: a random point of a random triangle, moved along its
/// normal by −2 … 12 mm.
fn points_near(mesh: &TriangleMesh, count: usize) -> Vec<Vec3> {
    let mut random = Rng::new(7);
    (0..count)
        .map(|_| {
            let t = ((random.unit() * mesh.triangles.len() as f32) as usize)
                .min(mesh.triangles.len() - 1);
            let [a, b, c] = mesh.triangles[t].map(|i| mesh.positions[i as usize]);
            let (mut u, mut v) = (random.unit(), random.unit());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let normal = (b - a).cross(c - a).normalize();
            a + (b - a) * u + (c - a) * v + normal * (-0.002 + 0.014 * random.unit())
        })
        .collect()
}

#[test]
fn near_the_surface_the_moved_field_is_the_deformed_meshs_distance() {
    let rest = rest_mesh();
    let mut deformed = rest.clone();
    for p in &mut deformed.positions {
        *p = deform(*p, true);
    }
    let (_, body) = moved_body(&rest, &deformed.positions);
    // Where each point's closest point lies, how sharply the faces turn there, at rest and
    // deformed (the rest field's interpolation error, and the deformed surface's own kinks).
    let bends: Vec<f32> = bends_around(&rest)
        .into_iter()
        .zip(bends_around(&deformed))
        .map(|(a, b)| a.max(b))
        .collect();
    let mut worst_bend = 0.0f32;
    let deviation = body.deviation_from_rest().unwrap();
    // The stretch moves vertices by up to 8 % of the head's 12 cm half-height, and the fit
    // takes the turn and the move out.
    assert!(
        deviation > 0.002 && deviation < 0.02,
        "deviation {deviation}"
    );
    let (mut sampled, mut worst, mut worst_angle) = (0, 0.0f32, 0.0f32);
    for p in points_near(&deformed, 4000) {
        let exact = body.closest_local_surface_point(p).unwrap();
        let Some((distance, gradient)) = body.local_field_sample(p) else {
            continue;
        };
        sampled += 1;
        let error = (distance - exact.signed_distance).abs();
        let bend = bends[exact.triangle as usize];
        let allowed = STRETCH * exact.signed_distance.abs() + interpolation(bend);
        assert!(
            error <= allowed,
            "at {p}: moved field {distance}, exact {}, allowed {allowed}",
            exact.signed_distance
        );
        worst = worst.max(error);
        if exact.signed_distance.abs() > 0.001 {
            // The exact gradient is the unit direction from the closest point.
            let direction = (p - exact.point) * exact.signed_distance.signum();
            let angle = gradient
                .normalize()
                .dot(direction.normalize())
                .clamp(-1.0, 1.0)
                .acos();
            // Within the stretch's shear (atan 0.1 ≈ 0.1 rad) and the faces' turn there (across
            // an edge the exact direction turns by up to that much, where the interpolated one
            // turns smoothly) of the exact direction.
            assert!(
                angle <= STRETCH + bend,
                "at {p}: gradient {angle} rad off, faces turn by {bend}"
            );
            worst_angle = worst_angle.max(angle);
            worst_bend = worst_bend.max(bend);
        }
    }
    // Every point within the moving reach (16 mm, less the stretch) samples.
    assert!(sampled > 3900, "{sampled} of 4000 sampled");
    eprintln!(
        "worst distance error {worst} m, worst angle {worst_angle} rad (faces turning by up to \
         {worst_bend}), {sampled} samples"
    );
}

#[test]
fn the_certified_bound_holds_around_the_deformed_head() {
    let rest = rest_mesh();
    let mut deformed = rest.clone();
    for p in &mut deformed.positions {
        *p = deform(*p, true);
    }
    let (_, body) = moved_body(&rest, &deformed.positions);
    let (low, high) = deformed.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(l, h), p| (l.min(*p), h.max(*p)),
    );
    let mut random = Rng::new(11);
    let (mut certified, mut inside) = (0, 0);
    for _ in 0..3000 {
        let t = Vec3::new(random.unit(), random.unit(), random.unit());
        let p = low - Vec3::splat(0.05) + (high - low + Vec3::splat(0.1)) * t;
        let exact = body.closest_local_surface_point(p).unwrap();
        let (bound, sign) = body.local_field_bound(p);
        assert!(
            bound <= exact.signed_distance.abs() + 1e-6,
            "at {p}: bound {bound} above the distance {}",
            exact.signed_distance
        );
        if bound > 0.0 {
            certified += 1;
            assert_eq!(sign, exact.signed_distance.signum(), "at {p}");
            if sign < 0.0 {
                inside += 1;
            }
        }
    }
    assert!(
        certified > 1500 && inside > 50,
        "{certified} certified, {inside} inside"
    );
}

#[test]
fn an_affine_squash_and_stretch_keeps_the_bounds_tight() {
    let rest = rest_mesh();
    // No bulge: the squash and stretch (8 % up, 4 and 3 % in), turned and moved.
    let affine = |p: Vec3| {
        Quat::from_rotation_x(0.35) * Vec3::new(p.x * 0.96, p.y * 1.08, p.z * 0.97)
            + Vec3::new(0.01, -0.02, 0.005)
    };
    let mut moved = rest.clone();
    for p in &mut moved.positions {
        *p = affine(*p);
    }
    let (_, body) = moved_body(&rest, &moved.positions);
    // The rigid fit cannot take a stretch out: its vertices stray by millimetres.
    let rigid = body.deviation_from_rest().unwrap();
    assert!(rigid > 0.003, "rigid deviation {rigid}");
    let mut random = Rng::new(5);
    let (mut slack, mut count) = (0.0f32, 0);
    for p in points_near(&moved, 2000) {
        // 2 to 14 mm out: where the bound is read.
        let p = p + p.normalize() * 0.004 * random.unit();
        let exact = body.closest_local_surface_point(p).unwrap().signed_distance;
        let (bound, sign) = body.local_field_bound(p);
        assert!(
            bound <= exact.abs() + 1e-6,
            "at {p}: bound {bound}, exact {exact}"
        );
        if bound > 0.0 {
            assert_eq!(sign, exact.signum(), "at {p}");
        }
        if exact > 0.002 {
            slack += exact - bound;
            count += 1;
        }
    }
    let mean = slack / count as f32;
    eprintln!("mean slack {mean} m over {count} points; rigid deviation {rigid} m");
    // Through the affine fit the slack is the rest field's own (its corners' `h√3` at most, a
    // few per cent of the distance from the least stretch, 0.96); through the rigid fit it
    // would be at least the rigid deviation.
    assert!(
        count > 1000 && mean < 0.5 * rigid,
        "mean slack {mean} m of {count}, rigid deviation {rigid} m"
    );
}

#[test]
fn a_rigid_motion_is_read_as_exactly_as_the_rest_field() {
    let rest = rest_mesh();
    let turned: Vec<Vec3> = rest
        .positions
        .iter()
        .map(|p| Quat::from_rotation_x(0.35) * *p + Vec3::new(0.01, -0.02, 0.005))
        .collect();
    let (_, body) = moved_body(&rest, &turned);
    let deviation = body.deviation_from_rest().unwrap();
    assert!(deviation < 2e-6, "deviation {deviation}");
    let mut moved = rest.clone();
    moved.positions = turned;
    let bends = bends_around(&rest);
    for p in points_near(&moved, 1000) {
        let closest = body.closest_local_surface_point(p).unwrap();
        let exact = closest.signed_distance;
        let (distance, _) = body.local_field_sample(p).unwrap();
        // The rest field's error alone, plus the f32 rounding of the turn at 20 cm.
        assert!(
            (distance - exact).abs() <= interpolation(bends[closest.triangle as usize]) + 1e-6,
            "at {p}: {distance} against {exact}"
        );
    }
}

#[test]
fn a_body_of_another_mesh_is_refused() {
    let rest = rest_mesh();
    let rest_body = CollisionBody::from_mesh(&rest).unwrap();
    let field = RestField::of(&rest_body);
    let mut other = rest.clone();
    other.triangles.swap(0, 1);
    let body =
        CollisionBody::from_moving_mesh(&other, vec![Vec3::ZERO; other.positions.len()]).unwrap();
    let error = body.reading_rest_field(&field).unwrap_err().to_string();
    assert!(error.contains("rest field"), "{error}");
}

/// Occluder boxes on a head turned by 20° and moved (a body file's nod, baked into its points):
/// the carried boxes follow the turn, every point of a 5 × 5 × 5 grid over each lies inside the
/// turned head (exact signed distances), and none is shrunk away; the rest boxes left where
/// they were would poke out of it.
#[test]
fn occluder_boxes_follow_a_turned_head() {
    let head = Head::procedural(&HeadParams::default()).unwrap();
    let rest = head.mesh.clone();
    let turned: Vec<Vec3> = rest
        .positions
        .iter()
        .map(|p| Quat::from_rotation_x(0.35) * *p + Vec3::new(0.01, -0.02, 0.005))
        .collect();
    let (field, body) = moved_body(&rest, &turned);
    let boxes = head.occluder_boxes();
    let mut carried = Vec::new();
    assert!(body.carried_occluders(&field.boxes(&boxes), &mut carried));
    assert_eq!(carried.len(), boxes.len());
    let grid = |(low, high): (Vec3, Vec3)| {
        (0..125).map(move |i| {
            let t = Vec3::new((i % 5) as f32, ((i / 5) % 5) as f32, (i / 25) as f32) / 4.0;
            low + (high - low) * t
        })
    };
    let depth = |p: Vec3| body.closest_local_surface_point(p).unwrap().signed_distance;
    for p in carried.iter().flat_map(|&b| grid(b)) {
        assert!(
            depth(p) < 0.0,
            "{p} of a carried box is outside the turned head"
        );
    }
    let outside = boxes
        .iter()
        .flat_map(|&b| grid(b))
        .filter(|&p| depth(p) > 0.0)
        .count();
    assert!(
        outside > 0,
        "the rest boxes stay inside the turned head: the test tests nothing"
    );
}
