//! Knot vectors of B-splines (clamped, periodic or given), their parameter domain and the span search.

use crate::error::{HairError, Result};

use super::MAX_DEGREE;
use super::basis::{basis_functions, basis_functions_and_derivatives};

/// A validated, non-decreasing knot vector for `control_point_count` control points of degree
/// `degree`.
///
/// - Open (clamped or given): `values` has `control_point_count + degree + 1` knots `U₀ ≤ U₁ ≤ …`,
///   the domain is `[U_p, U_n]` (`n` = control point count) and control point `i` multiplies basis
///   function `Nᵢ,ₚ`.
/// - Periodic ([`KnotVector::periodic_uniform`]): `values` is the knot vector of the unrolled curve,
///   `n + 2p + 1` uniform knots `Uᵢ = (i − p) / n`; basis function `N_j,ₚ` (`j < n + p`) multiplies
///   control point `j mod n`, the domain is `[0, 1)` and parameters wrap around it.
///
/// Parameters are dimensionless. Every knot is finite, and no knot is repeated more than
/// `degree + 1` times, so every basis function has a non-empty support.
#[derive(Debug, Clone, PartialEq)]
pub struct KnotVector {
    degree: usize,
    values: Vec<f32>,
    control_point_count: usize,
    periodic: bool,
}

/// Checks `1 ≤ degree ≤ MAX_DEGREE` and `control_point_count ≥ degree + 1`.
fn check_degree_and_count(degree: usize, control_point_count: usize) -> Result<()> {
    if degree == 0 || degree > MAX_DEGREE {
        return Err(HairError::invalid(
            "degree",
            degree,
            "an integer in 1..=9 (MAX_DEGREE)",
        ));
    }
    if control_point_count < degree + 1 {
        return Err(HairError::invalid(
            "control_point_count",
            control_point_count,
            "at least degree + 1",
        ));
    }
    Ok(())
}

impl KnotVector {
    /// The clamped uniform knot vector on `[0, 1]`: `degree + 1` zeros, the interior knots
    /// `k / (n − p)` for `k = 1..n − p`, then `degree + 1` ones (`n` = `control_point_count`,
    /// `p` = `degree`). A curve over it starts at its first control point and ends at its last.
    ///
    /// Errors: `degree` outside `1..=MAX_DEGREE`, fewer than `degree + 1` control points.
    pub fn clamped_uniform(control_point_count: usize, degree: usize) -> Result<KnotVector> {
        check_degree_and_count(degree, control_point_count)?;
        let spans = control_point_count - degree;
        let mut values = Vec::with_capacity(control_point_count + degree + 1);
        values.extend(std::iter::repeat_n(0.0, degree + 1));
        values.extend((1..spans).map(|k| k as f32 / spans as f32));
        values.extend(std::iter::repeat_n(1.0, degree + 1));
        Ok(KnotVector {
            degree,
            values,
            control_point_count,
            periodic: false,
        })
    }

    /// The periodic uniform knot vector of a closed curve with `control_point_count` control points:
    /// `Uᵢ = (i − p) / n` for `i = 0..=n + 2p`, domain `[0, 1)`. Evaluation wraps control indices
    /// modulo `n`, so the curve is closed and `C^(p−1)` everywhere, with `n` spans of length `1 / n`.
    ///
    /// Errors: `degree` outside `1..=MAX_DEGREE`, fewer than `degree + 1` control points.
    pub fn periodic_uniform(control_point_count: usize, degree: usize) -> Result<KnotVector> {
        check_degree_and_count(degree, control_point_count)?;
        let n = control_point_count as f32;
        let values = (0..control_point_count + 2 * degree + 1)
            .map(|i| (i as f32 - degree as f32) / n)
            .collect();
        Ok(KnotVector {
            degree,
            values,
            control_point_count,
            periodic: true,
        })
    }

    /// An open knot vector from explicit `values` (clamped or not, uniform or not).
    ///
    /// Errors: `degree` outside `1..=MAX_DEGREE`; fewer than `degree + 1` control points;
    /// `values.len() != control_point_count + degree + 1` (size mismatch); a non-finite knot;
    /// a decreasing pair; a knot repeated more than `degree + 1` times; an empty domain
    /// (`U_p == U_n`).
    pub fn from_values(
        values: Vec<f32>,
        degree: usize,
        control_point_count: usize,
    ) -> Result<KnotVector> {
        check_degree_and_count(degree, control_point_count)?;
        let expected = control_point_count + degree + 1;
        if values.len() != expected {
            return Err(HairError::SizeMismatch {
                what: "knot_values",
                actual: values.len(),
                expected,
            });
        }
        if let Some(bad) = values.iter().find(|k| !k.is_finite()) {
            return Err(HairError::invalid("knot_values", bad, "finite numbers"));
        }
        if let Some(i) = values.windows(2).position(|pair| pair[1] < pair[0]) {
            return Err(HairError::invalid(
                "knot_values",
                format!("{} after {} at index {}", values[i + 1], values[i], i + 1),
                "a non-decreasing sequence",
            ));
        }
        let mut run_start = 0;
        for i in 1..=values.len() {
            if i == values.len() || values[i] != values[run_start] {
                if i - run_start > degree + 1 {
                    return Err(HairError::invalid(
                        "knot_values",
                        format!("{} repeated {} times", values[run_start], i - run_start),
                        "each knot repeated at most degree + 1 times",
                    ));
                }
                run_start = i;
            }
        }
        if values[degree] >= values[control_point_count] {
            return Err(HairError::invalid(
                "knot_values",
                format!(
                    "domain [{}, {}]",
                    values[degree], values[control_point_count]
                ),
                "a non-empty domain U[degree] < U[control_point_count]",
            ));
        }
        Ok(KnotVector {
            degree,
            values,
            control_point_count,
            periodic: false,
        })
    }

