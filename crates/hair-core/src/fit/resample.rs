//! Curves by arc length: length, total turning, resampling to `n` nodes, and the node count rule.

use glam::Vec3;

use super::settings::Smoothness;
use crate::error::{HairError, Result};
use crate::style::MIN_SEGMENT_COUNT;

/// Length of a polyline [m]: the sum of its segments' lengths (0 for fewer than two points).
pub fn curve_length(points: &[Vec3]) -> f32 {
    points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Total turning of a polyline [rad]: the sum of the angles between consecutive segments, the
/// discrete ∫|κ| ds. Zero-length segments are passed over; a straight line gives 0, a full circle
/// 2π, a zigzag of `k` bends by `θ` each `kθ`.
pub fn total_turning(points: &[Vec3]) -> f32 {
    let mut previous: Option<Vec3> = None;
    let mut turning = 0.0;
    for w in points.windows(2) {
        let Some(direction) = (w[1] - w[0]).try_normalize() else {
            continue;
        };
        if let Some(previous) = previous {
            turning += previous.dot(direction).clamp(-1.0, 1.0).acos();
        }
        previous = Some(direction);
    }
    turning
}

/// Node count of a skeleton for a curve of `length` [m] that turns by `turning` [rad] in all
/// ([`total_turning`]), by the rule of [`Smoothness`]:
/// `max(⌈L / max_segment_length⌉, ⌈Θ / max_turn_per_segment⌉, 3) + 1`, at most `max_nodes`.
/// A length or turning that is not finite or not positive counts as 0.
pub fn node_count_for(length: f32, turning: f32, smoothness: &Smoothness) -> usize {
    let segments_for = |amount: f32, per_segment: f32| -> usize {
        if amount.is_finite() && amount > 0.0 && per_segment > 0.0 {
            // `as` saturates: a huge ratio gives usize::MAX, clamped below.
            (amount / per_segment - 1e-4).ceil() as usize
        } else {
            0
        }
    };
    let segments = segments_for(length, smoothness.max_segment_length)
        .max(segments_for(turning, smoothness.max_turn_per_segment))
        .max(MIN_SEGMENT_COUNT);
    segments
        .saturating_add(1)
        .min(smoothness.max_nodes.max(MIN_SEGMENT_COUNT + 1))
}

/// Writes into `out` the points at equal arc-length steps along `points`: `out[j]` lies at arc
/// length `L · j / (out.len() − 1)`, so `out[0]` is the first point and the last is the last.
/// Zero-length segments are passed over. Returns `false`, leaving `out` untouched, when the curve
/// has fewer than two points, a non-finite point, or zero length, or when `out` has fewer than two
/// entries.
pub fn resample_into(points: &[Vec3], out: &mut [Vec3]) -> bool {
    let count = out.len();
    if points.len() < 2 || count < 2 || points.iter().any(|p| !p.is_finite()) {
        return false;
    }
    let length = curve_length(points);
    if !(length.is_finite() && length > 0.0) {
        return false;
    }
    let last = points.len() - 1;
    let mut segment = 0;
    // Arc length at the start of `segment`.
    let mut start = 0.0f32;
    let mut segment_length = points[0].distance(points[1]);
    for (j, slot) in out.iter_mut().enumerate() {
        let target = length * j as f32 / (count - 1) as f32;
        while segment + 1 < last && start + segment_length < target {
            start += segment_length;
            segment += 1;
            segment_length = points[segment].distance(points[segment + 1]);
        }
        let t = if segment_length > 0.0 {
            ((target - start) / segment_length).clamp(0.0, 1.0)
        } else {
            0.0
        };
        *slot = points[segment].lerp(points[segment + 1], t);
    }
    out[0] = points[0];
    out[count - 1] = points[last];
    true
}

/// The curve `points` resampled to `count` nodes at equal arc-length steps ([`resample_into`]).
/// An error when `count < 2` or when the curve has fewer than two points, a non-finite point or
/// zero length.
pub fn resample_curve(points: &[Vec3], count: usize) -> Result<Vec<Vec3>> {
    if count < 2 {
        return Err(HairError::invalid("node count", count, "at least 2 nodes"));
    }
    let mut out = vec![Vec3::ZERO; count];
    if resample_into(points, &mut out) {
        Ok(out)
    } else {
        Err(HairError::invalid(
            "curve",
            format!("{} points, length {} m", points.len(), curve_length(points)),
            "at least 2 finite points and a length > 0 m",
        ))
    }
}

/// The point at fraction `u` (`0..=1`) of a polyline's *node index* range: `u · (n − 1)` between
/// nodes, linearly. For a skeleton resampled at equal arc-length steps this is the point at
/// fraction `u` of its length; for control points built from it (nodes plus offsets) it is the
/// point that corresponds, which is how a strand is drawn on its skeleton.
pub(crate) fn at_fraction(points: &[Vec3], u: f32) -> Vec3 {
    match points.len() {
        0 => Vec3::ZERO,
        1 => points[0],
        n => {
            let x = u.clamp(0.0, 1.0) * (n - 1) as f32;
            let k = (x.floor() as usize).min(n - 2);
            points[k].lerp(points[k + 1], x - k as f32)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{PI, TAU};

    #[test]
    fn a_straight_curve_keeps_its_length_and_is_spaced_evenly() {
        // Uneven input spacing along a line: the resampled nodes are evenly spaced on it and the
        // length is kept exactly (every chord lies on the line).
        let points = [0.0, 0.01, 0.05, 0.06, 0.2].map(|s| Vec3::new(0.3, 1.0, 0.0) + Vec3::Y * -s);
        let out = resample_curve(&points, 9).unwrap();
        assert!((curve_length(&out) - 0.2).abs() < 1e-6);
        for w in out.windows(2) {
            assert!((w[0].distance(w[1]) - 0.025).abs() < 1e-6);
        }
        assert_eq!(out[0], points[0]);
        assert_eq!(out[8], points[4]);
    }

    #[test]
    fn an_arc_keeps_its_length_to_the_chord_error() {
        // A circular arc of radius R through angle α, sampled finely, resampled to n nodes: each
        // chord of arc h = αR/(n−1) is 2R sin(h/2R), so the length is (n−1)·2R·sin(α/(2(n−1))).
        let radius = 0.05;
        let angle = 1.5 * PI;
        let fine: Vec<Vec3> = (0..=3000)
            .map(|i| {
                let a = angle * i as f32 / 3000.0;
                Vec3::new(radius * a.cos(), radius * a.sin(), 0.0)
            })
            .collect();
        for n in [4, 8, 20, 60] {
            let out = resample_curve(&fine, n).unwrap();
            let segments = (n - 1) as f32;
            let expected = segments * 2.0 * radius * (angle / (2.0 * segments)).sin();
            assert!(
                (curve_length(&out) - expected).abs() < 1e-4 * expected,
                "{n}: {} vs {expected}",
                curve_length(&out)
            );
            // Every node lies on the circle.
            assert!(out.iter().all(|p| (p.length() - radius).abs() < 1e-5));
        }
    }

    #[test]
    fn turning_counts_the_bends() {
        let circle: Vec<Vec3> = (0..=64)
            .map(|i| {
                let a = TAU * i as f32 / 64.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        // A closed 64-gon turns by 63 exterior angles of 2π/64 between its 64 segments.
        assert!((total_turning(&circle) - 63.0 * TAU / 64.0).abs() < 1e-4);
        let zigzag = [
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        assert!((total_turning(&zigzag) - PI / 2.0).abs() < 1e-6);
        assert_eq!(
            total_turning(&[Vec3::ZERO, Vec3::X, Vec3::X, Vec3::X * 2.0]),
            0.0
        );
    }

    #[test]
    fn node_counts_follow_length_and_turning() {
        let rule = Smoothness {
            max_segment_length: 0.02,
            max_turn_per_segment: 0.25,
            max_nodes: 50,
        };
        // Short and straight: the floor of 3 segments.
        assert_eq!(node_count_for(0.01, 0.0, &rule), 4);
        // Length rules: 0.2 m / 0.02 m = 10 segments.
        assert_eq!(node_count_for(0.2, 0.5, &rule), 11);
        // Turning rules: 5 rad / 0.25 rad = 20 segments.
        assert_eq!(node_count_for(0.2, 5.0, &rule), 21);
        // Capped.
        assert_eq!(node_count_for(100.0, 0.0, &rule), 50);
        assert_eq!(node_count_for(f32::INFINITY, f32::NAN, &rule), 4);
    }

    #[test]
    fn bad_curves_are_errors_not_panics() {
        assert!(resample_curve(&[Vec3::ZERO], 4).is_err());
        assert!(resample_curve(&[Vec3::ZERO, Vec3::ZERO], 4).is_err());
        assert!(resample_curve(&[Vec3::ZERO, Vec3::NAN], 4).is_err());
        assert!(resample_curve(&[Vec3::ZERO, Vec3::X], 1).is_err());
        // Repeated points inside are passed over.
        let out = resample_curve(&[Vec3::ZERO, Vec3::X, Vec3::X, Vec3::X * 2.0], 5).unwrap();
        assert!((out[2] - Vec3::X).length() < 1e-6 && (out[3] - Vec3::X * 1.5).length() < 1e-6);
    }
}
