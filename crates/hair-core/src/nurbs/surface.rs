//! Tensor-product NURBS surfaces: points, partial derivatives and tessellation into triangle meshes.

use glam::{Vec3, Vec4};

use crate::error::{HairError, Result};

use super::MAX_DEGREE;
use super::curve::{check_points, check_weights};
use super::knots::KnotVector;

/// A (rational) tensor-product B-spline surface
/// `S(u, v) = Σᵢ Σⱼ Nᵢ(u) Nⱼ(v) wᵢⱼ Pᵢⱼ / Σᵢ Σⱼ Nᵢ(u) Nⱼ(v) wᵢⱼ`.
///
/// Each direction has its own degree and [`KnotVector`], open (clamped or given) or periodic
/// (closed around: a tube's cross-section). The control grid is `count_u × count_v` points [m]
/// stored **u-fastest**: `Pᵢⱼ` (`i < count_u`, `j < count_v`) is at index `i + count_u · j`, and so is
/// its weight (dimensionless, finite, `> 0`). For hair, `u` runs along the hair (root to tip) and
/// `v` across it.
///
/// Orientation: the surface normal is `∂S/∂u × ∂S/∂v`; [`NurbsSurface::tessellate`] winds triangles
/// counter-clockwise seen from that side.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsSurface {
    knots_u: KnotVector,
    knots_v: KnotVector,
    control_points: Vec<Vec3>,
    weights: Vec<f32>,
    rational: bool,
}

impl NurbsSurface {
    /// A polynomial surface (all weights 1) over `knots_u × knots_v` with
    /// `knots_u.control_point_count() × knots_v.control_point_count()` control points [m],
    /// u-fastest.
    ///
    /// Errors: a wrong number of control points (size mismatch), a non-finite coordinate.
    pub fn new(
        knots_u: KnotVector,
        knots_v: KnotVector,
        control_points: Vec<Vec3>,
    ) -> Result<NurbsSurface> {
        let expected = knots_u
            .control_point_count()
            .checked_mul(knots_v.control_point_count())
            .ok_or_else(|| {
                HairError::invalid(
                    "control_point_count",
                    "count_u × count_v overflows",
                    "a grid that fits in memory",
                )
            })?;
        if control_points.len() != expected {
            return Err(HairError::SizeMismatch {
                what: "control_points",
                actual: control_points.len(),
                expected,
            });
        }
        check_points("control_points", &control_points)?;
        Ok(NurbsSurface {
            knots_u,
            knots_v,
            weights: vec![1.0; expected],
            control_points,
            rational: false,
        })
    }

    /// An open surface on clamped uniform knot vectors in both directions (domain `[0, 1]²`); it
    /// interpolates the four corner control points. `control_points` holds `count_u × count_v`
    /// points, u-fastest.
    ///
    /// Errors: a degree outside `1..=MAX_DEGREE` or fewer than `degree + 1` points in a direction
    /// (named `degree` / `control_point_count`), a wrong number of points, a non-finite point.
    pub fn clamped(
        control_points: Vec<Vec3>,
        count_u: usize,
        count_v: usize,
        degree_u: usize,
        degree_v: usize,
    ) -> Result<NurbsSurface> {
        let knots_u = KnotVector::clamped_uniform(count_u, degree_u)?;
        let knots_v = KnotVector::clamped_uniform(count_v, degree_v)?;
        NurbsSurface::new(knots_u, knots_v, control_points)
    }

    /// The same surface with the given weights (dimensionless, one per control point, u-fastest).
    ///
    /// Errors: a wrong number of weights (size mismatch), a weight that is not finite and `> 0`.
    pub fn with_weights(mut self, weights: Vec<f32>) -> Result<NurbsSurface> {
        self.rational = check_weights(&weights, self.control_points.len())?;
        self.weights = weights;
        Ok(self)
    }

    /// The knot vector in `u`.
    pub fn knots_u(&self) -> &KnotVector {
        &self.knots_u
    }

    /// The knot vector in `v`.
    pub fn knots_v(&self) -> &KnotVector {
        &self.knots_v
    }

    /// Control points in `u` (the fast index).
    pub fn count_u(&self) -> usize {
        self.knots_u.control_point_count()
    }

    /// Control points in `v` (the slow index).
    pub fn count_v(&self) -> usize {
        self.knots_v.control_point_count()
    }

