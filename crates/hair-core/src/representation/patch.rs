//! Patch control points (§3.3): two points per node, colinear with it, half the patch width either
//! side along the node frame's binormal (which starts across the section on the scalp and is carried
//! along the wave): `2n` points of a ruled strip.

use glam::Vec3;

use crate::frame::Frame;

/// Control points per skeleton node of a patch.
pub const PATCH_POINTS_PER_NODE: usize = 2;

/// Writes the `2n` control points of one patch, node-major: `node_k − (w/2)·binormal_k` then
/// `node_k + (w/2)·binormal_k` [m]. As a NURBS surface: a `2 × n` grid, u (across, degree 1)
/// fastest.
pub fn patch_control_points(
    node_positions: &[Vec3],
    node_frames: &[Frame],
    width: f32,
    control_points: &mut [Vec3],
) {
    debug_assert_eq!(
        control_points.len(),
        PATCH_POINTS_PER_NODE * node_positions.len()
    );
    let half = 0.5 * width;
    for (k, (&node, frame)) in node_positions.iter().zip(node_frames).enumerate() {
        control_points[2 * k] = node - frame.binormal * half;
        control_points[2 * k + 1] = node + frame.binormal * half;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_colinear_points_per_node_half_a_width_away() {
        let nodes = [
            Vec3::ZERO,
            Vec3::new(0.0, -0.02, 0.01),
            Vec3::new(0.01, -0.04, 0.01),
        ];
        let frames: Vec<Frame> = nodes
            .iter()
            .map(|_| Frame::from_tangent_and_normal(Vec3::NEG_Y, Vec3::Z).unwrap())
            .collect();
        let mut points = [Vec3::ZERO; 6];
        patch_control_points(&nodes, &frames, 0.04, &mut points);
        for (k, node) in nodes.iter().enumerate() {
            let (a, b) = (points[2 * k], points[2 * k + 1]);
            assert!((a.distance(*node) - 0.02).abs() < 1e-7);
            assert!((b.distance(*node) - 0.02).abs() < 1e-7);
            // Colinear with the node, on opposite sides: the node is their midpoint.
            assert!(((a + b) * 0.5 - *node).length() < 1e-7);
        }
    }
}
