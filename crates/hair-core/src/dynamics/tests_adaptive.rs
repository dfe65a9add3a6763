//! Tests of the adaptive substeps: the rule, the speed it reads, and a step that takes more
//! substeps being the fixed step at that count.

use glam::Vec3;

use crate::dynamics::stability::{Scenario, TestChain};
use crate::dynamics::*;

#[test]
fn doublings_follow_the_courant_rule() {
    // A step of 1/60 s in 8 substeps, a Courant limit c = 0.2, at most 32 substeps: a node at
    // `s` segment lengths per second moves s/(60·n) of its segment per substep, so n doubles
    // from 8 until s/(60·n) ≤ 0.2, that is while s > 12·n: 96 per second fits 8 substeps exactly,
    // just over it takes 16, over 192 takes 32, and any speed beyond stops at 32.
    let adaptive = AdaptiveSubsteps {
        max_substeps: 32,
        max_courant: 0.2,
    };
    let step = 1.0 / 60.0;
    for (speed, doublings) in [
        (0.0, 0),
        (95.0, 0),
        (97.0, 1),
        (191.0, 1),
        (193.0, 2),
        (1e9, 2),
        (f32::INFINITY, 2),
    ] {
        assert_eq!(
            adaptive.doublings(step, 8, speed),
            doublings,
            "{speed} per second"
        );
    }
    // A base count at or above the limit never doubles.
    assert_eq!(adaptive.doublings(step, 32, 1e9), 0);
    let mut settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
    assert_eq!(
        (settings.substeps, settings.max_substeps()),
        (8, XPBD_MAX_SUBSTEPS)
    );
    assert_eq!(settings.substeps_for(1e9), XPBD_MAX_SUBSTEPS);
    assert_eq!(settings.substeps_label(), "×8–32");
    settings.adaptive = None;
    assert_eq!(
        (settings.substeps_for(1e9), settings.substeps_label()),
        (8, "×8".into())
    );
    // The other integrators' recommendations are fixed.
    for integrator in [
        IntegratorKind::LinearImplicit,
        IntegratorKind::SemiImplicitEuler,
    ] {
        assert_eq!(SimulationSettings::recommended(integrator).adaptive, None);
    }
}

#[test]
fn bad_adaptive_settings_are_named() {
    for (adaptive, name) in [
        (
            AdaptiveSubsteps {
                max_substeps: 0,
                max_courant: 0.2,
            },
            "adaptive.max_substeps",
        ),
        (
            AdaptiveSubsteps {
                max_substeps: 1 << 17,
                max_courant: 0.2,
            },
            "adaptive.max_substeps",
        ),
        (
            AdaptiveSubsteps {
                max_substeps: 32,
                max_courant: 0.0,
            },
            "adaptive.max_courant",
        ),
        (
            AdaptiveSubsteps {
                max_substeps: 32,
                max_courant: f32::NAN,
            },
            "adaptive.max_courant",
        ),
    ] {
        let settings = SimulationSettings {
            adaptive: Some(adaptive),
            ..SimulationSettings::recommended(IntegratorKind::Xpbd)
        };
        let error = settings.validate().unwrap_err().to_string();
        assert!(error.contains(name), "{error}");
    }
}

/// Two test chains (straight, then curly) with their own segment lengths.
fn two_chains() -> DynamicsModel {
    let mut rest = TestChain::Straight.rest();
    rest.push_chain_from(&TestChain::Curly.rest(), 0).unwrap();
    let params = DynamicsParams::for_style(&TestChain::Straight.style());
    DynamicsModel::new(rest, params).unwrap()
}

#[test]
fn the_relative_speed_is_the_fastest_node_against_its_root_per_segment_length() {
    let model = two_chains();
    let settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
    let simulation = Simulation::new(model.clone(), settings).unwrap();
    let mut state = simulation.rest_state(&Environment::default(), 0.0);
    let mut random = crate::random::SplitMix64::new(7);
    for v in &mut state.node_velocities {
        *v = Vec3::new(
            random.range(-2.0, 2.0),
            random.range(-2.0, 2.0),
            random.range(-2.0, 2.0),
        );
    }
    // Brute force: every non-root node's speed relative to its chain's root, over its
    // segment's rest length.
    let rest = &model.rest;
    let brute = |state: &SimulationState, chain: usize| {
        let nodes = rest.nodes(chain);
        let root = state.node_velocities[nodes.start];
        (nodes.start + 1..nodes.end)
            .map(|node| {
                (state.node_velocities[node] - root).length() / rest.segment_rest_lengths[node]
            })
            .fold(0.0f32, f32::max)
    };
    for chain in 0..rest.chain_count() {
        let expected = brute(&state, chain);
        let measured = simulation.relative_speed(&state, chain).unwrap();
        assert!(expected > 10.0, "{expected}");
        // One square root of the squared maximum against the maximum of square roots: within
        // the rounding of a few operations.
        assert!(
            (measured - expected).abs() <= 1e-5 * expected,
            "{measured} against {expected}"
        );
    }
    // A rigid translation of every node (a head carried fast) does not count.
    let mut translated = state.clone();
    for v in &mut translated.node_velocities {
        *v += Vec3::new(30.0, -5.0, 12.0);
    }
    assert_eq!(simulation.relative_speed(&state, 2), None);
    for chain in 0..rest.chain_count() {
        let (expected, measured) = (
            brute(&state, chain),
            simulation.relative_speed(&translated, chain).unwrap(),
        );
        assert!(
            (measured - expected).abs() <= 1e-4 * expected,
            "{measured} against {expected}"
        );
    }
}

