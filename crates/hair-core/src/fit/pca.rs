//! The principal direction of a set of points (largest-variance axis), by power iteration on the
//! covariance matrix: deterministic and allocation-free for small dimensions.

/// Power-iteration steps.
const ITERATIONS: usize = 64;

/// The unit direction of largest variance of `points` (each `D` coordinates), or `None` when
/// they have no spread (fewer than two distinct points) or a value is not finite. The sign is
/// fixed so that the largest-magnitude coordinate is positive.
pub(crate) fn principal_direction<const D: usize>(points: &[[f32; D]]) -> Option<[f32; D]> {
    if points.len() < 2 {
        return None;
    }
    let mut mean = [0f64; D];
    for p in points {
        for (m, v) in mean.iter_mut().zip(p) {
            *m += f64::from(*v);
        }
    }
    mean.iter_mut().for_each(|m| *m /= points.len() as f64);
    let mut covariance = [[0f64; D]; D];
    for p in points {
        let mut d = [0f64; D];
        for i in 0..D {
            d[i] = f64::from(p[i]) - mean[i];
        }
        for i in 0..D {
            for j in 0..D {
                covariance[i][j] += d[i] * d[j];
            }
        }
    }
    let trace: f64 = (0..D).map(|i| covariance[i][i]).sum();
    if !(trace.is_finite() && trace > 0.0) {
        return None;
    }
    // Start from the axis of largest variance, plus a little of every axis so that the start is
    // not orthogonal to the answer.
    let start = (0..D)
        .max_by(|&a, &b| covariance[a][a].total_cmp(&covariance[b][b]))
        .unwrap_or(0);
    let mut v = [0.1f64; D];
    v[start] = 1.0;
    for _ in 0..ITERATIONS {
        let mut next = [0f64; D];
        for i in 0..D {
            next[i] = (0..D).map(|j| covariance[i][j] * v[j]).sum();
        }
        let norm = next.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 1e-300) {
            return None;
        }
        next.iter_mut().for_each(|x| *x /= norm);
        v = next;
    }
    let largest = (0..D)
        .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
        .unwrap_or(0);
    let sign = if v[largest] < 0.0 { -1.0 } else { 1.0 };
    let mut out = [0f32; D];
    for i in 0..D {
        out[i] = (sign * v[i]) as f32;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_long_axis_of_an_ellipse_is_found() {
        // Points on an ellipse with semi-axes 3 (along (1,1)/√2) and 1: the principal direction
        // is (1,1)/√2.
        let points: Vec<[f32; 2]> = (0..100)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / 100.0;
                let (x, y) = (3.0 * a.cos(), a.sin());
                let s = std::f32::consts::FRAC_1_SQRT_2;
                [s * (x - y) + 5.0, s * (x + y) - 2.0]
            })
            .collect();
        let d = principal_direction(&points).unwrap();
        let s = std::f32::consts::FRAC_1_SQRT_2;
        assert!((d[0] - s).abs() < 1e-4 && (d[1] - s).abs() < 1e-4, "{d:?}");
        assert_eq!(principal_direction(&[[1.0f32, 2.0]; 5]), None);
        assert_eq!(principal_direction(&[[1.0f32, f32::NAN], [0.0, 0.0]]), None);
    }
}
