//! B-spline basis functions and their derivatives at one knot span (Piegl & Tiller A2.2, A2.3), as pure functions.
//!
//! All functions take the full knot slice `knots`, the `degree` `p`, a `span` index `s` with
//! `knots[s] ≤ u ≤ knots[s + 1]` and `knots[s] < knots[s + 1]` (as returned by
//! [`KnotVector::find_span`](super::KnotVector::find_span)), and write the `p + 1` non-zero
//! functions `N_(s−p),ₚ(u) … N_s,ₚ(u)` into caller-provided slices, in that order. They never
//! allocate. Parameters are dimensionless; derivatives are per unit parameter.
//!
//! Preconditions (a valid span, slices long enough, `degree ≤ MAX_DEGREE`) are programming errors,
//! checked by slice indexing (a panic), not by `Result`: validated [`KnotVector`](super::KnotVector)s
//! guarantee them.

use super::MAX_DEGREE;

/// Evaluates the `degree + 1` non-zero B-spline basis functions at `u` in knot span `span`
/// (Piegl & Tiller A2.2, Cox–de Boor in triangular form) into `values[..=degree]`.
///
/// `values[j]` is `N_(span − degree + j), degree(u)`. They are non-negative and sum to one.
///
/// # Panics
/// If `values.len() < degree + 1` or `span` is not a valid span of `knots` (see the module docs).
pub fn basis_functions(knots: &[f32], degree: usize, span: usize, u: f32, values: &mut [f32]) {
    values[0] = 1.0;
    for level in 1..=degree {
        raise_degree(knots, span, u, level, values);
    }
}

/// One step of A2.2: turns the `level` functions of degree `level − 1` in `values[..level]` into the
/// `level + 1` functions of degree `level`. The knot differences `right = U[s+r+1] − u` and
/// `left = u − U[s+1+r−level]` are computed in place (no scratch arrays).
#[inline]
fn raise_degree(knots: &[f32], span: usize, u: f32, level: usize, values: &mut [f32]) {
    let mut saved = 0.0;
    for r in 0..level {
        let right = knots[span + r + 1] - u;
        let left = u - knots[span + 1 + r - level];
        let temp = values[r] / (right + left);
        values[r] = saved + right * temp;
        saved = left * temp;
    }
    values[level] = saved;
}

/// Evaluates the non-zero basis functions and their first derivatives at `u` in span `span` into
/// `values[..=degree]` and `derivatives[..=degree]` (`derivatives[j] = dN_(span − degree + j)/du`).
///
/// Uses `N′ᵢ,ₚ = p·Nᵢ,ₚ₋₁ / (U_(i+p) − Uᵢ) − p·Nᵢ₊₁,ₚ₋₁ / (U_(i+p+1) − U_(i+1))` (Piegl & Tiller
/// eq. 2.7, the first-order case of A2.3), folded into the last degree-raising step of A2.2, so
/// it costs one extra multiply-add per function and never divides by a zero knot difference.
/// The derivatives sum to zero.
///
/// # Panics
/// If a slice is shorter than `degree + 1` or `span` is not a valid span of `knots`.
pub fn basis_functions_and_derivatives(
    knots: &[f32],
    degree: usize,
    span: usize,
    u: f32,
    values: &mut [f32],
    derivatives: &mut [f32],
) {
    values[0] = 1.0;
    for level in 1..degree {
        raise_degree(knots, span, u, level, values);
    }
    // Last step (level = degree): temp_r = N_(s−p+1+r),p−1 / (U_(s+1+r) − U_(s+1+r−p)), and
    // dN_(s−p+j),p/du = p (temp_(j−1) − temp_j) with temp_(−1) = temp_p = 0.
    let p = degree as f32;
    let mut saved = 0.0;
    let mut previous = 0.0;
    for r in 0..degree {
        let right = knots[span + r + 1] - u;
        let left = u - knots[span + 1 + r - degree];
        let temp = values[r] / (right + left);
        derivatives[r] = p * (previous - temp);
        values[r] = saved + right * temp;
        saved = left * temp;
        previous = temp;
    }
    values[degree] = saved;
    derivatives[degree] = p * previous;
}

