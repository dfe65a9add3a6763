//! The collision stage gives the same state whatever the thread count: the volumes, node frames
//! and control points, the contact query and the projection's first pass run side by side over
//! blocks of chains, and the projection's walk along the chains that need it runs in chain order.
//! The curly groom at mixed levels (every volume kind) in a 6 rad/s shake for 0.5 s, so that
//! hair is driven into the head and projected, stepped in pools of 1, 2 and 3 threads: the node
//! positions and velocities must agree bit for bit.

mod support;

use glam::Vec3;
use hair_collide::{CollisionBody, CollisionSettings, CollisionSolver};
use hair_core::Scene;
use hair_core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, HeadMotion, IntegratorKind, Simulation,
    SimulationSettings,
};
use support::mixed_levels;

/// Steps of the run (0.5 s at 60 Hz).
const STEPS: usize = 30;

/// The final positions and velocities, and the projections made, in a pool of `threads`.
fn run(threads: usize) -> (Vec<Vec3>, Vec<Vec3>, usize) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let scene = Scene::preset("curly").unwrap();
        let groom = &scene.groom;
        let (rest, chains) = mixed_levels(groom);
        let model =
            DynamicsModel::new(rest, DynamicsParams::for_style(&groom.params.style)).unwrap();
        let settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
        let mut simulation = Simulation::new(model, settings).unwrap();
        let environment = Environment {
            head: HeadMotion::shake(0.6, 6.0),
            ..Environment::default()
        };
        let mut state = simulation.rest_state(&environment, 0.0);
        let mut body = CollisionBody::from_mesh(&scene.head.mesh).unwrap();
        let mut solver = CollisionSolver::new(CollisionSettings::default()).unwrap();
        solver.set_chains(&simulation, &chains).unwrap();
        let mut projected = 0;
        for _ in 0..STEPS {
            let report = solver
                .step(
                    std::slice::from_mut(&mut body),
                    &mut simulation,
                    &mut state,
                    &environment,
                )
                .unwrap();
            projected += report.projection.projected_nodes;
        }
        (state.node_positions, state.node_velocities, projected)
    })
}

#[test]
fn collision_results_do_not_depend_on_the_thread_count() {
    let (positions, velocities, projected) = run(1);
    // The shake must drive hair into the head, or the walk along the chains is not exercised.
    assert!(projected > 0, "no node was projected");
    for threads in [2, 3] {
        let (other_positions, other_velocities, other_projected) = run(threads);
        assert_eq!(projected, other_projected, "{threads} threads");
        let same = |a: &[Vec3], b: &[Vec3]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_array() == y.to_array())
        };
        assert!(same(&positions, &other_positions), "{threads} threads");
        assert!(same(&velocities, &other_velocities), "{threads} threads");
    }
}
