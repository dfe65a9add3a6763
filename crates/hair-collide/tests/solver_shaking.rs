//! The positional guarantee under a head shaking at 6 rad/s: the curly groom at mixed levels
//! (section `s` at level `s mod 3`, as the LOD may leave it, so every volume kind is in play),
//! 5 s at each integrator's recommended settings. After every step
//! no node (attached roots aside) is deeper inside the head than `PENETRATION_TOLERANCE`,
//! measured with parry3d's oriented `TriMesh` (independent of the solver's own signed distance)
//! in the head's frame.

mod support;

use hair_collide::{CollisionBody, CollisionSettings, CollisionSolver, PENETRATION_TOLERANCE};
use hair_core::Scene;
use hair_core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, HeadMotion, IntegratorKind, Simulation,
    SimulationSettings,
};
use support::{ParrySignedDistance, mixed_levels};

/// Peak angular speed of the shake [rad/s] and its amplitude [rad] (≈ 1.6 Hz).
const PEAK_SPEED: f32 = 6.0;
const AMPLITUDE: f32 = 0.6;
const SECONDS: f32 = 5.0;
/// The reference check runs every `CHECK_EVERY` steps (it costs more than the solver).
const CHECK_EVERY: usize = 5;

/// The largest relative length error `|ℓ − ℓ₀| / ℓ₀` over every segment (brute force).
fn largest_stretch(simulation: &Simulation, positions: &[glam::Vec3]) -> f32 {
    let rest = &simulation.model().rest;
    (0..rest.chain_count())
        .flat_map(|c| rest.nodes(c).skip(1))
        .map(|m| {
            let length = positions[m].distance(positions[m - 1]);
            let rest_length = rest.segment_rest_lengths[m];
            (length - rest_length).abs() / rest_length
        })
        .fold(0.0, f32::max)
}

fn run(kind: IntegratorKind) {
    let scene = Scene::preset("curly").unwrap();
    let groom = &scene.groom;
    let (rest, chains) = mixed_levels(groom);
    let model = DynamicsModel::new(rest, DynamicsParams::for_style(&groom.params.style)).unwrap();
    let settings = SimulationSettings::recommended(kind);
    let mut simulation = Simulation::new(model, settings).unwrap();
    let environment = Environment {
        head: HeadMotion::shake(AMPLITUDE, PEAK_SPEED),
        ..Environment::default()
    };
    let mut state = simulation.rest_state(&environment, 0.0);
    let mut body = CollisionBody::from_mesh(&scene.head.mesh).unwrap();
    let mut solver = CollisionSolver::new(CollisionSettings::default()).unwrap();
    solver.set_chains(&simulation, &chains).unwrap();
    let reference = ParrySignedDistance::new(&scene.head.mesh);
    let rest = &simulation.model().rest;
    let roots: Vec<usize> = (0..rest.chain_count())
        .map(|c| rest.nodes(c).start)
        .collect();
    let steps = (SECONDS / settings.time_step).round() as usize;
    let (mut projected, mut deepest_before, mut contacts) = (0usize, 0.0f32, 0usize);
    let mut deepest_after = f32::NEG_INFINITY;
    let (mut worst_stretch, mut worst_brute) = (0.0f32, 0.0f32);
    let started = std::time::Instant::now();
    for step in 0..steps {
        let report = solver
            .step(
                std::slice::from_mut(&mut body),
                &mut simulation,
                &mut state,
                &environment,
            )
            .unwrap();
        projected += report.projection.projected_nodes;
        // The reported stretch is a real segment's, never above the largest over all segments;
        // and every stretch past the integrators' own length error (they keep lengths within
        // 1e-5; 1e-4 allowed) is one the projection made and reports.
        let brute = largest_stretch(&simulation, &state.node_positions);
        assert!(
            report.projection.max_stretch <= brute + 1e-6,
            "{kind}: reported stretch {} above the largest segment's {brute}",
            report.projection.max_stretch
        );
        assert!(
            brute <= report.projection.max_stretch.max(1e-4) + 1e-6,
            "{kind}: a segment is {brute} off its length, the projection reported {}",
            report.projection.max_stretch
        );
        worst_stretch = worst_stretch.max(report.projection.max_stretch);
        worst_brute = worst_brute.max(brute);
        deepest_before = deepest_before.max(report.projection.max_depth);
        contacts += report.contacts.contact_segments;
        if step % CHECK_EVERY == CHECK_EVERY - 1 || step + 1 == steps {
            let to_head = environment.head.transform_at(state.time).inverse();
            let mut is_root = roots.iter().peekable();
            for (node, &p) in state.node_positions.iter().enumerate() {
                if is_root.peek() == Some(&&node) {
                    is_root.next();
                    continue;
                }
                let depth = -reference.at(to_head.transform_point(p));
                deepest_after = deepest_after.max(depth);
                assert!(
                    depth <= PENETRATION_TOLERANCE,
                    "{kind}: node {node} is {depth} m inside the head at t = {:.3} s",
                    state.time
                );
            }
        }
    }
    assert_eq!(solver.rebuild_count(), 1, "same layout: refit only");
    println!(
        "{kind}: {steps} steps in {:.2} s; {contacts} segment contacts, {projected} projections \
         (deepest {:.2} mm before projection, {:.4} mm after); largest stretch {:.2e} reported, \
         {:.2e} over all segments",
        started.elapsed().as_secs_f32(),
        deepest_before * 1e3,
        deepest_after.max(0.0) * 1e3,
        worst_stretch,
        worst_brute
    );
    // The shake must actually drive hair into the head, or the test proves nothing.
    assert!(contacts > 0 && projected > 0);
    // Length and collision together: where projecting a node out would stretch its segment,
    // the projection turns the segment about its parent instead, so every segment keeps its
    // length within 0.1 % (the dynamics' own promise) after the projection too. (Before, the
    // position won: position-based stretched segments by 25.6 % in this test.)
    assert!(
        worst_brute <= 1e-3,
        "{kind}: a segment is {worst_brute} off its length after the projection"
    );
}

#[test]
fn shaking_semi_implicit_euler_stays_out_of_the_head() {
    run(IntegratorKind::SemiImplicitEuler);
}

#[test]
fn shaking_position_based_stays_out_of_the_head() {
    run(IntegratorKind::PositionBased);
}

#[test]
fn shaking_linear_implicit_stays_out_of_the_head() {
    run(IntegratorKind::LinearImplicit);
}

#[test]
fn shaking_xpbd_stays_out_of_the_head() {
    run(IntegratorKind::Xpbd);
}
