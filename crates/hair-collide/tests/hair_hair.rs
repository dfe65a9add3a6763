//! Hair–hair repulsion (beyond the paper): two overlapping sections are pushed apart until their
//! volumes no longer overlap; with repulsion off (the default) they stay as they are. The forces
//! are equal and opposite (they sum to zero), and chains of the same section ignore each other.

use glam::Vec3;
use hair_collide::{
    ChainShape, ChainVolume, CollisionChain, CollisionSettings, CollisionSolver, HairBvh,
    HairHairSettings, Lss, SweptSphere, add_repulsion_forces,
};
use hair_core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, IntegratorKind, RootMode, Simulation,
    SimulationSettings,
};
use hair_core::skeleton::measure_chain;
use hair_core::{Frame, HairStyle, SkeletonRest};

/// Group radius [m]; the two chains' axes are `GAP` apart, so they overlap by `2·RADIUS − GAP`.
const RADIUS: f32 = 0.004;
const GAP: f32 = 0.005;

fn straight_chain(x: f32) -> Vec<Vec3> {
    (0..6)
        .map(|k| Vec3::new(x, -0.015 * k as f32, 0.0))
        .collect()
}

/// The smallest signed separation [m] between the two chains' segment volumes.
fn separation(positions: &[Vec3]) -> f32 {
    let lss = |p: &[Vec3]| -> Vec<SweptSphere> {
        p.windows(2)
            .map(|w| {
                Lss {
                    start: w[0],
                    end: w[1],
                    radius: RADIUS,
                }
                .into()
            })
            .collect()
    };
    let (a, b) = (lss(&positions[..6]), lss(&positions[6..]));
    a.iter()
        .flat_map(|x| b.iter().map(move |y| x.distance(y)))
        .fold(f32::INFINITY, f32::min)
}

fn run(hair_hair: Option<HairHairSettings>) -> f32 {
    let mut rest = SkeletonRest::default();
    for x in [0.0, GAP] {
        let nodes = straight_chain(x);
        let frame = Frame::from_tangent_and_normal(Vec3::NEG_Y, Vec3::Z).unwrap();
        rest.push_chain(nodes[0], frame, &measure_chain(&frame, &nodes).unwrap())
            .unwrap();
    }
    let model =
        DynamicsModel::new(rest, DynamicsParams::for_style(&HairStyle::straight(0.02))).unwrap();
    let settings = SimulationSettings {
        roots: RootMode::Free,
        ..SimulationSettings::recommended(IntegratorKind::SemiImplicitEuler)
    };
    let mut simulation = Simulation::new(model, settings).unwrap();
    let environment = Environment {
        gravity: Vec3::ZERO,
        ..Environment::default()
    };
    let mut state = simulation.rest_state(&environment, 0.0);
    assert!((separation(&state.node_positions) - (GAP - 2.0 * RADIUS)).abs() < 1e-6);
    let settings = CollisionSettings {
        hair_hair,
        ..CollisionSettings::default()
    };
    let mut solver = CollisionSolver::new(settings).unwrap();
    let chains: Vec<CollisionChain> = (0..2)
        .map(|c| CollisionChain {
            chain: c,
            section: c,
            shape: ChainShape::StrandGroup { thickness: RADIUS },
        })
        .collect();
    solver.set_chains(&simulation, &chains).unwrap();
    for _ in 0..60 {
        solver
            .step(&mut [], &mut simulation, &mut state, &environment)
            .unwrap();
    }
    separation(&state.node_positions)
}

#[test]
fn repulsion_separates_two_overlapping_sections() {
    let initial = GAP - 2.0 * RADIUS;
    let off = run(None);
    let on = run(Some(HairHairSettings::default()));
    println!("after 1 s: separation {off} m with repulsion off, {on} m with it on");
    // Off: nothing acts (no gravity, straight rest shapes), the overlap stays to rounding.
    assert!((off - initial).abs() < 1e-5, "{off}");
    // On: the 3 mm overlap is gone (the spring acts only while they overlap), and gently: the
    // push ends when the overlap does, so the sections drift apart at most at the speed the
    // spring gives over the 3 mm, √(n·overlap²/τ²) with n ≈ 3 overlapping pairs per node:
    // ≈ 5 cm/s, i.e. less than 5 cm in 1 s.
    assert!(on >= -1e-4, "still overlapping by {} m", -on);
    assert!(on < 0.05, "kicked apart: {on} m");
}

#[test]
fn repulsion_forces_cancel_and_skip_the_same_section() {
    let mut positions = straight_chain(0.0);
    positions.extend(straight_chain(GAP));
    let volumes = [ChainVolume::StrandGroup { thickness: RADIUS }; 2];
    let hair = HairBvh::build(&[0, 6, 12], &volumes, &positions, &[]).unwrap();
    let settings = HairHairSettings::default();
    let mut forces = vec![Vec3::ZERO; 12];
    let masses = vec![1.5e-5; 12];
    let pairs = add_repulsion_forces(&hair, &[0, 1], &masses, &settings, &mut forces).unwrap();
    assert!(pairs >= 5, "every facing segment pair overlaps ({pairs})");
    let total: Vec3 = forces.iter().sum();
    assert!(total.length() < 1e-9, "net force {total}");
    // Chain 0 is pushed towards −x, chain 1 towards +x.
    assert!(forces[..6].iter().all(|f| f.x <= 0.0) && forces[6..].iter().all(|f| f.x >= 0.0));
    let mut same = vec![Vec3::ZERO; 12];
    assert_eq!(
        add_repulsion_forces(&hair, &[3, 3], &masses, &settings, &mut same).unwrap(),
        0
    );
    assert!(same.iter().all(|f| *f == Vec3::ZERO));
    // Bad input: a section per chain, a force per node, a positive stiffness.
    assert!(add_repulsion_forces(&hair, &[0], &masses, &settings, &mut forces).is_err());
    assert!(add_repulsion_forces(&hair, &[0, 1], &masses, &settings, &mut forces[..3]).is_err());
    let bad = HairHairSettings {
        relaxation_time: 0.0,
    };
    assert!(add_repulsion_forces(&hair, &[0, 1], &masses, &bad, &mut forces).is_err());
    assert!(add_repulsion_forces(&hair, &[0, 1], &masses[..4], &settings, &mut forces).is_err());
}