#[test]
fn each_chain_takes_its_own_count() {
    // Two chains in one model, the first moving fast, the second at rest: the first takes 32
    // substeps and the second 8, each chain bit for bit as it moves alone (the fixed step at its
    // own count), and the report gives the most.
    let model = two_chains();
    let settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
    let environment = Environment::default();
    let mut together = Simulation::new(model.clone(), settings).unwrap();
    let mut state = together.rest_state(&environment, 0.0);
    let first = model.rest.nodes(0);
    for (k, node) in first.clone().enumerate() {
        // Growing along the chain to about 4.2 m/s at the tip, over 2 cm segments: about 200
        // segment lengths per second, over the 192 that 16 substeps hold at a Courant limit of 0.2.
        state.node_velocities[node] = Vec3::new(0.0, 4.5 * k as f32 / first.len() as f32, 0.0);
    }
    let speeds = [0, 1].map(|chain| together.relative_speed(&state, chain).unwrap());
    let counts = speeds.map(|speed| settings.substeps_for(speed));
    assert_eq!(counts, [32, 8], "{speeds:?}");
    let before = state.clone();
    let report = together.step(&mut state, &environment).unwrap();
    assert_eq!(report.substeps, 32);
    for (chain, count) in counts.into_iter().enumerate() {
        let mut rest = crate::skeleton::SkeletonRest::default();
        rest.push_chain_from(&model.rest, chain).unwrap();
        let alone_model = DynamicsModel::new(rest, model.params).unwrap();
        let fixed = SimulationSettings::new(IntegratorKind::Xpbd, settings.time_step, count);
        let mut alone = Simulation::new(alone_model, fixed).unwrap();
        let nodes = model.rest.nodes(chain);
        let mut single = alone.rest_state(&environment, 0.0);
        single
            .node_positions
            .copy_from_slice(&before.node_positions[nodes.clone()]);
        single
            .node_velocities
            .copy_from_slice(&before.node_velocities[nodes.clone()]);
        alone.step(&mut single, &environment).unwrap();
        assert_eq!(
            single.node_positions[..],
            state.node_positions[nodes.clone()],
            "chain {chain}"
        );
        assert_eq!(
            single.node_velocities[..],
            state.node_velocities[nodes],
            "chain {chain}"
        );
    }
}

#[test]
fn an_adaptive_step_is_the_fixed_step_at_the_count_it_chose() {
    // The straight test chain in the stability map's 10 rad/s head shake (where XPBD at a
    // fixed 8 substeps is damped wrong): the recommended settings take more substeps in the
    // fast frames and 8 in the slow ones, each step, bit for bit, the fixed step at the count
    // chosen from the state it starts from (so a resumed run steps as the original did).
    let scenario = Scenario {
        label: "shake 10 rad/s".into(),
        stiffness_per_mass: None,
        wind_speed: 0.0,
        shake_speed: 10.0,
    };
    let chain = TestChain::Straight;
    let model = DynamicsModel::new(chain.rest(), scenario.params(&chain.style())).unwrap();
    let environment = scenario.environment();
    let settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
    let mut adaptive = Simulation::new(model.clone(), settings).unwrap();
    let mut state = adaptive.rest_state(&environment, 0.0);
    let mut counts = std::collections::BTreeMap::new();
    for _ in 0..60 {
        let before = state.clone();
        let chosen = settings.substeps_for(adaptive.relative_speed(&before, 0).unwrap());
        let report = adaptive.step(&mut state, &environment).unwrap();
        assert_eq!(report.substeps, chosen);
        *counts.entry(chosen).or_insert(0) += 1;
        let fixed = SimulationSettings::new(IntegratorKind::Xpbd, settings.time_step, chosen);
        let mut plain = Simulation::new(model.clone(), fixed).unwrap();
        let mut again = before;
        plain.step(&mut again, &environment).unwrap();
        assert_eq!(
            again.node_positions, state.node_positions,
            "{chosen} substeps"
        );
        assert_eq!(
            again.node_velocities, state.node_velocities,
            "{chosen} substeps"
        );
    }
    println!("substeps per step: {counts:?}");
    assert!(counts.contains_key(&8), "{counts:?}");
    assert!(counts.keys().any(|&n| n > 8), "{counts:?}");
}
