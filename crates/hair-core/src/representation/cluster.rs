//! Cluster control points (§3.4): four points per node on a circle in the node's cross-section,
//! radius interpolated linearly from root to tip: a closed generalized cylinder of `4n` points.

use glam::Vec3;

use crate::frame::Frame;

/// Control points per skeleton node of a cluster.
pub const CLUSTER_POINTS_PER_NODE: usize = 4;

/// Radius of a cluster's control circle at node `node` of `node_count` [m]:
/// `r_root + (r_tip − r_root) · node / (node_count − 1)`.
pub fn cluster_radius_at(node: usize, node_count: usize, root_radius: f32, tip_radius: f32) -> f32 {
    let t = if node_count > 1 {
        node as f32 / (node_count - 1) as f32
    } else {
        0.0
    };
    root_radius + (tip_radius - root_radius) * t
}

/// Writes the `4n` control points of one cluster, node-major: point `4k + j` is
/// `node_k + r_k · (cos(j·90°) · normal_k + sin(j·90°) · binormal_k)` [m].
///
/// As a NURBS surface this is a `4 × n` grid, u (around, periodic) fastest. A periodic cubic
/// B-spline through 4 points on a circle of radius r stays within 2r/3 and 0.648r of the axis, so
/// the drawn tube is about two thirds of the control radius (and inside the control polygon, which
/// the collision volumes enclose).
pub fn cluster_control_points(
    node_positions: &[Vec3],
    node_frames: &[Frame],
    root_radius: f32,
    tip_radius: f32,
    control_points: &mut [Vec3],
) {
    let node_count = node_positions.len();
    debug_assert_eq!(control_points.len(), CLUSTER_POINTS_PER_NODE * node_count);
    for (k, (&node, frame)) in node_positions.iter().zip(node_frames).enumerate() {
        let radius = cluster_radius_at(k, node_count, root_radius, tip_radius);
        let around = [frame.normal, frame.binormal, -frame.normal, -frame.binormal];
        for (j, direction) in around.into_iter().enumerate() {
            control_points[CLUSTER_POINTS_PER_NODE * k + j] = node + direction * radius;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_points_per_node_on_the_interpolated_circle() {
        let n = 5;
        let nodes: Vec<Vec3> = (0..n)
            .map(|k| Vec3::new(0.0, -(k as f32) * 0.02, 0.0))
            .collect();
        let frame = Frame::from_tangent_and_normal(Vec3::NEG_Y, Vec3::Z).unwrap();
        let frames = vec![frame; n];
        let mut points = vec![Vec3::ZERO; 4 * n];
        cluster_control_points(&nodes, &frames, 0.01, 0.005, &mut points);
        for k in 0..n {
            // r_k = 0.01 + (0.005 − 0.01)·k/4
            let radius = 0.01 - 0.005 * k as f32 / 4.0;
            let ring = &points[4 * k..4 * k + 4];
            for point in ring {
                assert!((point.distance(nodes[k]) - radius).abs() < 1e-7);
                // In the cross-section plane: perpendicular to the tangent.
                assert!((*point - nodes[k]).dot(frame.tangent).abs() < 1e-7);
            }
            // Opposite points are diametrically opposite; neighbours are 90° apart.
            assert!((ring[0] + ring[2] - 2.0 * nodes[k]).length() < 1e-7);
            assert!((ring[0] - nodes[k]).dot(ring[1] - nodes[k]).abs() < 1e-9);
        }
    }
}
