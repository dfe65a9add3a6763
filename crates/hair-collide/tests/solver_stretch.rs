//! The projection's stretch report: where a segment cannot keep its length and its lower node
//! stay outside the head, the position wins and `ProjectionReport::max_stretch` says by how much
//! the segment stretched.

mod support;

use glam::Vec3;
use hair_collide::{
    ChainShape, CollisionBody, CollisionChain, CollisionSettings, CollisionSolver, STRETCH_WARNING,
};
use hair_core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, Simulation, SimulationSettings, SimulationState,
};
use hair_core::skeleton::ChainAngles;
use hair_core::{Frame, SkeletonRest};

const RADIUS: f32 = 0.1;
const SEGMENT: f32 = 0.01;

/// A three-node chain of 1 cm segments rooted at `root`, its simulation at rest and a solver
/// with the sphere of radius `RADIUS` at the origin, whose skin is returned too.
fn one_chain_on_the_sphere(
    root: Vec3,
) -> (
    Simulation,
    SimulationState,
    CollisionSolver,
    CollisionBody,
    f32,
) {
    let mut rest = SkeletonRest::default();
    rest.push_chain(
        root,
        Frame::default(),
        &ChainAngles {
            segment_lengths: vec![0.0, SEGMENT, SEGMENT],
            polar_angles: vec![0.0; 3],
            azimuth_angles: vec![0.0; 3],
        },
    )
    .unwrap();
    let model = DynamicsModel::new(rest, DynamicsParams::default()).unwrap();
    let simulation = Simulation::new(model, SimulationSettings::default()).unwrap();
    let state = simulation.rest_state(&Environment::default(), 0.0);
    let body = CollisionBody::from_mesh(&support::uv_sphere(Vec3::ZERO, RADIUS, 32, 64)).unwrap();
    let settings = CollisionSettings::default();
    let skin = settings.skin;
    let mut solver = CollisionSolver::new(settings).unwrap();
    let chain = CollisionChain {
        chain: 0,
        section: 0,
        shape: ChainShape::StrandGroup { thickness: 0.0 },
    };
    solver.set_chains(&simulation, &[chain]).unwrap();
    (simulation, state, solver, body, skin)
}

/// One chain of three nodes, 1 cm segments, on a sphere of radius 10 cm at the origin, its
/// attached root 5 cm deep inside (a root the groom put in the scalp) and the next two nodes
/// above it, still inside. The projection puts node 1 on the sphere's surface by the top pole,
/// about 5 cm from the root: the segment cannot be 1 cm long with node 1 outside, so it is about
/// `(5 cm + skin) / 1 cm − 1 ≈ 4` too long (400 %), and that is what is reported.
#[test]
fn a_segment_that_cannot_keep_its_length_is_reported() {
    let root = Vec3::new(0.0, 0.05, 0.0);
    let (simulation, mut state, mut solver, mut body, skin) = one_chain_on_the_sphere(root);
    state.node_positions[0] = root;
    state.node_positions[1] = root + Vec3::Y * 0.005;
    state.node_positions[2] = root + Vec3::Y * 0.015;
    let report = solver
        .after_step(
            std::slice::from_mut(&mut body),
            &simulation,
            &mut state,
            &Environment::default(),
        )
        .unwrap();

    // The reported stretch is segment 0–1's as it ended up.
    assert!(report.projected_nodes >= 1);
    let actual = state.node_positions[1].distance(root) / SEGMENT - 1.0;
    assert!(
        (report.max_stretch - actual).abs() < 1e-4,
        "reported {} against the segment's {actual}",
        report.max_stretch
    );
    // Node 1 is on the mesh near the pole, between the pole (y = R) and the first ring of
    // vertices (y = R·cos(π/32)), plus the skin: the stretch is within those bounds.
    let (low, high) = (
        (RADIUS * (std::f32::consts::PI / 32.0).cos() - root.y + skin) / SEGMENT - 1.0,
        (RADIUS - root.y + skin) / SEGMENT - 1.0,
    );
    assert!(
        (low - 1e-4..=high + 1e-4).contains(&report.max_stretch),
        "stretch {} outside {low}..{high}",
        report.max_stretch
    );
    assert!(report.max_stretch > STRETCH_WARNING);
}

/// Nothing inside: nothing projected, no stretch.
#[test]
fn hair_outside_reports_no_stretch() {
    let (simulation, mut state, mut solver, mut body, _) =
        one_chain_on_the_sphere(Vec3::new(0.0, 0.2, 0.0));
    let report = solver
        .after_step(
            std::slice::from_mut(&mut body),
            &simulation,
            &mut state,
            &Environment::default(),
        )
        .unwrap();
    assert_eq!(report.projected_nodes, 0);
    assert_eq!(report.max_stretch, 0.0);
}
