//! Roots carried by a deforming body ([`RootCarrier`]): a body moved only rigidly through time
//! samples drives the chains exactly as the same rigid motion given as head keyframes, with
//! every integrator; a deforming body carries each root to its own triangle's point.

use std::sync::Arc;

use glam::{Quat, Vec3};

use super::tests::ring_of_chains;
use super::*;
use crate::mesh_sequence::MeshSequence;
use crate::transform::RigidTransform;
use crate::{HairStyle, SkeletonRest};

/// One small triangle per chain of `rest`, its centroid on the chain's root (so the root rides
/// it at barycentric (⅓, ⅓, ⅓)), lying across the root's tangent.
pub(crate) fn triangles_under(
    rest: &SkeletonRest,
) -> (Vec<Vec3>, Vec<[u32; 3]>, Vec<SurfaceAttachment>) {
    let mut points = Vec::new();
    let mut triangles = Vec::new();
    let mut attachments = Vec::new();
    for chain in 0..rest.chain_count() {
        let root = rest.root_positions[chain];
        let frame = rest.root_frames[chain];
        let (u, v) = (frame.normal * 0.01, frame.binormal * 0.01);
        let first = points.len() as u32;
        points.extend([root + u, root - 0.5 * u + v, root - 0.5 * u - v]);
        triangles.push([first, first + 1, first + 2]);
        attachments.push(SurfaceAttachment {
            triangle: chain as u32,
            barycentric: Vec3::splat(1.0 / 3.0),
        });
    }
    (points, triangles, attachments)
}

/// A rigid motion: 2 rad/s about a tilted axis through the origin, and a drift.
fn rigid(time: f64) -> RigidTransform {
    let t = time as f32;
    RigidTransform::new(
        Quat::from_axis_angle(Vec3::new(0.3, 1.0, 0.2).normalize(), 2.0 * t),
        Vec3::new(0.05 * t, 0.02 * (5.0 * t).sin(), -0.03 * t),
    )
}

#[test]
fn a_body_moved_rigidly_through_samples_drives_the_chains_as_the_same_keyframed_head() {
    let style = HairStyle::curly(50.0, 0.01, 0.02);
    let rest = ring_of_chains(&style, 0.2, 6);
    let (points, triangles, attachments) = triangles_under(&rest);
    for integrator in IntegratorKind::ALL {
        let settings = SimulationSettings::recommended(integrator);
        let steps = 12;
        // A sample (and a keyframe) at every substep boundary: no interpolation anywhere, so
        // both runs see the same root poses up to rounding (the carry's frames, ~1e-7).
        let h = settings.substep() as f64;
        let times: Vec<f64> = (0..=steps * settings.substeps as usize)
            .map(|k| k as f64 * h)
            .collect();
        let samples = times
            .iter()
            .map(|&t| {
                points
                    .iter()
                    .map(|&p| rigid(t).transform_point(p))
                    .collect()
            })
            .collect();
        let sequence = MeshSequence::new(triangles.clone(), times.clone(), samples).unwrap();
        let keys = times
            .iter()
            .map(|&time| HeadKeyframe {
                time,
                transform: rigid(time),
            })
            .collect();
        let model = DynamicsModel::new(rest.clone(), DynamicsParams::for_style(&style)).unwrap();
        let mut keyed = Simulation::new(model.clone(), settings).unwrap();
        let mut carried = Simulation::new(model, settings).unwrap();
        carried
            .set_root_carrier(Some(RootCarrier {
                body: Arc::new(DeformingBody::new(Arc::new(sequence))),
                attachments: attachments.clone(),
            }))
            .unwrap();
        let keyframed = Environment {
            head: HeadMotion::keyframed(keys).unwrap(),
            ..Environment::default()
        };
        let still = Environment::default();
        let mut a = keyed.rest_state(&keyframed, 0.0);
        let mut b = carried.rest_state(&still, 0.0);
        keyed.run(&mut a, &keyframed, steps).unwrap();
        carried.run(&mut b, &still, steps).unwrap();
        // Rounding of the carried poses (1e-7 relative) grows through 12 steps of stiff springs
        // by far less than a micrometre; the motion itself moved the roots by centimetres.
        let difference = super::tests::largest_distance(&a, &b);
        assert!(difference < 1e-5, "{integrator}: {difference} m");
        let moved = (a.node_positions[0] - rest.root_positions[0]).length();
        assert!(moved > 0.01, "{integrator}: the roots moved {moved} m");
    }
}

#[test]
fn each_root_rides_its_own_triangle_of_a_deforming_body() {
    let style = HairStyle::curly(50.0, 0.01, 0.02);
    let rest = ring_of_chains(&style, 0.2, 6);
    let (points, triangles, attachments) = triangles_under(&rest);
    // Squash and stretch about the origin: y scaled by 1 − 0.3·s, x and z by 1 + 0.15·s, at
    // s = 0, 1, 0.5 over 0.2 s.
    let shape = |s: f32| Vec3::new(1.0 + 0.15 * s, 1.0 - 0.3 * s, 1.0 + 0.15 * s);
    let times = vec![0.0, 0.1, 0.2];
    let samples = [0.0, 1.0, 0.5]
        .iter()
        .map(|&s| points.iter().map(|&p| p * shape(s)).collect())
        .collect();
    let sequence = MeshSequence::new(triangles, times, samples).unwrap();
    let body = Arc::new(DeformingBody::new(Arc::new(sequence)));
    let settings = SimulationSettings::recommended(IntegratorKind::Xpbd);
    let model = DynamicsModel::new(rest.clone(), DynamicsParams::for_style(&style)).unwrap();
    let mut simulation = Simulation::new(model, settings).unwrap();
    let carrier = RootCarrier {
        body: body.clone(),
        attachments: attachments.clone(),
    };
    // A wrong count of attachments is refused, naming them.
    let short = RootCarrier {
        attachments: attachments[..5].to_vec(),
        ..carrier.clone()
    };
    let error = simulation.set_root_carrier(Some(short)).unwrap_err();
    assert!(error.to_string().contains("root attachments"), "{error}");
    simulation.set_root_carrier(Some(carrier)).unwrap();
    let environment = Environment::default();
    let mut state = simulation.rest_state(&environment, 0.0);
    for step in 1..=9 {
        simulation.step(&mut state, &environment).unwrap();
        let time = step as f64 * settings.time_step as f64;
        let s = match time {
            t if t <= 0.1 => t / 0.1,
            t if t <= 0.2 => 1.0 - 0.5 * (t - 0.1) / 0.1,
            _ => 0.5,
        } as f32;
        for chain in 0..rest.chain_count() {
            // The root is the triangle's centroid, scaled as the vertices are (the scaling is
            // linear, so the centroid of the scaled triangle is the scaled centroid).
            let expected = rest.root_positions[chain] * shape(s);
            let root = state.node_positions[rest.nodes(chain).start];
            assert!(
                (root - expected).length() < 1e-6,
                "step {step} chain {chain}: {root} against {expected}"
            );
        }
    }
    assert_eq!(simulation.root_carrier().unwrap().body, body);
}