    /// The degree in `u`.
    pub fn degree_u(&self) -> usize {
        self.knots_u.degree()
    }

    /// The degree in `v`.
    pub fn degree_v(&self) -> usize {
        self.knots_v.degree()
    }

    /// The control grid [m], `count_u × count_v`, u-fastest.
    pub fn control_points(&self) -> &[Vec3] {
        &self.control_points
    }

    /// Control point `Pᵢⱼ` [m].
    ///
    /// # Panics
    /// If `i >= count_u()` or `j >= count_v()`.
    pub fn control_point(&self, i: usize, j: usize) -> Vec3 {
        assert!(
            i < self.count_u(),
            "control point index i = {i} out of range"
        );
        self.control_points[i + self.count_u() * j]
    }

    /// The weights, `count_u × count_v`, u-fastest.
    pub fn weights(&self) -> &[f32] {
        &self.weights
    }

    /// Whether the `u` direction is periodic (closed).
    pub fn is_closed_u(&self) -> bool {
        self.knots_u.is_periodic()
    }

    /// Whether the `v` direction is periodic (closed).
    pub fn is_closed_v(&self) -> bool {
        self.knots_v.is_periodic()
    }

    /// Whether some weight differs from 1.
    pub fn is_rational(&self) -> bool {
        self.rational
    }

    /// The parameter domains `((u₀, u₁), (v₀, v₁))`.
    pub fn domain(&self) -> ((f32, f32), (f32, f32)) {
        (self.knots_u.domain(), self.knots_v.domain())
    }

    /// Replaces the control grid [m] (same size, u-fastest).
    ///
    /// Errors: a different number of points (size mismatch), a non-finite coordinate; the surface
    /// is left unchanged then.
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

    /// Replaces the weights. Errors as for [`NurbsSurface::with_weights`]; unchanged on error.
    pub fn set_weights(&mut self, weights: &[f32]) -> Result<()> {
        self.rational = check_weights(weights, self.weights.len())?;
        self.weights.copy_from_slice(weights);
        Ok(())
    }

    /// The point `S(u, v)` [m]; each parameter is clamped (open direction) or wrapped (periodic).
    pub fn point(&self, u: f32, v: f32) -> Vec3 {
        self.point_and_partials(u, v).0
    }

    /// The point `S(u, v)` [m] and the partial derivatives `∂S/∂u`, `∂S/∂v` [m per unit parameter].
    /// For a rational surface, `S_u = (A_u − w_u S) / w` and `S_v = (A_v − w_v S) / w` with
    /// `A = Σ NᵢNⱼ wᵢⱼ Pᵢⱼ`, `w = Σ NᵢNⱼ wᵢⱼ`.
    pub fn point_and_partials(&self, u: f32, v: f32) -> (Vec3, Vec3, Vec3) {
        let mut values_u = [0.0; MAX_DEGREE + 1];
        let mut derivatives_u = [0.0; MAX_DEGREE + 1];
        let mut values_v = [0.0; MAX_DEGREE + 1];
        let mut derivatives_v = [0.0; MAX_DEGREE + 1];
        let span_u = self
            .knots_u
            .basis_and_derivatives(u, &mut values_u, &mut derivatives_u);
        let span_v = self
            .knots_v
            .basis_and_derivatives(v, &mut values_v, &mut derivatives_v);
        let mut indices_u = [0u32; MAX_DEGREE + 1];
        let mut indices_v = [0u32; MAX_DEGREE + 1];
        let (order_u, order_v) = (self.degree_u() + 1, self.degree_v() + 1);
        for (j, index) in indices_u[..order_u].iter_mut().enumerate() {
            *index = self.knots_u.control_index(span_u, j) as u32;
        }
        for (j, index) in indices_v[..order_v].iter_mut().enumerate() {
            *index = self.knots_v.control_index(span_v, j) as u32;
        }
        self.evaluate_from_basis(
            (
                &indices_u[..order_u],
                &values_u[..order_u],
                &derivatives_u[..order_u],
            ),
            (
                &indices_v[..order_v],
                &values_v[..order_v],
                &derivatives_v[..order_v],
            ),
        )
    }

