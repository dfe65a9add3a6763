//! Tests of the lane kernels (the only position-based and XPBD steps): their spring forces
//! against the one-chain forces that the other integrators use, a chain's step independent of
//! the chains beside it in its run (chains of other lengths, free roots, a chain alone), a segment
//! turned back on its parent, the failure policy's report, and the longest chain they take.

use glam::{Vec3, Vec4};

use crate::dynamics::lane_springs::{LaneFrame, SpringScratch, spring_forces};
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::tests::{coiled_positions, largest_distance, ring_chains, ring_of_chains};
use crate::dynamics::*;
use crate::frame::Frame;
use crate::skeleton::SkeletonRest;
use crate::style::HairStyle;

/// The busy ring's 4 rad/s shake and gusting wind.
fn busy_environment() -> Environment {
    Environment {
        head: HeadMotion::shake(0.5, 4.0),
        wind: WindField::gusting(Vec3::new(3.0, 0.0, 1.0), 1.5, 0.8, 0.3, 5),
        gravity: STANDARD_GRAVITY,
    }
}

/// `steps` steps of `settings` on `rest` in the busy environment, from rest.
fn stepped(
    rest: SkeletonRest,
    style: &HairStyle,
    settings: SimulationSettings,
    steps: usize,
) -> SimulationState {
    let environment = busy_environment();
    let model = DynamicsModel::new(rest, DynamicsParams::for_style(style)).unwrap();
    let mut simulation = Simulation::new(model, settings).unwrap();
    let mut state = simulation.rest_state(&environment, 0.0);
    simulation.run(&mut state, &environment, steps).unwrap();
    state
}

#[test]
fn lane_spring_forces_match_the_one_chain_forces() {
    // Reference: `add_spring_forces`, the exact gradient of the bending energy for one chain
    // (checked against finite differences in `forces.rs`), which the semi-implicit Euler and
    // linear-implicit integrators use. The lanes compute the same sums in another order (one
    // reciprocal of 1 + t·d for the binormal and the transport, the normal not renormalised, a
    // polynomial bend angle): each force is a sum over the chain's joints of terms of some twenty
    // roundings each, so they agree to about n·20·ε ≈ 2e-5 of the largest force (n = 13 nodes,
    // ε = 6e-8), plus the polynomial's 1e-6 relative error; bound 1e-4 of the largest force.
    let lengths: Vec<f32> = (0..13).map(|i| if i == 0 { 0.0 } else { 0.02 }).collect();
    let n = lengths.len();
    let root =
        Frame::from_tangent_and_normal(Vec3::new(0.3, -0.2, 1.0).normalize(), Vec3::Y).unwrap();
    let rest_local: Vec<Vec3> = (0..n)
        .map(|i| rest_local_direction(0.3, 0.5 * i as f32))
        .collect();
    let stiffness: Vec<f32> = (0..n).map(|i| if i == 0 { 0.0 } else { 2e-4 }).collect();
    let chains: Vec<Vec<Vec3>> = (0..LANES)
        .map(|lane| coiled_positions(&root, &lengths, 0.1 + 0.15 * lane as f32))
        .collect();
    let mut positions = [LaneVec3::default(); 16];
    for (lane, chain) in chains.iter().enumerate() {
        for (i, p) in chain.iter().enumerate() {
            positions[i].set(lane, *p);
        }
    }
    let splat = |v: Vec3| LaneVec3 {
        x: Lanes::splat(v.x),
        y: Lanes::splat(v.y),
        z: Lanes::splat(v.z),
    };
    let root_frame = LaneFrame {
        normal: splat(root.normal),
        binormal: splat(root.binormal),
        tangent: splat(root.tangent),
    };
    let mut scratch = SpringScratch::<16>::new();
    let (energy, _) = spring_forces(
        &mut scratch,
        &positions,
        n,
        1,
        |i| splat(rest_local[i]),
        |i| Lanes::splat(stiffness[i]),
        |_| Lanes::splat(1.0),
        root_frame,
    );
    for (lane, chain) in chains.iter().enumerate() {
        let mut forces = vec![Vec3::ZERO; n];
        let mut work = vec![Vec4::ZERO; n];
        let expected_energy = add_spring_forces(
            chain,
            chain,
            &root,
            Vec3::ZERO,
            &rest_local,
            &stiffness,
            0.0,
            false,
            &mut work,
            &mut forces,
        );
        let largest = forces.iter().map(|f| f.length()).fold(0.0f32, f32::max);
        assert!(largest > 0.0);
        for (i, expected) in forces.iter().enumerate() {
            let error = (scratch.forces[i].get(lane) - *expected).length();
            assert!(
                error <= 1e-4 * largest,
                "lane {lane} node {i}: {error:e} N off, largest force {largest:e} N"
            );
        }
        let energy_error = (energy.0[lane] - expected_energy).abs();
        assert!(
            energy_error <= 1e-4 * expected_energy,
            "lane {lane}: energy {energy_error:e}"
        );
    }
}

