//! Contacts from a body's distance field against the exact ones, on the procedural head
//! (12,096 triangles, 2 mm cells):
//!
//! - the field's interpolated signed distance against the exact closest-point distance, and its
//!   gradient against the direction to the closest point, at points within 8 mm of the scalp;
//! - the field's contacts against the exact segment–triangle distances of the paper-curly groom
//!   at every level at rest, shaken hair included: a segment clearly touching (exact separation
//!   below `−δ`) is always a field contact, a field contact is never clearly apart (above `δ`),
//!   and the field's normal agrees with the touched triangles' mean normal; and the segments
//!   of a chain, which share the samples at their common nodes, find what each finds alone.

mod support;

use glam::Vec3;
use hair_collide::{
    BroadPhase, CollisionBody, CollisionSettings, CollisionSolver, FieldContacts,
    groom_level_chains, query_body_field,
};
use hair_core::dynamics::Environment;
use hair_core::{Level, Scene};

/// How far the field's distance may be from the exact one [m], at the field's cell `h`, on a
/// mesh whose neighbouring faces turn by at most `bend` [rad]: the exact distance to a faceted
/// surface is smooth over each face and has a kink over each edge, where its slope turns by the
/// faces' angle; linear interpolation across a kink of slope change `θ` errs by at most `θh/4`
/// (the kink in the middle of the cell), so the trilinear interpolation by at most `3θh/4` (one
/// such term per axis). On a smooth patch the curvature term `3h²/(8R)` is below this for the
/// head's faces (`R ≥ edge length / θ`).
fn distance_tolerance(h: f32, bend: f32) -> f32 {
    0.75 * bend * h
}

/// The largest angle [rad] between the normals of two faces that share an edge.
fn largest_bend(mesh: &hair_core::TriangleMesh) -> f32 {
    support::mesh_edges(mesh)
        .values()
        .filter(|faces| faces.len() == 2)
        .map(|faces| support::bend_between(mesh, faces[0], faces[1]))
        .fold(0.0, f32::max)
}

fn head() -> (Scene, CollisionBody) {
    let scene = Scene::preset("paper-curly").unwrap();
    let body = CollisionBody::from_mesh(&scene.head.mesh).unwrap();
    (scene, body)
}

#[test]
fn field_distance_and_gradient_match_the_exact_ones_near_the_scalp() {
    let (scene, body) = head();
    let field = body.distance_field();
    let mesh = &scene.head.mesh;
    let (mut worst_angle, mut sampled) = (0.0f32, 0);
    let mut errors = Vec::new();
    // Points above and below every 7th vertex, along its normal, 0–7.9 mm out and 0–2 mm in.
    for (k, (&vertex, &normal)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
        if k % 7 != 0 {
            continue;
        }
        let offset = -0.002 + 0.0099 * ((k * 37 % 101) as f32 / 100.0);
        let p = vertex + normal * offset + Vec3::new(0.3, -0.7, 0.5) * 1e-3 * (k % 3) as f32;
        let exact = body.closest_local_surface_point(p).unwrap();
        let Some((distance, gradient)) = field.sample(p) else {
            panic!("{p} ({offset} m off the surface) is not in an exact cell");
        };
        errors.push((distance - exact.signed_distance).abs());
        if exact.signed_distance.abs() > 5e-4 {
            // Away from the surface the gradient points from the closest point.
            let direction = (p - exact.point).normalize() * exact.signed_distance.signum();
            let angle = gradient.normalize().dot(direction).clamp(-1.0, 1.0).acos();
            worst_angle = worst_angle.max(angle);
        }
        sampled += 1;
    }
    errors.sort_by(f32::total_cmp);
    let (median, worst) = (errors[errors.len() / 2], errors[errors.len() - 1]);
    let h = field.cell();
    let bend = largest_bend(mesh);
    let bound = distance_tolerance(h, bend);
    println!(
        "{sampled} points, cells of {:.3} mm, faces turning by up to {:.1}°: distance error \
         median {:.2} µm, largest {:.2} µm (bound {:.2} µm); largest gradient angle {:.2}°",
        h * 1e3,
        bend.to_degrees(),
        median * 1e6,
        worst * 1e6,
        bound * 1e6,
        worst_angle.to_degrees()
    );
    assert!(sampled > 500);
    assert!(worst <= bound, "distance error {worst} m");
    // Most points lie over the smooth scalp, far from the sharpest edges: a tenth of the bound.
    assert!(median <= 0.1 * bound, "median distance error {median} m");
    // The gradient of the interpolation: within the faces' largest bend and a half of the true
    // direction (the cell's gradient averages the faces' across a kink).
    assert!(worst_angle <= 1.5 * bend, "{}°", worst_angle.to_degrees());
}