/// Evaluates the non-zero basis functions and their derivatives up to `derivative_order` at `u` in
/// span `span` (Piegl & Tiller A2.3) into `out`, row-major: `out[k * (degree + 1) + j]` is the
/// `k`-th derivative of `N_(span − degree + j), degree` (`k = 0` the values). Derivatives of order
/// above `degree` are zero.
///
/// Scratch lives on the stack (`(MAX_DEGREE + 1)²` floats), nothing is allocated.
///
/// # Panics
/// If `out.len() < (derivative_order + 1) * (degree + 1)`, `degree > MAX_DEGREE`, or `span` is not
/// a valid span of `knots`.
pub fn basis_function_derivatives(
    knots: &[f32],
    degree: usize,
    span: usize,
    u: f32,
    derivative_order: usize,
    out: &mut [f32],
) {
    assert!(degree <= MAX_DEGREE, "degree {degree} > MAX_DEGREE");
    let p = degree;
    let row = p + 1;
    // ndu[j][r] (r < j): knot differences U_(s+r+1) − U_(s+1+r−j); ndu[r][j] (r ≤ j): N_(s−j+r),j.
    let mut ndu = [[0.0f32; MAX_DEGREE + 1]; MAX_DEGREE + 1];
    let mut left = [0.0f32; MAX_DEGREE + 1];
    let mut right = [0.0f32; MAX_DEGREE + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for j in 0..=p {
        out[j] = ndu[j][p];
    }
    let top_order = derivative_order.min(p);
    // a[s][·]: the coefficients of the two most recent derivative orders (A2.3).
    let mut a = [[0.0f32; MAX_DEGREE + 1]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0, 1);
        a[0][0] = 1.0;
        for k in 1..=top_order {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if rk >= 0 {
                let rk = rk as usize;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r <= pk + 1 { k - 1 } else { p - r };
            for j in j1..=j2 {
                let index = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][index];
                d += a[s2][j] * ndu[index][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            out[k * row + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    // Multiply by p! / (p − k)!.
    let mut factor = p as f32;
    for k in 1..=top_order {
        for value in &mut out[k * row..(k + 1) * row] {
            *value *= factor;
        }
        factor *= (p - k) as f32;
    }
    for k in top_order + 1..=derivative_order {
        out[k * row..(k + 1) * row].fill(0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::KnotVector;
    use crate::nurbs::test_support::{reference_basis, reference_basis_derivative};

    /// Parameters spread over the domain, including both ends and every knot.
    fn parameters(knots: &KnotVector) -> Vec<f32> {
        let (low, high) = knots.domain();
        let mut us: Vec<f32> = (0..=97)
            .map(|k| low + (high - low) * k as f32 / 97.0)
            .collect();
        us.extend(
            knots
                .values()
                .iter()
                .copied()
                .filter(|k| (low..high).contains(k)),
        );
        us
    }

    fn knot_vectors() -> Vec<KnotVector> {
        let mut all = Vec::new();
        for degree in 1..=5 {
            for count in [degree + 1, degree + 3, 11] {
                all.push(KnotVector::clamped_uniform(count, degree).unwrap());
                all.push(KnotVector::periodic_uniform(count, degree).unwrap());
            }
        }
        // A non-uniform, partly repeated, unclamped vector: degree 2, 6 control points.
        all.push(
            KnotVector::from_values(vec![-0.5, 0.0, 0.1, 0.1, 0.4, 0.9, 1.0, 1.0, 1.3], 2, 6)
                .unwrap(),
        );
        all
    }

    #[test]
    fn partition_of_unity_and_zero_derivative_sum() {
        // Σ_j N_j,p(u) = 1 and Σ_j N'_j,p(u) = d/du 1 = 0. Each value is in [0, 1]; f32 roundoff of
        // the p-level recursion stays within a few ulp per level: 1e-5 covers p ≤ 5 with margin.
        // Derivatives have magnitude up to ~p / (min knot spacing), so their sum is checked
        // relative to Σ|N'_j|.
        for knots in knot_vectors() {
            let p = knots.degree();
            let mut values = [0.0; MAX_DEGREE + 1];
            let mut derivatives = [0.0; MAX_DEGREE + 1];
            for u in parameters(&knots) {
                let span = knots.basis_and_derivatives(u, &mut values, &mut derivatives);
                let sum: f32 = values[..=p].iter().sum();
                assert!((sum - 1.0).abs() <= 1e-5, "p={p} u={u} sum={sum}");
                assert!(
                    values[..=p]
                        .iter()
                        .all(|&n| (-1e-7..=1.0 + 1e-6).contains(&n))
                );
                let derivative_sum: f32 = derivatives[..=p].iter().sum();
                let scale: f32 = derivatives[..=p].iter().map(|d| d.abs()).sum();
                assert!(
                    derivative_sum.abs() <= 1e-5 * scale.max(1.0),
                    "p={p} u={u} span={span} Σ={derivative_sum}"
                );
            }
        }
    }

    #[test]
    fn basis_matches_the_cox_de_boor_recursion() {
        // Reference: the recursive definition N_i,0 = [U_i ≤ u < U_i+1],
        // N_i,p = (u − U_i)/(U_i+p − U_i) N_i,p−1 + (U_i+p+1 − u)/(U_i+p+1 − U_i+1) N_i+1,p−1,
        // and N'_i,p from eq. 2.7, both in f64 on the same span. Tolerance: f32 roundoff, 1e-5
        // absolute for values in [0, 1], relative to p / (min span) for derivatives.
        for knots in knot_vectors() {
            let p = knots.degree();
            let knots64: Vec<f64> = knots.values().iter().map(|&k| k as f64).collect();
            let mut values = [0.0; MAX_DEGREE + 1];
            let mut derivatives = [0.0; MAX_DEGREE + 1];
            for u in parameters(&knots) {
                let span = knots.basis_and_derivatives(u, &mut values, &mut derivatives);
                let u = knots.parameter_in_domain(u);
                for j in 0..=p {
                    let i = span - p + j;
                    let n = reference_basis(&knots64, i, p, u as f64, span);
                    let d = reference_basis_derivative(&knots64, i, p, u as f64, span);
                    assert!((values[j] as f64 - n).abs() <= 1e-5, "N p={p} i={i} u={u}");
                    assert!(
                        (derivatives[j] as f64 - d).abs() <= 1e-5 * (1.0 + d.abs()) * p as f64,
                        "N' p={p} i={i} u={u}: {} vs {d}",
                        derivatives[j]
                    );
                }
            }
        }
    }

    #[test]
    fn a2_3_agrees_with_the_first_derivative_path_and_finite_differences() {
        // k = 0, 1 rows of A2.3 must equal basis_functions_and_derivatives (same maths, different
        // arithmetic order: f32 roundoff, 1e-5 relative). The k = 2 row is checked against the
        // central difference of the k = 1 row: (N'(u+h) − N'(u−h)) / 2h = N'' + O(h²) within a
        // span (N'' is linear in u there for p = 3, so the difference is exact up to roundoff
        // ≈ ε·max|N'|/h). h = 1e-3, points kept ≥ 2h from knots.
        let knots = KnotVector::from_values(
            vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.45, 0.7, 1.0, 1.0, 1.0, 1.0],
            3,
            7,
        )
        .unwrap();
        let p = 3;
        let h = 1e-3f32;
        let mut out = [0.0f32; 4 * 4];
        let mut values = [0.0f32; 4];
        let mut first = [0.0f32; 4];
        let mut plus = [0.0f32; 4];
        let mut minus = [0.0f32; 4];
        let mut scratch = [0.0f32; 4];
        for k in 0..=200 {
            let u = k as f32 / 200.0;
            let span = knots.find_span(u);
            basis_function_derivatives(knots.values(), p, span, u, 3, &mut out);
            basis_functions_and_derivatives(knots.values(), p, span, u, &mut values, &mut first);
            for j in 0..=p {
                assert!((out[j] - values[j]).abs() <= 1e-5);
                assert!((out[4 + j] - first[j]).abs() <= 1e-5 * (1.0 + first[j].abs()));
            }
            let near_knot = knots.values().iter().any(|&t| (u - t).abs() < 2.0 * h);
            if near_knot {
                continue;
            }
            basis_functions_and_derivatives(
                knots.values(),
                p,
                span,
                u + h,
                &mut scratch,
                &mut plus,
            );
            basis_functions_and_derivatives(
                knots.values(),
                p,
                span,
                u - h,
                &mut scratch,
                &mut minus,
            );
            for j in 0..=p {
                let central = (plus[j] - minus[j]) / (2.0 * h);
                let max_first = 3.0 / 0.2; // p / (shortest span)
                let tolerance = 4.0 * f32::EPSILON * max_first / h + 1e-4 * out[8 + j].abs();
                assert!(
                    (central - out[8 + j]).abs() <= tolerance,
                    "u={u} j={j}: {central} vs {}",
                    out[8 + j]
                );
            }
        }
    }

    #[test]
    fn a2_3_third_derivative_of_a_cubic_bezier_is_constant() {
        // Bernstein cubic on [0, 1]: B_0 = (1−u)³ so B_0''' = −6, B_1 = 3u(1−u)² → 18,
        // B_2 = 3u²(1−u) → −18, B_3 = u³ → 6; the fourth derivatives are zero.
        let knots = KnotVector::clamped_uniform(4, 3).unwrap();
        let mut out = [1.0f32; 5 * 4];
        basis_function_derivatives(knots.values(), 3, 3, 0.37, 4, &mut out);
        let expected = [-6.0, 18.0, -18.0, 6.0];
        for j in 0..4 {
            assert!((out[12 + j] - expected[j]).abs() <= 1e-4);
            assert_eq!(out[16 + j], 0.0);
        }
    }
}
