//! Strand control points (§3.5): the skeleton's nodes offset by the strand's root offset, expressed
//! in each node's frame, so a strand follows its group's curls.

use glam::{Vec2, Vec3};

use crate::frame::Frame;

/// Writes the `n` control points of one strand: `node_k + offset.x · normal_k + offset.y ·
/// binormal_k` [m]. All three slices have the chain's node count.
pub fn strand_control_points(
    node_positions: &[Vec3],
    node_frames: &[Frame],
    root_offset: Vec2,
    control_points: &mut [Vec3],
) {
    for ((point, &node), frame) in control_points
        .iter_mut()
        .zip(node_positions)
        .zip(node_frames)
    {
        *point = node + frame.normal * root_offset.x + frame.binormal * root_offset.y;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_follow_the_node_frames() {
        let frames = [
            Frame::default(),
            Frame::from_tangent_and_normal(Vec3::X, Vec3::Y).unwrap(),
        ];
        let nodes = [Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)];
        let mut points = [Vec3::ZERO; 2];
        strand_control_points(&nodes, &frames, Vec2::new(0.1, 0.2), &mut points);
        // Frame 0: normal X, binormal Y. Frame 1: tangent X, normal Y, binormal X × Y = Z.
        assert!((points[0] - Vec3::new(0.1, 0.2, 0.0)).length() < 1e-6);
        assert!((points[1] - Vec3::new(1.0, 0.1, 0.2)).length() < 1e-6);
        // The distance to the skeleton is |offset| at every node.
        for (p, n) in points.iter().zip(&nodes) {
            assert!((p.distance(*n) - Vec2::new(0.1, 0.2).length()).abs() < 1e-6);
        }
    }
}
