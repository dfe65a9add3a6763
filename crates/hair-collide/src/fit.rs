//! Per-representation segment volumes (§5.3): LSS for strand groups and clusters, RSS for
//! patches, a PSS around the whole head. Every fitted volume encloses its points.
//!
//! Fitted radii get a rounding slack of [`ROUNDING_SLACK`] times the largest coordinate
//! magnitude involved (about 1 µm at 0.5 m), so that enclosure holds for the exact real numbers
//! and not only for the f32 distance evaluation.

use glam::Vec3;
use hair_core::TriangleMesh;

use crate::geometry::{Rectangle, point_segment_distance_squared};
use crate::volume::{Lss, Pss, Rss};

/// Relative slack added to fitted radii: radius += `ROUNDING_SLACK` × (largest |coordinate| \[m\]).
pub const ROUNDING_SLACK: f32 = 16.0 * f32::EPSILON;

fn slack_for(points: &[Vec3]) -> f32 {
    ROUNDING_SLACK
        * points
            .iter()
            .fold(0.0f32, |m, p| m.max(p.abs().max_element()))
}

/// Strand-group segment: the LSS around skeleton segment `[top, bottom]` \[m\] with radius
/// `thickness` \[m\] (0 for a lone strand, which makes the volume the segment itself).
pub fn strand_group_segment(top: Vec3, bottom: Vec3, thickness: f32) -> Lss {
    Lss {
        start: top,
        end: bottom,
        radius: thickness,
    }
}

/// The LSS on axis `[start, end]` \[m\] with the smallest radius that encloses `points` \[m\]
/// (the largest point-to-segment distance), plus rounding slack.
pub fn lss_on_axis(start: Vec3, end: Vec3, points: &[Vec3]) -> Lss {
    let farthest = points
        .iter()
        .map(|&p| point_segment_distance_squared(p, start, end).sqrt())
        .fold(0.0f32, f32::max);
    let slack = slack_for(points).max(slack_for(&[start, end]));
    Lss {
        start,
        end,
        radius: farthest + slack,
    }
}

/// Cluster segment: an LSS on the skeleton axis `[top, bottom]` \[m\] enclosing the segment's 8
/// control points \[m\] (the 4 of the top cross-section, then the 4 of the bottom one).
///
/// The axis is the skeleton segment, so only the radius is fitted: the largest distance from a
/// control point to the segment. This is the tightest LSS on that axis; for the circular
/// cross-sections of §3.4 it equals the larger of the two cross-section radii when the
/// cross-sections are perpendicular to the segment, and is smaller when they are tilted.
pub fn cluster_segment(top: Vec3, bottom: Vec3, control_points: &[Vec3; 8]) -> Lss {
    lss_on_axis(top, bottom, control_points)
}

/// Patch segment: an RSS enclosing the 4 control points \[m\] that outline the segment, ordered
/// `[top_left, top_right, bottom_left, bottom_right]` (the two per-node control points of §3.3,
/// for the top node then the bottom node).
///
/// The plane passes through the centroid with Newell's normal of the quadrilateral
/// (`(bottom_right − top_left) × (bottom_left − top_right)`, the least-squares normal direction
/// for a quad); the rectangle's first axis is the mean width direction projected onto the plane,
/// the second completes a right-handed frame. The rectangle is the bounding box of the projected
/// points, and the radius is the largest out-of-plane distance plus rounding slack. Degenerate
/// inputs (zero width, coincident points) fall back to any orthonormal frame, which still
/// encloses: every point lies at its in-plane coordinates inside the rectangle and within its
/// height of it.
pub fn patch_segment(control_points: &[Vec3; 4]) -> Rss {
    let [top_left, top_right, bottom_left, bottom_right] = *control_points;
    let centroid = (top_left + top_right + bottom_left + bottom_right) * 0.25;
    let mean_width = (top_right - top_left) + (bottom_right - bottom_left);
    let mean_length = (bottom_left + bottom_right) - (top_left + top_right);

    let mut normal = (bottom_right - top_left)
        .cross(bottom_left - top_right)
        .normalize_or_zero();
    if normal == Vec3::ZERO {
        // Collinear points: any normal perpendicular to the main direction.
        let main = if mean_width.length_squared() >= mean_length.length_squared() {
            mean_width
        } else {
            mean_length
        };
        normal = main.normalize_or(Vec3::X).any_orthonormal_vector();
    }
    let mut axis_u = (mean_width - normal * mean_width.dot(normal)).normalize_or_zero();
    if axis_u == Vec3::ZERO {
        axis_u = (mean_length - normal * mean_length.dot(normal)).normalize_or_zero();
    }
    if axis_u == Vec3::ZERO {
        axis_u = normal.any_orthonormal_vector();
    }
    let axis_v = normal.cross(axis_u).normalize();

    let mut low = [f32::INFINITY; 2];
    let mut high = [f32::NEG_INFINITY; 2];
    let mut height = 0.0f32;
    for p in control_points {
        let local = *p - centroid;
        for (k, axis) in [axis_u, axis_v].into_iter().enumerate() {
            let coordinate = local.dot(axis);
            low[k] = low[k].min(coordinate);
            high[k] = high[k].max(coordinate);
        }
        height = height.max(local.dot(normal).abs());
    }
    let center =
        centroid + axis_u * (0.5 * (low[0] + high[0])) + axis_v * (0.5 * (low[1] + high[1]));
    let half_extents = [0.5 * (high[0] - low[0]), 0.5 * (high[1] - low[1])];
    let rectangle = Rectangle {
        center,
        axes: [axis_u, axis_v],
        half_extents,
    };
    let slack = slack_for(control_points) + ROUNDING_SLACK * (half_extents[0] + half_extents[1]);
    Rss::new(rectangle, height + slack)
}

/// A ball enclosing `points` \[m\]: centred on their bounding-box centre, radius the largest
/// distance to it plus rounding slack. `None` for no points.
pub fn enclosing_ball(points: &[Vec3]) -> Option<Pss> {
    let first = *points.first()?;
    let (low, high) = points
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let center = (low + high) * 0.5;
    let farthest = points
        .iter()
        .map(|p| p.distance(center))
        .fold(0.0f32, f32::max);
    Some(Pss {
        center,
        radius: farthest + slack_for(points) + ROUNDING_SLACK * farthest,
    })
}

/// Head at the top level: the PSS around the whole mesh (every vertex, hence every triangle).
/// `None` for a mesh without vertices.
pub fn head_volume(mesh: &TriangleMesh) -> Option<Pss> {
    enclosing_ball(&mesh.positions)
}
