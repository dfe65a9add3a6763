//! Test references for the NURBS module: the recursive Cox–de Boor definition in f64, finite-difference tolerances, shared shapes.

use glam::Vec3;

use super::{KnotVector, NurbsCurve, NurbsSurface};

/// `N_i,p(u)` by the recursive definition in f64, with the degree-0 functions taken on knot span
/// `span` (`N_i,0 = 1` iff `i == span`), so the value at a span's right end is the limit from the
/// left, as in the iterative code. Terms with a zero knot difference are zero (0/0 := 0).
pub fn reference_basis(knots: &[f64], i: usize, p: usize, u: f64, span: usize) -> f64 {
    if p == 0 {
        return if i == span { 1.0 } else { 0.0 };
    }
    let mut value = 0.0;
    let left_width = knots[i + p] - knots[i];
    if left_width > 0.0 {
        value += (u - knots[i]) / left_width * reference_basis(knots, i, p - 1, u, span);
    }
    let right_width = knots[i + p + 1] - knots[i + 1];
    if right_width > 0.0 {
        value +=
            (knots[i + p + 1] - u) / right_width * reference_basis(knots, i + 1, p - 1, u, span);
    }
    value
}

/// `dN_i,p/du` by Piegl & Tiller eq. 2.7 on the f64 recursion:
/// `p N_i,p−1 / (U_i+p − U_i) − p N_i+1,p−1 / (U_i+p+1 − U_i+1)`.
pub fn reference_basis_derivative(knots: &[f64], i: usize, p: usize, u: f64, span: usize) -> f64 {
    let mut value = 0.0;
    let left_width = knots[i + p] - knots[i];
    if left_width > 0.0 {
        value += p as f64 * reference_basis(knots, i, p - 1, u, span) / left_width;
    }
    let right_width = knots[i + p + 1] - knots[i + 1];
    if right_width > 0.0 {
        value -= p as f64 * reference_basis(knots, i + 1, p - 1, u, span) / right_width;
    }
    value
}

/// Tolerance of a central difference `(f(u+h) − f(u−h)) / 2h` against `f′(u)` in f32:
/// truncation `h² M₃ / 6` (`M₃` bounds `|f‴|` near `u`) plus roundoff `2 ε M₀ / (2h)` on values of
/// magnitude up to `M₀`, doubled for the rounding of the evaluation itself.
pub fn central_difference_tolerance(h: f32, third_derivative_bound: f32, value_bound: f32) -> f32 {
    h * h * third_derivative_bound / 6.0 + 4.0 * f32::EPSILON * value_bound / h
}

/// Whether `a` and `b` agree to f32 roundoff: `|a − b| ≤ 10⁻⁵ · max(scale, 1)`, `scale` the magnitude
/// of the terms summed to get them.
pub fn close(a: Vec3, b: Vec3, scale: f32) -> bool {
    (a - b).length() <= 1e-5 * scale.max(1.0)
}

/// A cylinder of radius `radius` around +Y from `base` to `base + height·Y`: u is the line
/// (degree 1, 2 points), v the rational quadratic circle turning about −Y, so that
/// S_u × S_v = height·Y × C′(v) points outwards.
pub fn cylinder(base: Vec3, radius: f32, height: f32) -> (NurbsSurface, NurbsCurve) {
    let circle = NurbsCurve::circle(base, radius, -Vec3::Y).unwrap();
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for (&point, &weight) in circle.control_points().iter().zip(circle.weights()) {
        for i in 0..2 {
            points.push(point + i as f32 * height * Vec3::Y);
            weights.push(weight);
        }
    }
    let knots_u = KnotVector::clamped_uniform(2, 1).unwrap();
    let surface = NurbsSurface::new(knots_u, circle.knots().clone(), points)
        .unwrap()
        .with_weights(weights)
        .unwrap();
    (surface, circle)
}