#[test]
fn lanes_step_a_busy_scene_for_a_second() {
    // 60 steps of XPBD on the busy ring of 11 curly chains (one run of 8 and one of 3): finite,
    // and the lengths hold within 0.1 %.
    let style = HairStyle::curly(50.0, 0.01, 0.02);
    let rest = ring_of_chains(&style, 0.25, 11);
    let settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
    let state = stepped(rest.clone(), &style, settings, 60);
    assert!(state.is_finite());
    assert!(state.max_length_error(&rest) < 1e-3);
}

#[test]
fn a_chain_moves_the_same_whichever_chains_share_its_lanes() {
    // The levels of detail step a level's sections together, so the chains beside a chain in
    // its run change as sections come and go. Each chain's step must not depend on them: every
    // Newton, line-search, halving and fallback decision is the chain's own. The busy ring of 11
    // curly chains with and without its first chain (so each other chain moves one lane down
    // and the batches split differently) must agree bit for bit on chains 1..10, after one step
    // and after 30 (the chaotic whipping would amplify any difference).
    let style = HairStyle::curly(50.0, 0.01, 0.02);
    let all: Vec<usize> = (0..11).collect();
    let settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
    let run = |chains: &[usize], steps: usize| {
        let rest = ring_chains(&style, 0.25, 11, chains.iter().copied());
        stepped(rest, &style, settings, steps).node_positions
    };
    for steps in [1, 30] {
        let with_first = run(&all, steps);
        let without_first = run(&all[1..], steps);
        let nodes = with_first.len() / 11;
        assert_eq!(
            &with_first[nodes..],
            &without_first[..],
            "after {steps} steps the chains moved differently without chain 0"
        );
    }
}

#[test]
fn chains_of_other_lengths_and_free_roots_step_as_they_would_alone() {
    // A batch of chains of three lengths is cut into runs of equal node counts, down to runs of
    // one; each chain must move bit for bit as it does alone in a model of its own (a run of
    // one, its lanes repeating it), for both lane integrators, attached and free roots, over 10
    // busy steps.
    let style = HairStyle::curly(50.0, 0.01, 0.02);
    let lengths = [
        0.25, 0.25, 0.2, 0.25, 0.15, 0.15, 0.25, 0.25, 0.25, 0.2, 0.25,
    ];
    let count = lengths.len();
    let ring = |chains: &[usize]| {
        let mut rest = SkeletonRest::default();
        for &c in chains {
            let one = ring_chains(&style, lengths[c], count, [c]);
            rest.push_chain_from(&one, 0).unwrap();
        }
        rest
    };
    let all: Vec<usize> = (0..count).collect();
    let full = ring(&all);
    let node_counts: Vec<usize> = (0..count).map(|c| full.nodes(c).len()).collect();
    assert!(
        node_counts
            .iter()
            .collect::<std::collections::BTreeSet<_>>()
            .len()
            == 3,
        "{node_counts:?}"
    );
    for integrator in [IntegratorKind::PositionBased, IntegratorKind::Xpbd] {
        for roots in [RootMode::Attached, RootMode::Free] {
            let mut settings = SimulationSettings::recommended(integrator);
            settings.roots = roots;
            let together = stepped(full.clone(), &style, settings, 10);
            assert!(together.is_finite());
            for (c, &node_count) in node_counts.iter().enumerate() {
                let alone = stepped(ring(&[c]), &style, settings, 10);
                assert_eq!(
                    &together.node_positions[full.nodes(c)],
                    &alone.node_positions[..],
                    "{integrator} {roots:?}: chain {c} ({} nodes) moved otherwise alone",
                    node_count
                );
                assert_eq!(
                    &together.node_velocities[full.nodes(c)],
                    &alone.node_velocities[..]
                );
            }
        }
    }
}

