//! NURBS curves: control points, weights and a knot vector; points and first derivatives, rational or not.

use glam::{Vec3, Vec4};

use crate::error::{HairError, Result};

use super::MAX_DEGREE;
use super::knots::KnotVector;

/// A (rational) B-spline curve `C(u) = Σ Nᵢ,ₚ(u) wᵢ Pᵢ / Σ Nᵢ,ₚ(u) wᵢ` in 3D.
///
/// Open curves use a clamped or given knot vector; closed curves a periodic one (see
/// [`KnotVector`]). Control points are in metres, weights dimensionless, finite and `> 0`; all
/// weights `1` make a polynomial B-spline (evaluated without the division). The field invariants
/// (one control point and one weight per knot-vector control point, all finite) are kept by the
/// constructors and setters, so evaluation cannot fail.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsCurve {
    knots: KnotVector,
    control_points: Vec<Vec3>,
    weights: Vec<f32>,
    rational: bool,
}

/// Checks that every control point is finite.
pub(super) fn check_points(name: &'static str, points: &[Vec3]) -> Result<()> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(i) => Err(HairError::invalid(
            name,
            format!("{} at index {i}", points[i]),
            "finite coordinates [m]",
        )),
        None => Ok(()),
    }
}

/// Checks that there are `expected` weights, all finite and `> 0`; returns whether any is not 1.
pub(super) fn check_weights(weights: &[f32], expected: usize) -> Result<bool> {
    if weights.len() != expected {
        return Err(HairError::SizeMismatch {
            what: "weights",
            actual: weights.len(),
            expected,
        });
    }
    if let Some(i) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(HairError::invalid(
            "weights",
            format!("{} at index {i}", weights[i]),
            "finite numbers > 0",
        ));
    }
    Ok(weights.iter().any(|&w| w != 1.0))
}

impl NurbsCurve {
    /// A polynomial B-spline curve (all weights 1) over `knots`, with
    /// `knots.control_point_count()` control points [m].
    ///
    /// Errors: a wrong number of control points (size mismatch), a non-finite coordinate.
    pub fn new(knots: KnotVector, control_points: Vec<Vec3>) -> Result<NurbsCurve> {
        let expected = knots.control_point_count();
        if control_points.len() != expected {
            return Err(HairError::SizeMismatch {
                what: "control_points",
                actual: control_points.len(),
                expected,
            });
        }
        check_points("control_points", &control_points)?;
        Ok(NurbsCurve {
            knots,
            weights: vec![1.0; expected],
            control_points,
            rational: false,
        })
    }

    /// An open curve of degree `degree` on the clamped uniform knot vector over `[0, 1]`: it starts
    /// at the first control point and ends at the last, tangent to the control polygon there.
    /// Use [`DEFAULT_DEGREE`](super::DEFAULT_DEGREE) (cubic) unless there is a reason not to.
    ///
    /// Errors: `degree` outside `1..=MAX_DEGREE`, fewer than `degree + 1` points, a non-finite point.
    pub fn clamped(control_points: Vec<Vec3>, degree: usize) -> Result<NurbsCurve> {
        let knots = KnotVector::clamped_uniform(control_points.len(), degree)?;
        NurbsCurve::new(knots, control_points)
    }

    /// A closed curve of degree `degree` on the periodic uniform knot vector (domain `[0, 1)`): the
    /// control polygon is closed implicitly (do not repeat the first point), the curve is
    /// `C^(degree−1)` everywhere, seam included.
    ///
    /// Errors: `degree` outside `1..=MAX_DEGREE`, fewer than `degree + 1` points, a non-finite point.
    pub fn periodic(control_points: Vec<Vec3>, degree: usize) -> Result<NurbsCurve> {
        let knots = KnotVector::periodic_uniform(control_points.len(), degree)?;
        NurbsCurve::new(knots, control_points)
    }

    /// The same curve with the given weights (dimensionless, one per control point), making it
    /// rational unless all are 1.
    ///
    /// Errors: a wrong number of weights (size mismatch), a weight that is not finite and `> 0`.
    pub fn with_weights(mut self, weights: Vec<f32>) -> Result<NurbsCurve> {
        self.rational = check_weights(&weights, self.control_points.len())?;
        self.weights = weights;
        Ok(self)
    }

