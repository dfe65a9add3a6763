//! The paper's benchmark groom (paper-curly: 91 sections, 37,765 strands) on the procedural head
//! (12,096 triangles): the BVH query returns exactly the brute-force contact set at every level
//! (patches: RSS; clusters: LSS around 8 control points; strand groups: LSS of the group's
//! radius), at rest and after the head has shaken the hair, and so do the per-volume query
//! through the head's tree and the query through the head's distance field; the hierarchy is refitted from the
//! node positions each step and rebuilt only when the layout (a section's level) changes.

mod support;

use hair_collide::{
    CollisionBody, CollisionSettings, CollisionSolver, HairHairSettings, SegmentContacts,
    groom_active_chains, groom_level_chains, query_body, query_body_brute_force, query_body_near,
    query_body_volumes,
};
use hair_core::dynamics::{Environment, HeadMotion};
use hair_core::{Level, Scene};

fn assert_bvh_equals_brute_force(
    solver: &CollisionSolver,
    body: &CollisionBody,
    what: &str,
) -> usize {
    let hair = solver.hierarchy().expect("built by before_step");
    let (mut fast, mut slow) = (SegmentContacts::new(), SegmentContacts::new());
    query_body(hair, body, &mut fast);
    query_body_brute_force(hair, body, &mut slow);
    assert_eq!(fast, slow, "{what}: BVH and brute force disagree");
    let mut volumes = SegmentContacts::new();
    query_body_volumes(hair.volumes(), body, &mut volumes);
    assert_eq!(
        volumes, slow,
        "{what}: the per-volume query and brute force disagree"
    );
    let mut near = SegmentContacts::new();
    query_body_near(hair.volumes(), body, &mut near);
    assert_eq!(
        near, slow,
        "{what}: the distance field and brute force disagree"
    );
    fast.pair_count()
}

#[test]
fn paper_curly_bvh_equals_brute_force_at_every_level_and_after_motion() {
    let scene = Scene::preset("paper-curly").unwrap();
    let groom = &scene.groom;
    let mut simulation = support::groom_simulation(groom);
    let environment = Environment {
        head: HeadMotion::shake(0.6, 6.0),
        ..Environment::default()
    };
    let mut state = simulation.rest_state(&environment, 0.0);
    let mut body = CollisionBody::from_mesh(&scene.head.mesh).unwrap();
    // Hair–hair contact on, so that the solver refits the hair's tree every step and the
    // simultaneous descent of both trees is checked on moved hair too.
    let mut solver = CollisionSolver::new(CollisionSettings {
        hair_hair: Some(HairHairSettings::default()),
        ..CollisionSettings::default()
    })
    .unwrap();

    // Each level at rest: a new layout, so a rebuild.
    for (k, level) in Level::ALL.into_iter().enumerate() {
        let chains = groom_level_chains(groom, level);
        solver.set_chains(&simulation, &chains).unwrap();
        let report = solver
            .before_step(
                std::slice::from_mut(&mut body),
                &simulation,
                &mut state,
                &environment,
            )
            .unwrap();
        assert!(report.rebuilt);
        assert_eq!(solver.rebuild_count(), k as u64 + 1);
        let pairs = assert_bvh_equals_brute_force(&solver, &body, level.name());
        assert!(pairs > 0, "{level:?}: the roots touch the scalp");
        println!("{}: {} segments, {pairs} contact pairs", level.name(), {
            solver.hierarchy().unwrap().segment_count()
        });
    }

    // Mixed levels, stepped while the head shakes: refit only, then one rebuild on a change.
    let mut levels: Vec<Level> = (0..groom.section_count())
        .map(|s| Level::ALL[s % 3])
        .collect();
    let mut chains = Vec::new();
    groom_active_chains(groom, &levels, &mut chains).unwrap();
    solver.set_chains(&simulation, &chains).unwrap();
    let before = solver.rebuild_count();
    for step in 0..4 {
        if step == 2 {
            levels[0] = Level::StrandGroup;
            groom_active_chains(groom, &levels, &mut chains).unwrap();
            solver.set_chains(&simulation, &chains).unwrap();
        }
        let report = solver
            .step(
                std::slice::from_mut(&mut body),
                &mut simulation,
                &mut state,
                &environment,
            )
            .unwrap();
        assert_eq!(
            report.contacts.rebuilt,
            step == 0 || step == 2,
            "step {step}"
        );
        // The hierarchy as the solver left it after `step`'s refit (moved hair) or rebuild.
        if step > 0 {
            assert_bvh_equals_brute_force(&solver, &body, &format!("mixed levels, step {step}"));
        }
    }
    assert_eq!(solver.rebuild_count(), before + 2);
    // Setting the same layout again is not a change.
    solver.set_chains(&simulation, &chains).unwrap();
    let report = solver
        .before_step(
            std::slice::from_mut(&mut body),
            &simulation,
            &mut state,
            &environment,
        )
        .unwrap();
    assert!(!report.rebuilt);
}