#[test]
fn a_segment_turned_back_on_its_parent_is_stepped_in_its_lane() {
    // Where a segment lies back along its parent (1 + t·d = 0), the fast frame transport of the
    // lanes is undefined; the lane carries that frame by the quaternion code instead. A straight
    // chain folded back on itself at its middle node, at rest, in calm air: one step of each lane
    // integrator is finite, keeps every segment within 0.1 % of its rest length, and moves no
    // node further than gravity and the springs can in 1/60 s (the springs unfold the fold:
    // well under one segment).
    let style = HairStyle::straight(0.02);
    let rest = ring_of_chains(&style, 0.25, 3);
    let environment = Environment {
        gravity: STANDARD_GRAVITY,
        ..Environment::default()
    };
    for integrator in [IntegratorKind::PositionBased, IntegratorKind::Xpbd] {
        let model = DynamicsModel::new(rest.clone(), DynamicsParams::for_style(&style)).unwrap();
        let settings = SimulationSettings::recommended(integrator);
        let mut simulation = Simulation::new(model, settings).unwrap();
        let mut state = simulation.rest_state(&environment, 0.0);
        let nodes = rest.nodes(1);
        let fold = nodes.start + nodes.len() / 2;
        for i in fold + 1..nodes.end {
            let mirrored = 2.0 * state.node_positions[fold] - state.node_positions[i];
            // Node i goes back along the chain by as much as it went on past the fold.
            state.node_positions[i] = mirrored;
        }
        let folded = state.clone();
        let direction = |p: &[Vec3], i: usize| (p[i] - p[i - 1]).normalize();
        let turn = direction(&folded.node_positions, fold + 1)
            .dot(direction(&folded.node_positions, fold));
        assert!(
            (1.0 + turn).abs() < 1e-4,
            "not folded: 1 + t·d = {}",
            1.0 + turn
        );
        simulation.step(&mut state, &environment).unwrap();
        assert!(state.is_finite(), "{integrator}");
        assert!(state.max_length_error(&rest) < 1e-3, "{integrator}");
        let segment = 0.25 / (nodes.len() - 1) as f32;
        let moved = largest_distance(&folded, &state);
        assert!(moved < segment, "{integrator}: moved {moved} m");
    }
}

#[test]
fn a_failing_chain_is_reported_after_its_halvings_and_the_state_is_kept() {
    // A NaN collision force on chain 5 (in the run of 8 of the busy ring) makes its step fail at
    // any substep: with three halvings allowed, the error names chain 5 after 3 halvings and a
    // non-finite velocity or position, and the state is what it was before the step.
    let style = HairStyle::curly(50.0, 0.01, 0.02);
    let rest = ring_of_chains(&style, 0.25, 11);
    let environment = busy_environment();
    for integrator in [IntegratorKind::PositionBased, IntegratorKind::Xpbd] {
        let model = DynamicsModel::new(rest.clone(), DynamicsParams::for_style(&style)).unwrap();
        let mut settings = SimulationSettings::recommended(integrator);
        settings.on_failure = FailurePolicy::HalveSubstep { max_halvings: 3 };
        let mut simulation = Simulation::new(model, settings).unwrap();
        let mut state = simulation.rest_state(&environment, 0.0);
        simulation.run(&mut state, &environment, 3).unwrap();
        let node = rest.nodes(5).start + 4;
        state.collision_forces[node] = Vec3::new(f32::NAN, 0.0, 0.0);
        let before = state.clone();
        let error = simulation.step(&mut state, &environment).unwrap_err();
        let failure = *error.failure().expect("an instability");
        assert_eq!(failure.chain, 5, "{error}");
        assert_eq!(failure.halvings, 3, "{error}");
        assert_eq!(failure.integrator, integrator);
        assert!(
            matches!(
                failure.quantity,
                FailedQuantity::NonFinitePosition | FailedQuantity::NonFiniteVelocity
            ),
            "{error}"
        );
        assert_eq!(failure.substep, settings.substep() / 8.0);
        assert_eq!(state.node_positions, before.node_positions);
        assert_eq!(state.node_velocities, before.node_velocities);
    }
}

#[test]
fn a_chain_longer_than_the_lanes_take_is_refused() {
    // 0.7 m at segments of at most 1 cm: 71 nodes, over MAX_CHAIN_NODES. The lane integrators
    // refuse the model, naming the chain, its nodes and the limit; semi-implicit Euler takes it.
    let style = HairStyle::straight(0.01);
    let mut rest = ring_of_chains(&style, 0.2, 2);
    let long = ring_of_chains(&style, 0.7, 1);
    rest.push_chain_from(&long, 0).unwrap();
    let nodes = rest.nodes(2).len();
    assert!(nodes > MAX_CHAIN_NODES, "{nodes}");
    let model = DynamicsModel::new(rest, DynamicsParams::for_style(&style)).unwrap();
    for integrator in [IntegratorKind::PositionBased, IntegratorKind::Xpbd] {
        let settings = SimulationSettings::recommended(integrator);
        let error = Simulation::new(model.clone(), settings).unwrap_err();
        assert_eq!(
            error,
            DynamicsError::ChainTooLong {
                chain: 2,
                nodes,
                limit: MAX_CHAIN_NODES,
                integrator,
            }
        );
        let message = error.to_string();
        assert!(
            message.contains("chain 2") && message.contains("64"),
            "{message}"
        );
    }
    let settings = SimulationSettings::recommended(IntegratorKind::SemiImplicitEuler);
    let mut simulation = Simulation::new(model, settings).unwrap();
    // Switching such a simulation to a lane integrator fails and keeps its settings.
    let xpbd = SimulationSettings::recommended(IntegratorKind::Xpbd);
    assert!(simulation.set_settings(xpbd).is_err());
    assert_eq!(
        simulation.settings().integrator,
        IntegratorKind::SemiImplicitEuler
    );
}
