//! The two broad phases that visit triangles are one method at two costs: the curly groom at mixed levels (every
//! volume kind) on the procedural head shaking at 6 rad/s, stepped with the distance field and
//! with the paper's hierarchies, gives the same contacts, the same projections and the same
//! state, bit for bit, at every step.

mod support;

use hair_collide::{BroadPhase, CollisionBody, CollisionSettings, CollisionSolver};
use hair_core::Scene;
use hair_core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, HeadMotion, IntegratorKind, Simulation,
    SimulationSettings,
};
use support::mixed_levels;

#[test]
fn the_distance_field_and_the_hierarchies_step_the_same_state() {
    let scene = Scene::preset("curly").unwrap();
    let groom = &scene.groom;
    let (rest, chains) = mixed_levels(groom);
    let model = DynamicsModel::new(rest, DynamicsParams::for_style(&groom.params.style)).unwrap();
    let settings = SimulationSettings::recommended(IntegratorKind::PositionBased);
    let environment = Environment {
        head: HeadMotion::shake(0.6, 6.0),
        ..Environment::default()
    };
    let body = CollisionBody::from_mesh(&scene.head.mesh).unwrap();
    let mut runs = [BroadPhase::Hierarchies, BroadPhase::DistanceField].map(|broad_phase| {
        let simulation = Simulation::new(model.clone(), settings).unwrap();
        let state = simulation.rest_state(&environment, 0.0);
        let mut solver = CollisionSolver::new(CollisionSettings {
            broad_phase,
            ..CollisionSettings::default()
        })
        .unwrap();
        solver.set_chains(&simulation, &chains).unwrap();
        (simulation, state, solver, body.clone())
    });
    let (mut contacts, mut projected) = (0, 0);
    // Half a second: the shake's first swing drives the hair into the head.
    for step in 0..30 {
        let reports = runs.each_mut().map(|(simulation, state, solver, body)| {
            solver
                .step(std::slice::from_mut(body), simulation, state, &environment)
                .unwrap()
        });
        assert_eq!(reports[0].contacts, reports[1].contacts, "step {step}");
        assert_eq!(reports[0].projection, reports[1].projection, "step {step}");
        let [(_, a, ..), (_, b, ..)] = &runs;
        assert_eq!(a.node_positions, b.node_positions, "step {step}");
        assert_eq!(a.node_velocities, b.node_velocities, "step {step}");
        contacts += reports[0].contacts.contact_pairs;
        projected += reports[0].projection.projected_nodes;
    }
    // The run must touch and project, or it compares nothing.
    assert!(
        contacts > 0 && projected > 0,
        "{contacts} contacts, {projected} projections"
    );
}