    /// The unit normal `(S_u × S_v) / |S_u × S_v|` at `(u, v)`.
    ///
    /// Where `S_u × S_v` (nearly) vanishes, at a collapsed edge or a pole (a cluster tip of radius
    /// 0), this is the limit normal: the normal 10⁻³ of the domain (`LIMIT_NORMAL_STEP`) away
    /// towards its centre, in `u`, else in `v`, else in both. Zero if the surface is degenerate there
    /// too.
    pub fn normal(&self, u: f32, v: f32) -> Vec3 {
        let (_, partial_u, partial_v) = self.point_and_partials(u, v);
        unit_cross(partial_u, partial_v)
            .or_else(|| self.limit_normal(u, v))
            .unwrap_or(Vec3::ZERO)
    }

    /// The unit normal a short step into the domain from a degenerate point (see
    /// [`NurbsSurface::normal`]).
    pub(super) fn limit_normal(&self, u: f32, v: f32) -> Option<Vec3> {
        let step_inwards = |knots: &KnotVector, t: f32| {
            let t = knots.parameter_in_domain(t);
            let (low, high) = knots.domain();
            let step = LIMIT_NORMAL_STEP * (high - low);
            if t < 0.5 * (low + high) {
                t + step
            } else {
                t - step
            }
        };
        let (u_inside, v_inside) = (
            step_inwards(&self.knots_u, u),
            step_inwards(&self.knots_v, v),
        );
        [(u_inside, v), (u, v_inside), (u_inside, v_inside)]
            .into_iter()
            .find_map(|(u, v)| {
                let (_, partial_u, partial_v) = self.point_and_partials(u, v);
                unit_cross(partial_u, partial_v)
            })
    }

    /// Sums the control grid against precomputed basis rows `(control indices, values,
    /// derivatives)` in `u` and in `v`: returns `(S, S_u, S_v)`.
    pub(super) fn evaluate_from_basis(
        &self,
        (indices_u, values_u, derivatives_u): (&[u32], &[f32], &[f32]),
        (indices_v, values_v, derivatives_v): (&[u32], &[f32], &[f32]),
    ) -> (Vec3, Vec3, Vec3) {
        let count_u = self.count_u();
        let mut sum = Vec4::ZERO;
        let mut sum_u = Vec4::ZERO;
        let mut sum_v = Vec4::ZERO;
        for ((&j, &n_v), &d_v) in indices_v.iter().zip(values_v).zip(derivatives_v) {
            let row = j as usize * count_u;
            let mut along = Vec4::ZERO;
            let mut along_derivative = Vec4::ZERO;
            for ((&i, &n_u), &d_u) in indices_u.iter().zip(values_u).zip(derivatives_u) {
                let k = row + i as usize;
                let w = self.weights[k];
                let homogeneous = (self.control_points[k] * w).extend(w);
                along += n_u * homogeneous;
                along_derivative += d_u * homogeneous;
            }
            sum += n_v * along;
            sum_u += n_v * along_derivative;
            sum_v += d_v * along;
        }
        if self.rational {
            let point = sum.truncate() / sum.w;
            (
                point,
                (sum_u.truncate() - sum_u.w * point) / sum.w,
                (sum_v.truncate() - sum_v.w * point) / sum.w,
            )
        } else {
            (sum.truncate(), sum_u.truncate(), sum_v.truncate())
        }
    }
}

/// How far into the domain (as a fraction of its length) [`NurbsSurface::normal`] looks for the
/// limit normal at a degenerate point.
const LIMIT_NORMAL_STEP: f32 = 1e-3;

