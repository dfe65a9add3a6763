//! CPU reference of the clamped uniform B-spline that the shaders evaluate (`shaders/bspline.wgsl`).
//!
//! A strand with `n` control points is the non-rational (unit-weight) B-spline of degree
//! `p = min(3, n − 1)` over the clamped uniform knot vector `t_i = clamp((i − p)/(n − p), 0, 1)`,
//! `i = 0..n+p`: it starts at the first control point and ends at the last, tangent to the control
//! polygon there. Evaluation is de Boor's algorithm, the same steps as the WGSL code, so the two can
//! be compared to float precision.

use glam::Vec3;

/// Highest degree used: cubic.
pub const MAX_DEGREE: usize = 3;

/// The degree `min(3, n − 1)` of a curve with `control_point_count` control points (0 for n ≤ 1).
pub fn degree(control_point_count: usize) -> usize {
    control_point_count.saturating_sub(1).min(MAX_DEGREE)
}

/// Knot `i` of the clamped uniform knot vector for `n` control points and degree `p` (n > p).
pub fn knot(i: usize, n: usize, p: usize) -> f32 {
    ((i as f32 - p as f32) / (n - p) as f32).clamp(0.0, 1.0)
}

/// Point and derivative `dC/du` of the curve at `u` ∈ [0, 1] (clamped), or `None` without
/// control points. One control point gives that point and a zero derivative.
pub fn evaluate(control_points: &[Vec3], u: f32) -> Option<(Vec3, Vec3)> {
    let n = control_points.len();
    match n {
        0 => return None,
        1 => return Some((control_points[0], Vec3::ZERO)),
        _ => {}
    }
    let p = degree(n);
    let segments = n - p;
    let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
    // Knot span k with t_k <= u < t_{k+1}; u = 1 belongs to the last span.
    let span = p + ((u * segments as f32).floor() as usize).min(segments - 1);
    let mut d = [Vec3::ZERO; MAX_DEGREE + 1];
    d[..=p].copy_from_slice(&control_points[span - p..=span]);
    let mut derivative = Vec3::ZERO;
    for r in 1..=p {
        if r == p {
            // The last two points of level p − 1 give the derivative:
            // C'(u) = p (d_p − d_{p−1}) / (t_{k+1} − t_k).
            let width = knot(span + 1, n, p) - knot(span, n, p);
            derivative = (d[p] - d[p - 1]) * (p as f32 / width);
        }
        for j in (r..=p).rev() {
            let i = span - p + j;
            let start = knot(i, n, p);
            let end = knot(i + p + 1 - r, n, p);
            let alpha = if end > start {
                (u - start) / (end - start)
            } else {
                0.0
            };
            d[j] = d[j - 1].lerp(d[j], alpha);
        }
    }
    Some((d[p], derivative))
}

/// `sample_count` points at evenly spaced parameters `u = i / (sample_count − 1)`.
pub fn sample(control_points: &[Vec3], sample_count: usize) -> Vec<Vec3> {
    (0..sample_count)
        .filter_map(|i| {
            let u = if sample_count > 1 {
                i as f32 / (sample_count - 1) as f32
            } else {
                0.0
            };
            evaluate(control_points, u).map(|(point, _)| point)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy(n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                Vec3::new(
                    (i as f32 * 1.3).sin(),
                    -(i as f32) * 0.5,
                    (i as f32 * 0.7).cos(),
                )
            })
            .collect()
    }

    #[test]
    fn clamped_curve_interpolates_its_end_points() {
        for n in 2..9 {
            let points = wavy(n);
            let (start, _) = evaluate(&points, 0.0).unwrap();
            let (end, _) = evaluate(&points, 1.0).unwrap();
            assert!((start - points[0]).length() < 1e-6, "n = {n}");
            assert!((end - points[n - 1]).length() < 1e-5, "n = {n}");
        }
    }

    #[test]
    fn two_points_give_the_segment_and_four_the_bezier() {
        let line = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)];
        let (mid, tangent) = evaluate(&line, 0.25).unwrap();
        assert!((mid - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-6);
        assert!((tangent - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
        // With n = 4 and p = 3 the knot vector is [0,0,0,0,1,1,1,1]: a cubic Bézier curve,
        // B(u) = (1−u)³P0 + 3u(1−u)²P1 + 3u²(1−u)P2 + u³P3.
        let bezier = wavy(4);
        let u = 0.3f32;
        let expected = bezier[0] * (1.0 - u).powi(3)
            + bezier[1] * 3.0 * u * (1.0 - u).powi(2)
            + bezier[2] * 3.0 * u * u * (1.0 - u)
            + bezier[3] * u.powi(3);
        assert!((evaluate(&bezier, u).unwrap().0 - expected).length() < 1e-6);
    }

    #[test]
    fn derivative_matches_central_differences() {
        // Central difference error is O(h²) times the third derivative; h = 1e-3 in f32 leaves
        // about 1e-3 relative error from rounding.
        let points = wavy(7);
        let h = 1e-3f32;
        for &u in &[0.05f32, 0.2, 0.37, 0.5, 0.66, 0.9] {
            let (_, derivative) = evaluate(&points, u).unwrap();
            let ahead = evaluate(&points, u + h).unwrap().0;
            let behind = evaluate(&points, u - h).unwrap().0;
            let numeric = (ahead - behind) / (2.0 * h);
            let error = (numeric - derivative).length() / derivative.length();
            assert!(error < 5e-3, "u = {u}: {derivative} vs {numeric}");
        }
    }

    #[test]
    fn collinear_control_points_stay_on_their_line() {
        let points: Vec<Vec3> = (0..6)
            .map(|i| Vec3::new(0.0, -(i as f32) * 0.1, 0.0))
            .collect();
        for point in sample(&points, 17) {
            assert!(point.x.abs() < 1e-7 && point.z.abs() < 1e-7);
            assert!(point.y <= 1e-7 && point.y >= -0.5 - 1e-6);
        }
        assert!(evaluate(&[], 0.5).is_none());
        assert_eq!(evaluate(&[Vec3::ONE], 0.5), Some((Vec3::ONE, Vec3::ZERO)));
    }
}