#[test]
fn field_contacts_match_the_exact_contacts_of_the_paper_groom() {
    let (scene, mut body) = head();
    let groom = &scene.groom;
    let simulation = support::groom_simulation(groom);
    let environment = Environment::default();
    let mut state = simulation.rest_state(&environment, 0.0);
    let triangles = body.local_triangles().to_vec();
    let mut solver = CollisionSolver::new(CollisionSettings {
        broad_phase: BroadPhase::FieldContacts,
        ..CollisionSettings::default()
    })
    .unwrap();
    let mut found = FieldContacts::new();
    for level in Level::ALL {
        solver
            .set_chains(&simulation, &groom_level_chains(groom, level))
            .unwrap();
        solver
            .before_step(
                std::slice::from_mut(&mut body),
                &simulation,
                &mut state,
                &environment,
            )
            .unwrap();
        let volumes = solver.hierarchy().unwrap().volumes();
        // A segment that starts where the one before it ended takes that sample as its start:
        // with a rigid body's field, whose samples do not depend on where a search began, the
        // contacts are those of each segment queried alone, bit for bit (the first 1,500).
        let some = &volumes[..volumes.len().min(1500)];
        query_body_field(some, &body, &mut found);
        let mut alone = FieldContacts::new();
        let mut one_by_one = Vec::new();
        for (segment, volume) in some.iter().enumerate() {
            query_body_field(std::slice::from_ref(volume), &body, &mut alone);
            one_by_one.extend(alone.contacts.iter().map(|&(_, n)| (segment as u32, n)));
        }
        assert_eq!(one_by_one, found.contacts, "{level:?}");
        assert!(!one_by_one.is_empty(), "{level:?}: no contact to compare");
        query_body_field(volumes, &body, &mut found);
        // The samples' error: s²/(8R) for samples s apart on a surface of radius R, with the
        // longest segment's half (strand groups and clusters) or the patch's half width.
        let longest = volumes
            .iter()
            .map(|v| v.aabb(0.0).extents().max_element())
            .fold(0.0f32, f32::max);
        let delta =
            distance_tolerance(body.distance_field().cell(), largest_bend(&scene.head.mesh))
                + (0.5 * longest).powi(2) / (8.0 * 0.03);
        let (mut touching, mut agreeing, mut normals_close) = (0, 0, 0);
        let mut field = found.contacts.iter().peekable();
        for (segment, volume) in volumes.iter().enumerate() {
            let contact = field.next_if(|(s, _)| *s as usize == segment).map(|c| c.1);
            // Exact separation and the touched triangles' mean normal.
            let mut separation = f32::INFINITY;
            let mut normal = Vec3::ZERO;
            for t in &triangles {
                let d = volume.triangle_distance(t);
                separation = separation.min(d);
                if d <= 0.0 {
                    normal += t.normal;
                }
            }
            if separation < -delta {
                assert!(
                    contact.is_some(),
                    "{level:?} segment {segment}: {:.3} mm inside its radius, no field contact",
                    -separation * 1e3
                );
            }
            if let Some(n) = contact {
                assert!(
                    separation <= delta,
                    "{level:?} segment {segment}: a field contact {:.3} mm clear of the head",
                    separation * 1e3
                );
                if let Some(exact) = normal.try_normalize() {
                    agreeing += 1;
                    if n.dot(exact) > 30f32.to_radians().cos() {
                        normals_close += 1;
                    }
                }
            }
            touching += usize::from(separation <= 0.0);
        }
        println!(
            "{level:?}: {} field contacts, {touching} exact, δ = {:.3} mm, {} exact fallbacks, \
             normals within 30° in {normals_close} of {agreeing}",
            found.contacts.len(),
            delta * 1e3,
            found.exact_fallbacks
        );
        assert!(touching > 50, "{level:?}: the rest pose touches the scalp");
        // The touched triangles' mean normal and the field's gradient describe the same
        // surface; they part where a volume touches across a fold (a few segments).
        assert!(
            normals_close as f64 >= 0.9 * agreeing as f64,
            "{level:?}: normals within 30° in only {normals_close} of {agreeing}"
        );
    }
}