    /// The polynomial degree `p` (order `p + 1`).
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots (dimensionless); for a periodic vector, those of the unrolled curve (see the type).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The number of distinct control points `n` this knot vector is made for.
    pub fn control_point_count(&self) -> usize {
        self.control_point_count
    }

    /// The number of basis functions: `n` when open, `n + p` when periodic (unrolled).
    pub fn basis_function_count(&self) -> usize {
        self.values.len() - self.degree - 1
    }

    /// Whether this is a periodic (closed) knot vector.
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// The parameter domain `(U_p, U_m)`, `m` = [`basis_function_count`](Self::basis_function_count);
    /// `(0, 1)` for the uniform constructors. Periodic domains are half-open: `1` is `0` again.
    pub fn domain(&self) -> (f32, f32) {
        (
            self.values[self.degree],
            self.values[self.basis_function_count()],
        )
    }

    /// `u` brought into the domain: clamped for an open knot vector, wrapped (modulo the domain
    /// length) for a periodic one. A NaN becomes the domain start, so evaluation never yields NaN
    /// from a NaN parameter.
    pub fn parameter_in_domain(&self, u: f32) -> f32 {
        let (low, high) = self.domain();
        if u.is_nan() {
            return low;
        }
        if self.periodic {
            if (low..high).contains(&u) {
                u
            } else if u.is_finite() {
                // rem_euclid may round up to exactly `high` for tiny negative offsets; that is the
                // same point of the closed curve, and `find_span` handles it as the last span's end.
                low + (u - low).rem_euclid(high - low)
            } else {
                low
            }
        } else {
            u.clamp(low, high)
        }
    }

    /// The knot span index `s` with `U_s ≤ u < U_(s+1)` (Piegl & Tiller, *The NURBS Book*, A2.1),
    /// in `degree..basis_function_count()`, after bringing `u` into the domain with
    /// [`parameter_in_domain`](Self::parameter_in_domain). At the end of the domain the last
    /// non-empty span is returned, so the curve there is the limit from the left.
    pub fn find_span(&self, u: f32) -> usize {
        let u = self.parameter_in_domain(u);
        let p = self.degree;
        let m = self.basis_function_count();
        // Knots U_(p+1)..U_(m-1) that are <= u: the span is p plus their number (binary search).
        let mut span = p + self.values[p + 1..m].partition_point(|&knot| knot <= u);
        // At u == U_m with repeated knots below it, step back to a span of non-zero length.
        while span > p && self.values[span] >= self.values[span + 1] {
            span -= 1;
        }
        span
    }

    /// The control point multiplied by the `j`-th non-zero basis function of span `span`
    /// (`j` in `0..=degree`): `(span − p + j) mod n`.
    #[inline]
    pub fn control_index(&self, span: usize, j: usize) -> usize {
        let index = span - self.degree + j;
        if index >= self.control_point_count {
            index - self.control_point_count
        } else {
            index
        }
    }

    /// Evaluates the `degree + 1` non-zero basis functions at `u` into `values[..=degree]` and
    /// returns the span (see [`basis_functions`]).
    ///
    /// # Panics
    /// If `values` is shorter than `degree + 1`.
    pub fn basis(&self, u: f32, values: &mut [f32]) -> usize {
        let u = self.parameter_in_domain(u);
        let span = self.find_span(u);
        basis_functions(&self.values, self.degree, span, u, values);
        span
    }

