//! Occluder boxes that follow a deforming body (issue 53): the boxes found inside the body at
//! rest ([`Head::occluder_boxes`](crate::Head::occluder_boxes)), moved by a rigid transform
//! fitted to the deformation and shrunk by how far the surface strays from it, so that they stay
//! inside the body and the level selection's occlusion tests stay conservative.

use glam::{Mat3, Vec3};

/// Writes into `out` (replacing its contents) axis-aligned boxes inside the boxes `boxes`
/// (`(low, high)` corners \[m\]) moved by the rigid transform `rotation`, `translation`, box
/// `i` shrunk by `shrinks[i]` \[m\] on every side (0 past the end of `shrinks`). A box that
/// would vanish is left out.
///
/// What it is for: where every point of a body's surface lies within the shrink of its rest
/// position moved by that transform (a deforming body's rigid fit and its deviation), a point at
/// depth at least the shrink inside the moved rest body is inside the deformed one (the surface,
/// morphing from one to the other, never crosses it), so boxes inside the body at rest stay
/// inside it.
///
/// How: each box keeps its moved centre and takes the largest half-extents `λ h` (one scale for
/// its three half-extents `h`) that fit in the turned box (a corner `s` of the axis-aligned box
/// lies in the turned one when `Σⱼ |Rⱼᵢ| λ hⱼ ≤ hᵢ` along every axis `i` of the turned box),
/// less the shrink.
pub fn carried_boxes(
    boxes: &[(Vec3, Vec3)],
    rotation: Mat3,
    translation: Vec3,
    shrinks: &[f32],
    out: &mut Vec<(Vec3, Vec3)>,
) {
    out.clear();
    let absolute = Mat3::from_cols(
        rotation.x_axis.abs(),
        rotation.y_axis.abs(),
        rotation.z_axis.abs(),
    );
    for (i, &(low, high)) in boxes.iter().enumerate() {
        let shrink = shrinks.get(i).copied().unwrap_or(0.0);
        let half = (high - low) * 0.5;
        let centre = rotation * ((low + high) * 0.5) + translation;
        // Along axis i of the turned box, Σⱼ |Rⱼᵢ| hⱼ: column i of |R| (R's columns are the
        // turned axes) dotted with h.
        let reach = Vec3::new(
            absolute.x_axis.dot(half),
            absolute.y_axis.dot(half),
            absolute.z_axis.dot(half),
        );
        let scale = [0, 1, 2]
            .map(|i| {
                if reach[i] > 0.0 {
                    half[i] / reach[i]
                } else {
                    0.0
                }
            })
            .into_iter()
            .fold(1.0f32, f32::min);
        let kept = half * scale - Vec3::splat(shrink.max(0.0));
        if kept.min_element() > 0.0 && kept.is_finite() && centre.is_finite() {
            out.push((centre - kept, centre + kept));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    /// Whether `p` lies in the box `(low, high)` moved by `rotation`, `translation`, at depth
    /// at least `depth`.
    fn in_moved(
        p: Vec3,
        (low, high): (Vec3, Vec3),
        rotation: Mat3,
        translation: Vec3,
        depth: f32,
    ) -> bool {
        let back = rotation.transpose() * (p - translation);
        let slack = 1e-5;
        (back - low).min_element() >= depth - slack && (high - back).min_element() >= depth - slack
    }

    /// Unmoved and unshrunk, the boxes are themselves.
    #[test]
    fn the_identity_keeps_the_boxes() {
        let boxes = [(Vec3::new(-1.0, -2.0, 0.0), Vec3::new(1.0, 0.5, 3.0))];
        let mut out = Vec::new();
        carried_boxes(&boxes, Mat3::IDENTITY, Vec3::ZERO, &[], &mut out);
        assert_eq!(out, boxes);
    }

    /// Turned by 0.4 rad about a skew axis, moved, and shrunk by 0.05: every corner and the
    /// middle of every face and edge of each carried box lies in its moved box at depth 0.05
    /// (the reference is the moved box itself, by the inverse transform).
    #[test]
    fn carried_boxes_lie_inside_the_moved_boxes() {
        let rotation = Mat3::from_quat(Quat::from_axis_angle(
            Vec3::new(1.0, 2.0, 0.5).normalize(),
            0.4,
        ));
        let translation = Vec3::new(0.3, -0.1, 0.2);
        let boxes = [
            (Vec3::new(-1.0, -0.5, -0.2), Vec3::new(1.0, 0.5, 0.2)),
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.3, 0.3, 0.3)),
        ];
        let mut out = Vec::new();
        carried_boxes(&boxes, rotation, translation, &[0.05, 0.05], &mut out);
        assert_eq!(out.len(), 2);
        for (&rest, &(low, high)) in boxes.iter().zip(&out) {
            for corner in 0..27 {
                let t = Vec3::new(
                    (corner % 3) as f32,
                    ((corner / 3) % 3) as f32,
                    (corner / 9) as f32,
                ) * 0.5;
                let p = low + (high - low) * t;
                assert!(
                    in_moved(p, rest, rotation, translation, 0.05),
                    "{p} of {low}..{high}"
                );
            }
        }
    }

    /// A cube of half-side `h` turned by θ about z keeps the largest axis-aligned cube inside
    /// it, of half-side `h / (cos θ + sin θ)` (its corner on the turned cube's face), less the
    /// shrink.
    #[test]
    fn a_turned_cube_keeps_the_inscribed_cube() {
        let (h, theta, shrink) = (0.15f32, 0.4f32, 0.05f32);
        let rotation = Mat3::from_rotation_z(theta);
        let mut out = Vec::new();
        carried_boxes(
            &[(Vec3::splat(-h), Vec3::splat(h))],
            rotation,
            Vec3::ZERO,
            &[shrink],
            &mut out,
        );
        let expected = h / (theta.cos() + theta.sin()) - shrink;
        let (low, high) = out[0];
        assert!(
            ((high - low) * 0.5 - Vec3::splat(expected))
                .abs()
                .max_element()
                < 1e-6,
            "{out:?}"
        );
    }

    /// A box thinner than twice the shrink vanishes.
    #[test]
    fn a_box_shrunk_away_is_left_out() {
        let boxes = [(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.08))];
        let mut out = vec![(Vec3::ZERO, Vec3::ONE)];
        carried_boxes(&boxes, Mat3::IDENTITY, Vec3::ZERO, &[0.05], &mut out);
        assert!(out.is_empty());
    }
}
