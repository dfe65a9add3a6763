//! One chain: nodes from rest angles, rest angles from nodes, and the frames at the nodes.

use glam::Vec3;

use crate::error::{HairError, Result};
use crate::frame::Frame;

/// Segment lengths and rest angles of one chain, one entry per node (the root's entries are 0).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChainAngles {
    /// Length of the segment ending at each node [m]; 0 at the root.
    pub segment_lengths: Vec<f32>,
    /// Polar angle θ of each node's segment from the previous segment [rad], `0..=π/2` for styles.
    pub polar_angles: Vec<f32>,
    /// Azimuth φ of each node's segment around the previous segment [rad], from the frame's normal
    /// towards its binormal.
    pub azimuth_angles: Vec<f32>,
}

impl ChainAngles {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.segment_lengths.len()
    }

    /// Total length of the chain [m].
    pub fn length(&self) -> f32 {
        self.segment_lengths.iter().sum()
    }
}

/// Places the nodes of one chain from its root and rest angles (§3.2).
///
/// `positions[0] = root_position`; for `i ≥ 1`, `positions[i] = positions[i − 1] + l_i · d_i` with
/// `d_i = F_{i−1}.direction(θ_i, φ_i)`, where `F_0` is `root_frame` and `F_i` is `F_{i−1}` transported
/// to `d_i`. All slices have the chain's node count; entry 0 of the per-node slices is ignored.
pub fn build_chain(
    root_position: Vec3,
    root_frame: &Frame,
    segment_lengths: &[f32],
    polar_angles: &[f32],
    azimuth_angles: &[f32],
    positions: &mut [Vec3],
) -> Result<()> {
    let node_count = positions.len();
    for (what, len) in [
        ("segment_lengths", segment_lengths.len()),
        ("polar_angles", polar_angles.len()),
        ("azimuth_angles", azimuth_angles.len()),
    ] {
        if len != node_count {
            return Err(HairError::SizeMismatch {
                what,
                actual: len,
                expected: node_count,
            });
        }
    }
    if node_count == 0 {
        return Ok(());
    }
    positions[0] = root_position;
    let mut frame = *root_frame;
    for i in 1..node_count {
        let direction = frame.direction(polar_angles[i], azimuth_angles[i]);
        positions[i] = positions[i - 1] + direction * segment_lengths[i];
        frame = frame.transported_to(direction);
    }
    Ok(())
}

/// Recovers segment lengths and rest angles from node positions: the inverse of [`build_chain`].
///
/// Where a segment continues straight on (θ = 0) its azimuth is undefined and reported as 0.
/// A zero-length or non-finite segment is an error naming the node.
pub fn measure_chain(root_frame: &Frame, positions: &[Vec3]) -> Result<ChainAngles> {
    let node_count = positions.len();
    let mut angles = ChainAngles {
        segment_lengths: vec![0.0; node_count],
        polar_angles: vec![0.0; node_count],
        azimuth_angles: vec![0.0; node_count],
    };
    let mut frame = *root_frame;
    for i in 1..node_count {
        let segment = positions[i] - positions[i - 1];
        let length = segment.length();
        if !(length.is_finite() && length > 0.0) {
            return Err(HairError::invalid(
                "segment length",
                format!("{length} at node {i}"),
                "a finite length > 0 m",
            ));
        }
        let direction = segment / length;
        let (polar, azimuth) = frame.angles_of(direction);
        angles.segment_lengths[i] = length;
        angles.polar_angles[i] = polar;
        angles.azimuth_angles[i] = azimuth;
        frame = frame.transported_to(direction);
    }
    Ok(angles)
}