    /// The exact full circle of radius `radius` [m] around `center` [m] in the plane orthogonal to
    /// `normal`, counter-clockwise seen from the side `normal` points to: the rational quadratic with
    /// 9 control points (the corners and edge midpoints of the circumscribed square, the first one
    /// repeated at the end), weights `1, √2/2, 1, √2/2, …, 1` and knots
    /// `0, 0, 0, ¼, ¼, ½, ½, ¾, ¾, 1, 1, 1`. It starts at `center + radius · e₁` with
    /// `e₁ = normal.any_orthonormal_vector()`; `u = k/4` is a quarter turn `k`.
    ///
    /// Errors: `radius` not finite and `> 0`; `center` not finite; `normal` zero or not finite.
    pub fn circle(center: Vec3, radius: f32, normal: Vec3) -> Result<NurbsCurve> {
        crate::error::require_positive("radius", radius)?;
        check_points("center", &[center])?;
        let normal = normal
            .try_normalize()
            .ok_or_else(|| HairError::invalid("normal", normal, "a finite non-zero vector"))?;
        let e1 = normal.any_orthonormal_vector() * radius;
        let e2 = normal.cross(e1);
        let corners = [e1, e1 + e2, e2, e2 - e1, -e1, -e1 - e2, -e2, e1 - e2, e1];
        let control_points = corners.iter().map(|&offset| center + offset).collect();
        let diagonal = std::f32::consts::FRAC_1_SQRT_2;
        let weights = (0..9)
            .map(|i| if i % 2 == 0 { 1.0 } else { diagonal })
            .collect();
        let knots = KnotVector::from_values(
            vec![
                0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
            ],
            2,
            9,
        )?;
        NurbsCurve::new(knots, control_points)?.with_weights(weights)
    }

    /// The polynomial degree.
    pub fn degree(&self) -> usize {
        self.knots.degree()
    }

    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// The control points [m].
    pub fn control_points(&self) -> &[Vec3] {
        &self.control_points
    }

    /// The weights (dimensionless, `> 0`), one per control point.
    pub fn weights(&self) -> &[f32] {
        &self.weights
    }

    /// Whether the curve is closed by its periodic knot vector. A clamped curve whose ends meet
    /// (like [`NurbsCurve::circle`]) is geometrically closed but reports `false`.
    pub fn is_closed(&self) -> bool {
        self.knots.is_periodic()
    }

    /// Whether some weight differs from 1.
    pub fn is_rational(&self) -> bool {
        self.rational
    }

    /// The parameter domain (see [`KnotVector::domain`]).
    pub fn domain(&self) -> (f32, f32) {
        self.knots.domain()
    }

    /// Replaces the control points [m] (the D-NURBS generalized coordinates at a new time).
    ///
    /// Errors: a different number of points (size mismatch), a non-finite coordinate; the curve is
    /// left unchanged then.
    pub fn set_control_points(&mut self, control_points: &[Vec3]) -> Result<()> {
        if control_points.len() != self.control_points.len() {
            return Err(HairError::SizeMismatch {
                what: "control_points",
                actual: control_points.len(),
                expected: self.control_points.len(),
            });
        }
        check_points("control_points", control_points)?;
        self.control_points.copy_from_slice(control_points);
        Ok(())
    }

    /// Replaces the weights. Errors as for [`NurbsCurve::with_weights`]; unchanged on error.
    pub fn set_weights(&mut self, weights: &[f32]) -> Result<()> {
        self.rational = check_weights(weights, self.weights.len())?;
        self.weights.copy_from_slice(weights);
        Ok(())
    }

    /// The point `C(u)` [m]; `u` is clamped into the domain (open) or wrapped (closed).
    pub fn point(&self, u: f32) -> Vec3 {
        let mut values = [0.0; MAX_DEGREE + 1];
        let span = self.knots.basis(u, &mut values);
        let mut sum = Vec4::ZERO;
        for (j, &n) in values[..=self.degree()].iter().enumerate() {
            sum += n * self.homogeneous(self.knots.control_index(span, j));
        }
        if self.rational {
            sum.truncate() / sum.w
        } else {
            sum.truncate()
        }
    }