/// The unit `S_u × S_v`, or `None` where it nearly vanishes (`|S_u × S_v| ≤ 10⁻⁶ |S_u| |S_v|`: the
/// partials are parallel to f32 precision, or one is zero) or is not finite.
pub(super) fn unit_cross(partial_u: Vec3, partial_v: Vec3) -> Option<Vec3> {
    let cross = partial_u.cross(partial_v);
    let scale = partial_u.length() * partial_v.length();
    if cross.is_finite() && cross.length() > 1e-6 * scale {
        cross.try_normalize()
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::test_support::{central_difference_tolerance, close, cylinder};

    /// The bicubic test surface: 5 × 6 points with |P| ≤ 1.5.
    fn wavy_surface() -> NurbsSurface {
        let mut points = Vec::new();
        for j in 0..6 {
            for i in 0..5 {
                let (x, y) = (i as f32, j as f32);
                points.push(Vec3::new(
                    0.25 * x - 0.5,
                    0.2 * y - 0.5,
                    0.5 * (1.1 * x + 0.7 * y).sin(),
                ));
            }
        }
        NurbsSurface::clamped(points, 5, 6, 3, 3).unwrap()
    }

    #[test]
    fn bilinear_patch_is_exact() {
        // Degree 1 × 1, 2 × 2 points: S = (1−u)(1−v)P00 + u(1−v)P10 + (1−u)v P01 + uv P11,
        // S_u = (1−v)(P10 − P00) + v(P11 − P01), S_v = (1−u)(P01 − P00) + u(P11 − P10).
        let [p00, p10, p01, p11] = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(2.0, 1.0, 1.5),
        ];
        let surface = NurbsSurface::clamped(vec![p00, p10, p01, p11], 2, 2, 1, 1).unwrap();
        assert_eq!(surface.control_point(1, 1), p11);
        for a in 0..=10 {
            for b in 0..=10 {
                let (u, v) = (a as f32 / 10.0, b as f32 / 10.0);
                let expected = (1.0 - u) * (1.0 - v) * p00
                    + u * (1.0 - v) * p10
                    + (1.0 - u) * v * p01
                    + u * v * p11;
                let expected_u = (1.0 - v) * (p10 - p00) + v * (p11 - p01);
                let expected_v = (1.0 - u) * (p01 - p00) + u * (p11 - p10);
                let (point, partial_u, partial_v) = surface.point_and_partials(u, v);
                assert!(close(point, expected, 2.0));
                assert!(close(partial_u, expected_u, 2.0));
                assert!(close(partial_v, expected_v, 2.0));
            }
        }
    }

    #[test]
    fn flat_bicubic_reproduces_the_plane() {
        // Linear precision: with P_ij = O + ξ_i A + η_j B at the Greville abscissae
        // ξ_i = (U_i+1 + … + U_i+p) / p, S(u, v) = O + uA + vB, S_u = A, S_v = B exactly.
        let (count_u, count_v, degree_u, degree_v) = (6, 5, 3, 2);
        let knots_u = KnotVector::clamped_uniform(count_u, degree_u).unwrap();
        let knots_v = KnotVector::clamped_uniform(count_v, degree_v).unwrap();
        let greville = |knots: &KnotVector, i: usize| {
            let p = knots.degree();
            knots.values()[i + 1..=i + p].iter().sum::<f32>() / p as f32
        };
        let (origin, a, b) = (
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(1.0, 0.5, 0.0),
            Vec3::new(0.0, -0.4, 2.0),
        );
        let mut points = Vec::new();
        for j in 0..count_v {
            for i in 0..count_u {
                points.push(origin + greville(&knots_u, i) * a + greville(&knots_v, j) * b);
            }
        }
        let surface = NurbsSurface::new(knots_u, knots_v, points).unwrap();
        for step_u in 0..=20 {
            for step_v in 0..=20 {
                let (u, v) = (step_u as f32 / 20.0, step_v as f32 / 20.0);
                let (point, partial_u, partial_v) = surface.point_and_partials(u, v);
                assert!(close(point, origin + u * a + v * b, 3.0), "({u}, {v})");
                // Partials sum |N′|·|P| ≤ (p/Δ)·|P| ≈ 10: roundoff relative to that.
                assert!(close(partial_u, a, 10.0));
                assert!(close(partial_v, b, 10.0));
            }
        }
    }

    #[test]
    fn surface_of_revolution_is_an_exact_cylinder() {
        // S(u, v) = circle(v) + u·h·Y: the distance to the axis is r and the height u·h, exactly
        // (1e-5 relative), and the outward normal is the radial direction.
        let base = Vec3::new(0.5, -1.0, 0.25);
        let (radius, height) = (0.3, 2.0);
        let (surface, circle) = cylinder(base, radius, height);
        assert!(surface.is_rational());
        for a in 0..=8 {
            for b in 0..=64 {
                let (u, v) = (a as f32 / 8.0, b as f32 / 64.0);
                let (point, partial_u, partial_v) = surface.point_and_partials(u, v);
                let offset = point - base;
                let radial = Vec3::new(offset.x, 0.0, offset.z);
                assert!(
                    (radial.length() - radius).abs() <= 1e-5 * radius,
                    "({u}, {v})"
                );
                assert!((offset.y - u * height).abs() <= 1e-5 * height);
                assert!(close(point, circle.point(v) + u * height * Vec3::Y, 2.0));
                assert!(close(partial_u, height * Vec3::Y, height));
                let (_, circle_derivative) = circle.point_and_derivative(v);
                assert!(close(
                    partial_v,
                    circle_derivative,
                    circle_derivative.length()
                ));
                let normal = surface.normal(u, v);
                assert!(close(normal, radial / radius, 1.0), "({u}, {v}): {normal}");
            }
        }
    }

    #[test]
    fn partials_match_central_differences() {
        // (S(u+h, v) − S(u−h, v)) / 2h = S_u + h² S_uuu / 6 + roundoff, likewise in v; h = 1e-3.
        // Wavy bicubic: |P| ≤ 1.5, spans Δu = 1/2, Δv = 1/3, so |S_uuu| ≤ 6·8·1.5/Δu³ = 576 and
        // |S_vvv| ≤ 6·8·1.5/Δv³ = 1944 (third differences of the control net).
        // Cylinder: S_uuu = 0 (linear in u) and |S_vvv| ≤ 450 r (the circle's bound); values
        // ≤ |base| + r + height ≤ 3.5.
        let h = 1e-3;
        let wavy = wavy_surface();
        let (cylinder, _) = cylinder(Vec3::new(0.5, -1.0, 0.25), 0.3, 2.0);
        let cases = [
            (
                &wavy,
                central_difference_tolerance(h, 576.0, 1.5),
                central_difference_tolerance(h, 1944.0, 1.5),
            ),
            (
                &cylinder,
                central_difference_tolerance(h, 0.0, 3.5),
                central_difference_tolerance(h, 450.0 * 0.3, 3.5),
            ),
        ];
        for (surface, tolerance_u, tolerance_v) in cases {
            for a in 1..20 {
                for b in 1..20 {
                    let (u, v) = (a as f32 / 20.0, b as f32 / 20.0 + 0.013);
                    let (_, partial_u, partial_v) = surface.point_and_partials(u, v);
                    let central_u = (surface.point(u + h, v) - surface.point(u - h, v)) / (2.0 * h);
                    let central_v = (surface.point(u, v + h) - surface.point(u, v - h)) / (2.0 * h);
                    assert!(
                        (central_u - partial_u).length() <= tolerance_u,
                        "S_u at ({u}, {v}): {central_u} vs {partial_u}"
                    );
                    assert!(
                        (central_v - partial_v).length() <= tolerance_v,
                        "S_v at ({u}, {v}): {central_v} vs {partial_v}"
                    );
                }
            }
        }
    }

    #[test]
    fn bad_surfaces_are_rejected() {
        let what = |error: HairError| match error {
            HairError::InvalidParameter { name, .. } => name,
            HairError::SizeMismatch { what, .. } => what,
            other => panic!("unexpected {other}"),
        };
        let points = vec![Vec3::ZERO; 6];
        assert_eq!(
            what(NurbsSurface::clamped(points.clone(), 2, 2, 1, 1).unwrap_err()),
            "control_points"
        );
        assert_eq!(
            what(NurbsSurface::clamped(points.clone(), 3, 2, 0, 1).unwrap_err()),
            "degree"
        );
        assert_eq!(
            what(NurbsSurface::clamped(points.clone(), 3, 2, 1, 2).unwrap_err()),
            "control_point_count"
        );
        let mut nan = points.clone();
        nan[4] = Vec3::new(0.0, f32::INFINITY, 0.0);
        assert_eq!(
            what(NurbsSurface::clamped(nan, 3, 2, 1, 1).unwrap_err()),
            "control_points"
        );
        let surface = NurbsSurface::clamped(points, 3, 2, 2, 1).unwrap();
        assert_eq!(
            what(surface.clone().with_weights(vec![1.0; 5]).unwrap_err()),
            "weights"
        );
        assert_eq!(
            what(
                surface
                    .clone()
                    .with_weights(vec![1.0, 1.0, -1.0, 1.0, 1.0, 1.0])
                    .unwrap_err()
            ),
            "weights"
        );
        // NaN parameters evaluate at the domain start, never to NaN.
        assert!(surface.point(f32::NAN, f32::NAN).is_finite());
    }
}