/// Computes the frame at every node of one chain from its positions alone (and the root frame).
///
/// The root gets `root_frame`, interior nodes the frame halfway between their two segments' frames,
/// the tip its last segment's frame. A zero-length segment keeps the previous direction. `frames`
/// has the chain's node count.
pub fn node_frames(root_frame: &Frame, positions: &[Vec3], frames: &mut [Frame]) {
    debug_assert_eq!(positions.len(), frames.len());
    let node_count = positions.len().min(frames.len());
    if node_count == 0 {
        return;
    }
    frames[0] = *root_frame;
    let mut segment_frame = *root_frame;
    for i in 1..node_count {
        let direction = (positions[i] - positions[i - 1])
            .try_normalize()
            .unwrap_or(segment_frame.tangent);
        segment_frame = segment_frame.transported_to(direction);
        if i + 1 < node_count {
            let next = (positions[i + 1] - positions[i])
                .try_normalize()
                .unwrap_or(direction);
            frames[i] = segment_frame.halfway_to(next);
        } else {
            frames[i] = segment_frame;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_PI_2;

    fn root_frame() -> Frame {
        Frame::from_tangent_and_normal(Vec3::new(0.1, -1.0, -0.2), Vec3::new(0.0, 0.3, 1.0))
            .unwrap()
    }

    #[test]
    fn straight_chain_is_a_line_along_the_root_tangent() {
        let frame = root_frame();
        let n = 6;
        let lengths = [0.0, 0.01, 0.02, 0.01, 0.03, 0.01];
        let mut positions = vec![Vec3::ZERO; n];
        build_chain(
            Vec3::ONE,
            &frame,
            &lengths,
            &[0.0; 6],
            &[0.0; 6],
            &mut positions,
        )
        .unwrap();
        // p_i = root + (Σ l) · t
        let total: f32 = lengths.iter().sum();
        assert!((positions[5] - (Vec3::ONE + frame.tangent * total)).length() < 1e-6);
    }

    #[test]
    fn build_and_measure_round_trip_for_arbitrary_angles() {
        let frame = root_frame();
        let n = 12;
        let lengths: Vec<f32> = (0..n)
            .map(|i| if i == 0 { 0.0 } else { 0.01 + 0.001 * i as f32 })
            .collect();
        let polar: Vec<f32> = (0..n)
            .map(|i| {
                if i == 0 {
                    0.0
                } else {
                    0.1 + 0.12 * i as f32 % 1.4
                }
            })
            .collect();
        let azimuth: Vec<f32> = (0..n)
            .map(|i| if i == 0 { 0.0 } else { -3.0 + 0.53 * i as f32 })
            .collect();
        let mut positions = vec![Vec3::ZERO; n];
        build_chain(
            Vec3::new(0.0, 0.1, 0.0),
            &frame,
            &lengths,
            &polar,
            &azimuth,
            &mut positions,
        )
        .unwrap();
        let measured = measure_chain(&frame, &positions).unwrap();
        for i in 1..n {
            assert!((measured.segment_lengths[i] - lengths[i]).abs() < 1e-6);
            assert!(
                (measured.polar_angles[i] - polar[i]).abs() < 1e-4,
                "node {i}"
            );
            let wrapped = (measured.azimuth_angles[i] - azimuth[i] + std::f32::consts::PI)
                .rem_euclid(std::f32::consts::TAU)
                - std::f32::consts::PI;
            assert!(wrapped.abs() < 1e-3, "node {i}: {wrapped}");
        }
        // And building again from the measured angles gives the same nodes.
        let mut again = vec![Vec3::ZERO; n];
        build_chain(
            positions[0],
            &frame,
            &measured.segment_lengths,
            &measured.polar_angles,
            &measured.azimuth_angles,
            &mut again,
        )
        .unwrap();
        for (a, b) in positions.iter().zip(&again) {
            assert!((*a - *b).length() < 1e-5);
        }
    }

    #[test]
    fn node_frames_bisect_the_bends() {
        let frame = root_frame();
        let n = 4;
        let mut positions = vec![Vec3::ZERO; n];
        build_chain(
            Vec3::ZERO,
            &frame,
            &[0.0, 0.01, 0.01, 0.01],
            &[0.0, 0.0, FRAC_PI_2, 0.0],
            &[0.0; 4],
            &mut positions,
        )
        .unwrap();
        let mut frames = vec![Frame::default(); n];
        node_frames(&frame, &positions, &mut frames);
        // Node 1 sits at a right-angle bend: its tangent is the bisector of the two segments.
        let expected = ((positions[1] - positions[0]).normalize()
            + (positions[2] - positions[1]).normalize())
        .normalize();
        assert!((frames[1].tangent - expected).length() < 1e-5);
        assert!((frames[3].tangent - (positions[3] - positions[2]).normalize()).length() < 1e-5);
    }

    #[test]
    fn size_mismatch_and_degenerate_segments_are_errors() {
        let frame = root_frame();
        let mut positions = vec![Vec3::ZERO; 3];
        assert!(
            build_chain(
                Vec3::ZERO,
                &frame,
                &[0.0; 2],
                &[0.0; 3],
                &[0.0; 3],
                &mut positions
            )
            .is_err()
        );
        let error = measure_chain(&frame, &[Vec3::ZERO, Vec3::ZERO]).unwrap_err();
        assert!(error.to_string().contains("node 1"));
        assert!(measure_chain(&frame, &[Vec3::ZERO, Vec3::NAN]).is_err());
    }
}