    /// Evaluates the non-zero basis functions and their first derivatives `dN/du` at `u` into
    /// `values[..=degree]` and `derivatives[..=degree]`, and returns the span (see
    /// [`basis_functions_and_derivatives`]).
    ///
    /// # Panics
    /// If either slice is shorter than `degree + 1`.
    pub fn basis_and_derivatives(
        &self,
        u: f32,
        values: &mut [f32],
        derivatives: &mut [f32],
    ) -> usize {
        let u = self.parameter_in_domain(u);
        let span = self.find_span(u);
        basis_functions_and_derivatives(&self.values, self.degree, span, u, values, derivatives);
        span
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamped_uniform_repeats_end_knots() {
        // n = 6, p = 3: 4 zeros, interior 1/3, 2/3, 4 ones (n + p + 1 = 10 knots).
        let knots = KnotVector::clamped_uniform(6, 3).unwrap();
        let third = 1.0 / 3.0;
        let expected = [0.0, 0.0, 0.0, 0.0, third, 2.0 * third, 1.0, 1.0, 1.0, 1.0];
        assert_eq!(knots.values().len(), expected.len());
        for (a, b) in knots.values().iter().zip(expected) {
            assert!((a - b).abs() <= f32::EPSILON);
        }
        assert_eq!(knots.domain(), (0.0, 1.0));
        assert!(!knots.is_periodic());
    }

    #[test]
    fn periodic_uniform_unrolls_the_knots() {
        // n = 4, p = 3: U_i = (i - 3) / 4 for i = 0..=10; domain [U_3, U_7] = [0, 1].
        let knots = KnotVector::periodic_uniform(4, 3).unwrap();
        assert_eq!(knots.values().len(), 4 + 2 * 3 + 1);
        for (i, &k) in knots.values().iter().enumerate() {
            assert_eq!(k, (i as f32 - 3.0) / 4.0);
        }
        assert_eq!(knots.domain(), (0.0, 1.0));
        assert_eq!(knots.basis_function_count(), 7);
        // span 6 (the last), j = 3 -> control index 6 mod 4 = 2... 6 - 3 + 3 = 6 -> 2.
        assert_eq!(knots.control_index(6, 3), 2);
        assert_eq!(knots.control_index(3, 0), 0);
    }

    #[test]
    fn find_span_brackets_the_parameter() {
        let knots = KnotVector::clamped_uniform(7, 3).unwrap();
        let values = knots.values().to_vec();
        for k in 0..=200 {
            let u = k as f32 / 200.0;
            let span = knots.find_span(u);
            assert!((3..7).contains(&span));
            assert!(values[span] <= u);
            assert!(u < values[span + 1] || (u == 1.0 && span == 6));
        }
        // Outside the domain the parameter is clamped.
        assert_eq!(knots.find_span(-5.0), 3);
        assert_eq!(knots.find_span(7.0), 6);
        assert_eq!(knots.find_span(f32::NAN), 3);
        assert_eq!(knots.parameter_in_domain(f32::INFINITY), 1.0);
    }

    #[test]
    fn periodic_parameters_wrap() {
        let knots = KnotVector::periodic_uniform(5, 2).unwrap();
        assert_eq!(knots.parameter_in_domain(1.25), 0.25);
        assert_eq!(knots.parameter_in_domain(-0.75), 0.25);
        assert_eq!(knots.parameter_in_domain(f32::NEG_INFINITY), 0.0);
        // u = 0.25 lies in [1/5, 2/5): span p + 1 = 3.
        assert_eq!(knots.find_span(1.25), 3);
    }

    #[test]
    fn end_span_skips_repeated_interior_knots() {
        // p = 1, n = 3: knots 0, 0.5, 1, 1, 2; domain [U_1, U_3] = [0.5, 1] and U_2 = U_3 = 1.
        let knots = KnotVector::from_values(vec![0.0, 0.5, 1.0, 1.0, 2.0], 1, 3).unwrap();
        assert_eq!(knots.domain(), (0.5, 1.0));
        assert_eq!(knots.find_span(1.0), 1);
    }

    #[test]
    fn bad_knot_vectors_are_rejected() {
        let name = |result: Result<KnotVector>| match result.unwrap_err() {
            HairError::InvalidParameter { name, .. } => name,
            HairError::SizeMismatch { what, .. } => what,
            other => panic!("unexpected error {other}"),
        };
        assert_eq!(name(KnotVector::clamped_uniform(4, 0)), "degree");
        assert_eq!(name(KnotVector::clamped_uniform(20, 10)), "degree");
        assert_eq!(
            name(KnotVector::clamped_uniform(3, 3)),
            "control_point_count"
        );
        assert_eq!(
            name(KnotVector::periodic_uniform(2, 2)),
            "control_point_count"
        );
        let values = |v: &[f32]| v.to_vec();
        assert_eq!(
            name(KnotVector::from_values(values(&[0.0, 0.0, 1.0]), 1, 2)),
            "knot_values"
        );
        assert_eq!(
            name(KnotVector::from_values(
                values(&[0.0, 0.0, 0.7, 0.5, 1.0, 1.0]),
                1,
                4
            )),
            "knot_values"
        );
        assert_eq!(
            name(KnotVector::from_values(
                values(&[0.0, 0.0, f32::NAN, 1.0, 1.0]),
                1,
                3
            )),
            "knot_values"
        );
        assert_eq!(
            name(KnotVector::from_values(
                values(&[0.0, 0.5, 0.5, 0.5, 1.0, 1.0]),
                1,
                4
            )),
            "knot_values"
        );
        assert_eq!(
            name(KnotVector::from_values(values(&[0.0, 0.0, 0.0, 1.0]), 1, 2)),
            "knot_values"
        );
        assert!(KnotVector::from_values(values(&[0.0, 0.0, 0.5, 1.0, 1.0]), 1, 3).is_ok());
    }
}