    /// The point `C(u)` [m] and the derivative `dC/du` [m per unit parameter]. For a rational curve
    /// `C′ = (A′ − w′ C) / w` with `A = Σ Nᵢ wᵢ Pᵢ`, `w = Σ Nᵢ wᵢ`. At a knot of multiplicity
    /// `degree` (a corner) the derivative is the one of the span to the right (left at the end).
    pub fn point_and_derivative(&self, u: f32) -> (Vec3, Vec3) {
        let mut values = [0.0; MAX_DEGREE + 1];
        let mut derivatives = [0.0; MAX_DEGREE + 1];
        let span = self
            .knots
            .basis_and_derivatives(u, &mut values, &mut derivatives);
        let mut sum = Vec4::ZERO;
        let mut derivative_sum = Vec4::ZERO;
        for j in 0..=self.degree() {
            let homogeneous = self.homogeneous(self.knots.control_index(span, j));
            sum += values[j] * homogeneous;
            derivative_sum += derivatives[j] * homogeneous;
        }
        if self.rational {
            let point = sum.truncate() / sum.w;
            let derivative = (derivative_sum.truncate() - derivative_sum.w * point) / sum.w;
            (point, derivative)
        } else {
            (sum.truncate(), derivative_sum.truncate())
        }
    }

    /// Control point `i` in homogeneous form `(wᵢ Pᵢ, wᵢ)`; `(Pᵢ, 1)` for a polynomial curve.
    #[inline]
    fn homogeneous(&self, i: usize) -> Vec4 {
        let w = self.weights[i];
        (self.control_points[i] * w).extend(w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::DEFAULT_DEGREE;
    use crate::nurbs::test_support::central_difference_tolerance;

    /// The polyline through `points`, at parameter `u` with uniform vertex parameters `i / (n − 1)`.
    fn polyline(points: &[Vec3], u: f32) -> Vec3 {
        let segments = (points.len() - 1) as f32;
        let x = (u * segments).min(segments - 1e-6);
        let i = x.floor() as usize;
        points[i].lerp(points[i + 1], x - i as f32)
    }

    fn wiggly_points(count: usize) -> Vec<Vec3> {
        (0..count)
            .map(|i| {
                let t = i as f32;
                Vec3::new((0.7 * t).sin(), 0.3 * t - 1.0, (1.3 * t).cos() * 0.5)
            })
            .collect()
    }

    #[test]
    fn circle_points_are_at_the_radius_with_perpendicular_tangents() {
        // |C(u) − c| = r exactly (rational quadratic conic) and C′·(C − c) = 0 (a circle's tangent
        // is perpendicular to its radius). Moreover, on each quarter u ∈ [k/4, (k+1)/4] with
        // local t = 4u − k and α = π/4, the angle is θ = kπ/2 + α + 2 atan(tan(α/2)(2t − 1)), so
        // |C′| = r · dθ/du = r · 16 tan(α/2) / (1 + tan²(α/2)(2t − 1)²). f32 tolerance 1e-5
        // relative (a handful of roundings of magnitude r).
        let center = Vec3::new(0.3, -1.2, 2.0);
        let radius = 0.75;
        let normal = Vec3::new(1.0, 2.0, -0.5);
        let circle = NurbsCurve::circle(center, radius, normal).unwrap();
        let axis = normal.normalize();
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        let k = (std::f32::consts::PI / 8.0).tan();
        for step in 0..=400 {
            let u = step as f32 / 400.0;
            let (point, derivative) = circle.point_and_derivative(u);
            let offset = point - center;
            assert!((offset.length() - radius).abs() <= 1e-5 * radius, "u={u}");
            assert!(offset.dot(axis).abs() <= 1e-5 * radius);
            let quarter = ((4.0 * u).floor() as i32).min(3);
            let t = 4.0 * u - quarter as f32;
            let s = 2.0 * t - 1.0;
            let theta = quarter as f32 * std::f32::consts::FRAC_PI_2
                + std::f32::consts::FRAC_PI_4
                + 2.0 * (k * s).atan();
            let expected = center + radius * (theta.cos() * e1 + theta.sin() * e2);
            assert!((point - expected).length() <= 1e-5 * radius, "u={u}");
            let speed = radius * 16.0 * k / (1.0 + k * k * s * s);
            let expected_derivative = speed * axis.cross(offset / radius);
            assert!(
                (derivative - expected_derivative).length() <= 1e-5 * speed,
                "u={u}: {derivative} vs {expected_derivative}"
            );
            assert!(derivative.dot(offset).abs() <= 1e-5 * speed * radius);
        }
        // Quarter turns land on the axes: u = 1/4 → c + r e₂ (counter-clockwise about normal).
        assert!((circle.point(0.25) - (center + radius * e2)).length() <= 1e-5 * radius);
        assert!((circle.point(1.0) - circle.point(0.0)).length() <= 1e-5 * radius);
    }

    #[test]
    fn clamped_curves_interpolate_their_end_points() {
        // With p + 1 repeated end knots, N_0,p(0) = 1 and N_n−1,p(1) = 1, so C(0) = P_0 and
        // C(1) = P_n−1 exactly (every other product is 0·P); C′(0) = p/(U_p+1 − U_1)(P_1 − P_0).
        for degree in 1..=5 {
            let points = wiggly_points(degree + 4);
            let curve = NurbsCurve::clamped(points.clone(), degree).unwrap();
            assert_eq!(curve.point(0.0), points[0]);
            assert_eq!(curve.point(1.0), *points.last().unwrap());
            let (_, start_derivative) = curve.point_and_derivative(0.0);
            let first_span = curve.knots().values()[degree + 1];
            let expected = degree as f32 / first_span * (points[1] - points[0]);
            assert!((start_derivative - expected).length() <= 1e-5 * expected.length());
        }
    }

    #[test]
    fn a_degree_one_curve_is_the_polyline() {
        // Degree 1 on clamped uniform knots: N_i,1 are the hat functions centred at u = i/(n−1),
        // so C(u) = (1 − λ) P_i + λ P_i+1 with λ = u(n−1) − i, and C′ = (n−1)(P_i+1 − P_i).
        let points = wiggly_points(6);
        let curve = NurbsCurve::clamped(points.clone(), 1).unwrap();
        for step in 0..=100 {
            let u = step as f32 / 100.0;
            let (point, derivative) = curve.point_and_derivative(u);
            assert!((point - polyline(&points, u)).length() <= 1e-5);
            let i = ((u * 5.0).floor() as usize).min(4);
            let expected = 5.0 * (points[i + 1] - points[i]);
            assert!((derivative - expected).length() <= 1e-5 * expected.length());
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        // (C(u+h) − C(u−h)) / 2h = C′(u) + h²C‴/6 + roundoff; h = 1e-3.
        // Polynomial cubic, 7 control points |P| ≤ 1.5, knot spacing Δ = 1/4: C‴ has control
        // points p(p−1)(p−2)·(third differences of P)/Δ³, so |C‴| ≤ 6·8·1.5·64 = 4608.
        let h = 1e-3;
        let points = wiggly_points(7);
        let cubic = NurbsCurve::clamped(points, DEFAULT_DEGREE).unwrap();
        let tolerance = central_difference_tolerance(h, 4608.0, 1.5);
        // Rational: the circle of radius 1 about the origin, |C‴| ≤ 450 r (from θ(u) above:
        // max over u of |θ‴ − θ′³, 3θ′θ″| = 436.4), values ≤ r.
        let circle = NurbsCurve::circle(Vec3::ZERO, 1.0, Vec3::Y).unwrap();
        let circle_tolerance = central_difference_tolerance(h, 450.0, 1.0);
        // The circle is only C¹ at its double knots k/4 (C″ jumps there, and a difference across
        // one errs by O(h)), so samples are offset by 0.003 > 2h from them.
        for (curve, tolerance) in [(&cubic, tolerance), (&circle, circle_tolerance)] {
            for step in 1..99 {
                let u = step as f32 / 100.0 + 0.003;
                let (_, derivative) = curve.point_and_derivative(u);
                let central = (curve.point(u + h) - curve.point(u - h)) / (2.0 * h);
                assert!(
                    (central - derivative).length() <= tolerance,
                    "u={u}: {central} vs {derivative} (tolerance {tolerance})"
                );
            }
        }
    }

    #[test]
    fn periodic_curves_close_smoothly() {
        // The limit at the domain end (span m−1 at u = 1, read off the unrolled knot vector) must
        // equal the start C(0), with the same derivative: the control points P_j mod n repeat.
        // Uniform periodic cubic: C(k/n) = (P_k + 4 P_k+1 + P_k+2) / 6 (indices mod n).
        use crate::nurbs::basis::basis_functions_and_derivatives;
        for degree in 1..=5 {
            let points = wiggly_points(degree + 3);
            let n = points.len();
            let curve = NurbsCurve::periodic(points.clone(), degree).unwrap();
            assert!(curve.is_closed());
            let knots = curve.knots();
            let last_span = knots.basis_function_count() - 1;
            let mut values = [0.0; MAX_DEGREE + 1];
            let mut derivatives = [0.0; MAX_DEGREE + 1];
            basis_functions_and_derivatives(
                knots.values(),
                degree,
                last_span,
                1.0,
                &mut values,
                &mut derivatives,
            );
            let (mut end, mut end_derivative) = (Vec3::ZERO, Vec3::ZERO);
            for j in 0..=degree {
                let p = points[knots.control_index(last_span, j)];
                end += values[j] * p;
                end_derivative += derivatives[j] * p;
            }
            let (start, start_derivative) = curve.point_and_derivative(0.0);
            assert!((end - start).length() <= 1e-5, "p={degree}");
            // C^(p−1): the derivative is continuous across the seam from degree 2 on (a degree-1
            // curve is a closed polygon, with a corner at every knot, seam included).
            if degree >= 2 {
                assert!(
                    (end_derivative - start_derivative).length()
                        <= 1e-5 * start_derivative.length().max(1.0),
                    "p={degree}: {end_derivative} vs {start_derivative}"
                );
            }
            // Approaching from the left: |C(1 − δ) − C(0)| ≤ δ·max|C′| + roundoff.
            let delta = 1e-3;
            let max_speed = (0..=100)
                .map(|k| curve.point_and_derivative(k as f32 / 100.0).1.length())
                .fold(0.0, f32::max);
            assert!((curve.point(1.0 - delta) - start).length() <= 1.1 * delta * max_speed + 1e-5);
            if degree == 3 {
                for k in 0..n {
                    let expected =
                        (points[k] + 4.0 * points[(k + 1) % n] + points[(k + 2) % n]) / 6.0;
                    let got = curve.point(k as f32 / n as f32);
                    assert!((got - expected).length() <= 1e-5, "k={k}");
                }
            }
        }
    }

    #[test]
    fn unit_weights_give_the_polynomial_curve() {
        // Σ N_i·1·P_i / Σ N_i·1 = Σ N_i P_i since Σ N_i = 1: only roundoff differs.
        let points = wiggly_points(8);
        let polynomial = NurbsCurve::clamped(points.clone(), 3).unwrap();
        let mut rational = polynomial.clone().with_weights(vec![2.0; 8]).unwrap();
        assert!(rational.is_rational());
        rational.set_weights(&[1.0; 8]).unwrap();
        assert!(!rational.is_rational());
        let scaled = polynomial.clone().with_weights(vec![2.5; 8]).unwrap();
        for step in 0..=50 {
            let u = step as f32 / 50.0;
            let (a, da) = polynomial.point_and_derivative(u);
            let (b, db) = scaled.point_and_derivative(u);
            assert!((a - b).length() <= 1e-5 * (1.0 + a.length()));
            assert!((da - db).length() <= 1e-5 * (1.0 + da.length()));
        }
    }

    #[test]
    fn bad_curves_are_rejected() {
        let points = wiggly_points(4);
        let name = |error: HairError| match error {
            HairError::InvalidParameter { name, .. } => name,
            HairError::SizeMismatch { what, .. } => what,
            other => panic!("unexpected {other}"),
        };
        assert_eq!(
            name(NurbsCurve::clamped(points.clone(), 0).unwrap_err()),
            "degree"
        );
        assert_eq!(
            name(NurbsCurve::clamped(points[..2].to_vec(), 3).unwrap_err()),
            "control_point_count"
        );
        let mut nan = points.clone();
        nan[2].y = f32::NAN;
        assert_eq!(
            name(NurbsCurve::periodic(nan.clone(), 2).unwrap_err()),
            "control_points"
        );
        let curve = NurbsCurve::clamped(points.clone(), 3).unwrap();
        for bad in [
            vec![1.0, 0.0, 1.0, 1.0],
            vec![1.0, -2.0, 1.0, 1.0],
            vec![1.0, f32::NAN, 1.0, 1.0],
        ] {
            assert_eq!(
                name(curve.clone().with_weights(bad).unwrap_err()),
                "weights"
            );
        }
        assert_eq!(
            name(curve.clone().with_weights(vec![1.0; 3]).unwrap_err()),
            "weights"
        );
        let mut copy = curve.clone();
        assert_eq!(
            name(copy.set_control_points(&nan).unwrap_err()),
            "control_points"
        );
        assert_eq!(
            name(copy.set_control_points(&points[..3]).unwrap_err()),
            "control_points"
        );
        assert_eq!(copy, curve);
        assert_eq!(
            name(NurbsCurve::circle(Vec3::ZERO, 0.0, Vec3::Y).unwrap_err()),
            "radius"
        );
        assert_eq!(
            name(NurbsCurve::circle(Vec3::ZERO, 1.0, Vec3::ZERO).unwrap_err()),
            "normal"
        );
        assert_eq!(
            name(NurbsCurve::circle(Vec3::NAN, 1.0, Vec3::Y).unwrap_err()),
            "center"
        );
        // A NaN parameter evaluates at the domain start rather than producing NaN.
        assert_eq!(curve.point(f32::NAN), points[0]);
    }
}
