//! Tests of sag-free initialisation: the closed form on a planar cantilever, rest shapes that stay
//! put under gravity with the implicit integrators (and fall without it), and the refusal of a
//! shape the springs cannot hold.

use glam::Vec3;

use crate::dynamics::tests_xpbd::{horizontal, straight_chain};
use crate::dynamics::*;
use crate::frame::Frame;
use crate::skeleton::SkeletonRest;
use crate::style::HairStyle;
use crate::transform::RigidTransform;

/// A straight horizontal chain of `segments` segments of `length` [m] along +X, its root frame's
/// normal up.
fn horizontal_chain(segments: usize, length: f32) -> SkeletonRest {
    straight_chain(horizontal(), segments, length)
}

/// Curly chains growing out sideways from a ring, like hair from the sides of a head.
fn curly_ring(count: usize) -> (SkeletonRest, DynamicsParams) {
    let style = HairStyle::curly(40.0, 0.01, 0.02);
    let angles = style.chain_angles(0.2).unwrap();
    let mut rest = SkeletonRest::default();
    for c in 0..count {
        let angle = c as f32 * std::f32::consts::TAU / count as f32;
        let outward = Vec3::new(angle.cos(), 0.3, angle.sin()).normalize();
        let frame = Frame::from_tangent_and_normal(outward, Vec3::Y).unwrap();
        rest.push_chain(outward * 0.1, frame, &angles).unwrap();
    }
    (rest, DynamicsParams::for_style(&style))
}

#[test]
fn a_planar_cantilever_turns_each_spring_by_its_cut_moment() {
    // A straight horizontal chain has no transport twist, so the balance is closed-form: the spring
    // of joint i turns up by ρ_i = M_i / k_i, M_i = g·Σ_{j ≥ i} m_j·(x_j − x_{i−1}).
    let mut rest = horizontal_chain(10, 0.01);
    let params = DynamicsParams::for_style(&HairStyle::straight(0.01));
    let report = make_sag_free(
        &mut rest,
        &params,
        &RigidTransform::IDENTITY,
        STANDARD_GRAVITY,
        &[],
        TurnLimit::Refuse,
    )
    .unwrap();
    let model = DynamicsModel::new(rest.clone(), params).unwrap();
    let n = model.node_count();
    let g = STANDARD_GRAVITY.length();
    let expected: Vec<f32> = (0..n)
        .map(|i| {
            if i == 0 {
                return 0.0;
            }
            let moment: f32 = (i..n)
                .map(|j| model.node_masses[j] * g * 0.01 * (j - i + 1) as f32)
                .sum();
            moment / model.joint_stiffness[i]
        })
        .collect();
    // Convergence stops at SAG_FREE_TOLERANCE of the largest moment; f32 rounding adds ~1e-6 rad.
    let bound = SAG_FREE_TOLERANCE * expected[1] + 1e-5;
    for (i, &want) in expected.iter().enumerate().skip(1) {
        assert!(
            (rest.natural_polar_angles[i] - want).abs() < bound,
            "joint {i}: {} rad, expected {want} rad",
            rest.natural_polar_angles[i],
        );
        // Turned up: towards the root frame's normal (+Y), azimuth 0.
        assert!(rest.natural_azimuth_angles[i].abs() < 1e-4, "joint {i}");
        // The rest shape itself is untouched.
        assert_eq!(rest.rest_polar_angles[i], 0.0);
    }
    assert!((report.max_turn - expected[1]).abs() < bound);
    assert!(report.max_residual <= SAG_FREE_TOLERANCE);
}

/// Largest and mean node displacement [m] after `seconds` of simulation from the rest shape.
fn drift(
    rest: SkeletonRest,
    params: DynamicsParams,
    integrator: IntegratorKind,
    seconds: f32,
) -> (f32, f32) {
    let model = DynamicsModel::new(rest, params).unwrap();
    let mut simulation =
        Simulation::new(model, SimulationSettings::recommended(integrator)).unwrap();
    let environment = Environment::default();
    let mut state = simulation.rest_state(&environment, 0.0);
    let start = state.node_positions.clone();
    let steps = (seconds / simulation.settings().time_step).round() as usize;
    simulation.run(&mut state, &environment, steps).unwrap();
    let distances: Vec<f32> = start
        .iter()
        .zip(&state.node_positions)
        .map(|(a, b)| a.distance(*b))
        .collect();
    let max = distances.iter().copied().fold(0.0f32, f32::max);
    (max, distances.iter().sum::<f32>() / distances.len() as f32)
}

#[test]
fn sag_free_curls_stay_at_rest_and_plain_ones_fall() {
    let (rest, params) = curly_ring(6);
    let mut balanced = rest.clone();
    let report = make_sag_free(
        &mut balanced,
        &params,
        &RigidTransform::IDENTITY,
        STANDARD_GRAVITY,
        &[],
        TurnLimit::Refuse,
    )
    .unwrap();
    // The twist of transport along the 3-D curls couples the joints: a few iterations.
    assert!(report.max_iterations >= 2, "{report:?}");
    // Without compensation the curls fall by centimetres.
    let (fall, _) = drift(rest, params, IntegratorKind::LinearImplicit, 2.0);
    assert!(fall > 0.02, "uncompensated curls moved only {fall} m");
    // With it, what is left for the linear-implicit integrator is the SAG_FREE_TOLERANCE
    // residual: a moment of 1e-4·M bends each spring by 1e-4 of its compensation turn (≤ 0.33 rad
    // here), moving a 0.2 m chain by well under 0.1 mm.
    let (max, mean) = drift(
        balanced.clone(),
        params,
        IntegratorKind::LinearImplicit,
        2.0,
    );
    assert!(
        max < 1e-4,
        "linear-implicit: largest drift {max} m, mean {mean} m"
    );
    // XPBD meets the lengths through springs 100× stiffer than the inertia m/h² and a projection
    // after the step, so its fixed point lies about 1/100 of the load's effect away from the
    // equilibrium of the forces: a few percent of the uncompensated fall.
    let (max, mean) = drift(balanced, params, IntegratorKind::Xpbd, 2.0);
    assert!(
        max < 0.05 * fall,
        "xpbd: largest drift {max} m, mean {mean} m, against a fall of {fall} m"
    );
}

#[test]
fn a_shape_too_heavy_for_its_springs_is_refused_by_name() {
    // 1 m held out horizontally by straight-hair springs needs a root turn of M/k ≈ 0.5·λ·g·L² /
    // (EI/l) = 0.5·9.81·1 / (2e-3/0.02) ≈ 49 rad: impossible.
    let mut rest = horizontal_chain(50, 0.02);
    let before = rest.clone();
    let params = DynamicsParams::for_style(&HairStyle::straight(0.02));
    let error = make_sag_free(
        &mut rest,
        &params,
        &RigidTransform::IDENTITY,
        STANDARD_GRAVITY,
        &[],
        TurnLimit::Refuse,
    )
    .unwrap_err();
    let message = error.to_string();
    assert!(
        message.contains("chain 0") && message.contains("too soft"),
        "{message}"
    );
    assert_eq!(rest, before);
}
