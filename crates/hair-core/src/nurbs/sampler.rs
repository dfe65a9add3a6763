//! Precomputed basis tables for evaluating many curves that share one knot vector at fixed parameters (the strand fast path).

use glam::{Vec3, Vec4};

use crate::error::{HairError, Result};

use super::curve::check_weights;
use super::knots::KnotVector;

/// The basis functions of one knot vector, tabulated at `samples` parameters evenly spread over
/// its domain, so that a curve is evaluated as a plain weighted sum of its control points.
///
/// Parameters: for an open knot vector `u_k = a + (b − a) k / (samples − 1)`, both ends included;
/// for a periodic one `u_k = a + (b − a) k / samples` (the end is the start again, not repeated).
///
/// The tables are flat, `order = degree + 1` entries per sample, sample-major (sample `k` owns
/// entries `k·order .. (k+1)·order`): ready to upload to a GPU as they are.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveSampler {
    degree: usize,
    control_point_count: usize,
    /// The sample parameters (dimensionless), one per sample.
    parameters: Vec<f32>,
    /// Knot span of each sample, one per sample.
    spans: Vec<u32>,
    /// Control point index of each non-zero basis function, `order` per sample (wrapped mod `n`
    /// for a periodic knot vector).
    control_indices: Vec<u32>,
    /// Basis values `N(u_k)`, `order` per sample; each group sums to 1.
    basis_values: Vec<f32>,
    /// Basis derivatives `dN/du (u_k)` [per unit parameter], `order` per sample; each sums to 0.
    derivative_values: Vec<f32>,
}

impl CurveSampler {
    /// Tabulates the basis of `knots` at `samples` parameters (see the type for where they lie).
    ///
    /// Errors: `samples < 2`; `samples` or the control point count too large for `u32` indices.
    pub fn new(knots: &KnotVector, samples: usize) -> Result<CurveSampler> {
        if samples < 2 || u32::try_from(samples).is_err() {
            return Err(HairError::invalid(
                "samples",
                samples,
                "an integer in 2..=u32::MAX",
            ));
        }
        if u32::try_from(knots.control_point_count()).is_err() {
            return Err(HairError::invalid(
                "control_point_count",
                knots.control_point_count(),
                "at most u32::MAX",
            ));
        }
        let degree = knots.degree();
        let order = degree + 1;
        let (low, high) = knots.domain();
        let divisions = if knots.is_periodic() {
            samples
        } else {
            samples - 1
        };
        let parameters: Vec<f32> = (0..samples)
            .map(|k| {
                if k == divisions {
                    high
                } else {
                    low + (high - low) * (k as f32 / divisions as f32)
                }
            })
            .collect();
        let mut spans = Vec::with_capacity(samples);
        let mut control_indices = Vec::with_capacity(samples * order);
        let mut basis_values = vec![0.0; samples * order];
        let mut derivative_values = vec![0.0; samples * order];
        for (k, &u) in parameters.iter().enumerate() {
            let range = k * order..(k + 1) * order;
            let span = knots.basis_and_derivatives(
                u,
                &mut basis_values[range.clone()],
                &mut derivative_values[range],
            );
            spans.push(span as u32);
            control_indices.extend((0..order).map(|j| knots.control_index(span, j) as u32));
        }
        Ok(CurveSampler {
            degree,
            control_point_count: knots.control_point_count(),
            parameters,
            spans,
            control_indices,
            basis_values,
            derivative_values,
        })
    }

    /// The degree of the knot vector; each sample has `degree + 1` table entries.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The number of control points a curve must have.
    pub fn control_point_count(&self) -> usize {
        self.control_point_count
    }

    /// The number of samples.
    pub fn sample_count(&self) -> usize {
        self.parameters.len()
    }

    /// The sample parameters (dimensionless), one per sample.
    pub fn parameters(&self) -> &[f32] {
        &self.parameters
    }

    /// The knot span of each sample.
    pub fn spans(&self) -> &[u32] {
        &self.spans
    }

    /// Control point indices, `degree + 1` per sample, sample-major.
    pub fn control_indices(&self) -> &[u32] {
        &self.control_indices
    }

    /// Basis values, `degree + 1` per sample, sample-major.
    pub fn basis_values(&self) -> &[f32] {
        &self.basis_values
    }

    /// Basis first derivatives [per unit parameter], `degree + 1` per sample, sample-major.
    pub fn derivative_values(&self) -> &[f32] {
        &self.derivative_values
    }

    /// The table rows of sample `sample`: (control indices, basis values, derivative values), each
    /// `degree + 1` long.
    ///
    /// # Panics
    /// If `sample >= sample_count()`.
    pub fn basis_at(&self, sample: usize) -> (&[u32], &[f32], &[f32]) {
        let order = self.degree + 1;
        let range = sample * order..(sample + 1) * order;
        (
            &self.control_indices[range.clone()],
            &self.basis_values[range.clone()],
            &self.derivative_values[range],
        )
    }

    /// Evaluates the polynomial B-spline (all weights 1) with `control_points` [m] at every sample:
    /// `positions[k] = Σ N_j(u_k) P_j` [m] and, if given, `tangents[k] = Σ N′_j(u_k) P_j`
    /// (`dC/du`, m per unit parameter, not normalized). No division, no allocation.
    ///
    /// Control points are not checked for finiteness (this is the per-frame path; the simulation
    /// owns that check).
    ///
    /// Errors (size mismatch): `control_points.len() != control_point_count()`, `positions` or
    /// `tangents` not `sample_count()` long.
    pub fn evaluate(
        &self,
        control_points: &[Vec3],
        positions: &mut [Vec3],
        tangents: Option<&mut [Vec3]>,
    ) -> Result<()> {
        self.check_sizes(control_points.len(), positions.len(), tangents.as_deref())?;
        let order = self.degree + 1;
        let rows = self
            .control_indices
            .chunks_exact(order)
            .zip(self.basis_values.chunks_exact(order));
        match tangents {
            None => {
                for (position, (indices, values)) in positions.iter_mut().zip(rows) {
                    let mut sum = Vec3::ZERO;
                    for (&index, &n) in indices.iter().zip(values) {
                        sum += n * control_points[index as usize];
                    }
                    *position = sum;
                }
            }
            Some(tangents) => {
                let rows = rows.zip(self.derivative_values.chunks_exact(order));
                for ((position, tangent), ((indices, values), derivatives)) in
                    positions.iter_mut().zip(tangents.iter_mut()).zip(rows)
                {
                    let mut sum = Vec3::ZERO;
                    let mut derivative_sum = Vec3::ZERO;
                    for ((&index, &n), &dn) in indices.iter().zip(values).zip(derivatives) {
                        let point = control_points[index as usize];
                        sum += n * point;
                        derivative_sum += dn * point;
                    }
                    *position = sum;
                    *tangent = derivative_sum;
                }
            }
        }
        Ok(())
    }

    /// Evaluates the rational curve with `control_points` [m] and `weights` (dimensionless, `> 0`):
    /// `C = A / w` with `A = Σ N_j w_j P_j`, `w = Σ N_j w_j`, and `C′ = (A′ − w′ C) / w`.
    /// No allocation.
    ///
    /// Errors: size mismatches as for [`CurveSampler::evaluate`] (and for `weights`), a weight that
    /// is not finite and `> 0`.
    pub fn evaluate_rational(
        &self,
        control_points: &[Vec3],
        weights: &[f32],
        positions: &mut [Vec3],
        tangents: Option<&mut [Vec3]>,
    ) -> Result<()> {
        self.check_sizes(control_points.len(), positions.len(), tangents.as_deref())?;
        check_weights(weights, self.control_point_count)?;
        let order = self.degree + 1;
        let homogeneous = |index: u32| {
            let w = weights[index as usize];
            (control_points[index as usize] * w).extend(w)
        };
        let rows = self
            .control_indices
            .chunks_exact(order)
            .zip(self.basis_values.chunks_exact(order));
        match tangents {
            None => {
                for (position, (indices, values)) in positions.iter_mut().zip(rows) {
                    let mut sum = Vec4::ZERO;
                    for (&index, &n) in indices.iter().zip(values) {
                        sum += n * homogeneous(index);
                    }
                    *position = sum.truncate() / sum.w;
                }
            }
            Some(tangents) => {
                let rows = rows.zip(self.derivative_values.chunks_exact(order));
                for ((position, tangent), ((indices, values), derivatives)) in
                    positions.iter_mut().zip(tangents.iter_mut()).zip(rows)
                {
                    let mut sum = Vec4::ZERO;
                    let mut derivative_sum = Vec4::ZERO;
                    for ((&index, &n), &dn) in indices.iter().zip(values).zip(derivatives) {
                        let point = homogeneous(index);
                        sum += n * point;
                        derivative_sum += dn * point;
                    }
                    let point = sum.truncate() / sum.w;
                    *position = point;
                    *tangent = (derivative_sum.truncate() - derivative_sum.w * point) / sum.w;
                }
            }
        }
        Ok(())
    }

    fn check_sizes(
        &self,
        control_point_count: usize,
        position_count: usize,
        tangents: Option<&[Vec3]>,
    ) -> Result<()> {
        let mismatch = |what, actual, expected| {
            Err(HairError::SizeMismatch {
                what,
                actual,
                expected,
            })
        };
        if control_point_count != self.control_point_count {
            return mismatch(
                "control_points",
                control_point_count,
                self.control_point_count,
            );
        }
        if position_count != self.sample_count() {
            return mismatch("positions", position_count, self.sample_count());
        }
        match tangents {
            Some(tangents) if tangents.len() != self.sample_count() => {
                mismatch("tangents", tangents.len(), self.sample_count())
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;

    fn points(count: usize) -> Vec<Vec3> {
        (0..count)
            .map(|i| {
                let t = i as f32;
                Vec3::new((0.9 * t).cos(), 0.25 * t, (0.6 * t).sin() - 0.2)
            })
            .collect()
    }

    #[test]
    fn sampler_equals_curve_evaluation() {
        // Same basis values, same sums: positions and tangents must equal NurbsCurve's to f32
        // roundoff (1e-5 relative to the magnitudes involved), for clamped and periodic knots,
        // degrees 1..=5, and the parameters must be k/(s−1) (clamped) or k/s (periodic).
        for degree in 1..=5 {
            for periodic in [false, true] {
                let control_points = points(degree + 5);
                let curve = if periodic {
                    NurbsCurve::periodic(control_points.clone(), degree)
                } else {
                    NurbsCurve::clamped(control_points.clone(), degree)
                }
                .unwrap();
                let samples = 23;
                let sampler = CurveSampler::new(curve.knots(), samples).unwrap();
                let mut positions = vec![Vec3::ZERO; samples];
                let mut tangents = vec![Vec3::ZERO; samples];
                sampler
                    .evaluate(&control_points, &mut positions, Some(&mut tangents))
                    .unwrap();
                let mut positions_only = vec![Vec3::ZERO; samples];
                sampler
                    .evaluate(&control_points, &mut positions_only, None)
                    .unwrap();
                assert_eq!(positions, positions_only);
                let divisions = if periodic { samples } else { samples - 1 } as f32;
                for k in 0..samples {
                    let u = sampler.parameters()[k];
                    assert!((u - k as f32 / divisions).abs() <= f32::EPSILON);
                    let (point, derivative) = curve.point_and_derivative(u);
                    assert!((positions[k] - point).length() <= 1e-5 * (1.0 + point.length()));
                    assert!(
                        (tangents[k] - derivative).length() <= 1e-5 * (1.0 + derivative.length())
                    );
                }
                if !periodic {
                    // Ends included: the clamped curve interpolates the end control points.
                    assert_eq!(positions[0], control_points[0]);
                    assert_eq!(positions[samples - 1], *control_points.last().unwrap());
                }
            }
        }
    }

    #[test]
    fn rational_sampler_equals_curve_evaluation() {
        // The circle (rational quadratic) and a randomly weighted cubic: C = A/w, C′ = (A′ − w′C)/w
        // computed the same way by both; 1e-5 relative.
        let circle = NurbsCurve::circle(Vec3::new(1.0, 0.0, -1.0), 0.5, Vec3::Z).unwrap();
        let weighted = NurbsCurve::periodic(points(7), 3)
            .unwrap()
            .with_weights(vec![1.0, 0.5, 2.0, 1.5, 0.8, 1.2, 3.0])
            .unwrap();
        for curve in [circle, weighted] {
            let sampler = CurveSampler::new(curve.knots(), 31).unwrap();
            let mut positions = vec![Vec3::ZERO; 31];
            let mut tangents = vec![Vec3::ZERO; 31];
            sampler
                .evaluate_rational(
                    curve.control_points(),
                    curve.weights(),
                    &mut positions,
                    Some(&mut tangents),
                )
                .unwrap();
            for (k, &u) in sampler.parameters().iter().enumerate() {
                let (point, derivative) = curve.point_and_derivative(u);
                assert!((positions[k] - point).length() <= 1e-5 * (1.0 + point.length()));
                assert!((tangents[k] - derivative).length() <= 1e-5 * (1.0 + derivative.length()));
            }
        }
    }

    #[test]
    fn tables_are_partitions_of_unity() {
        // Σ_j N_j(u_k) = 1 and Σ_j N′_j(u_k) = 0 for every sample (1e-5, f32 roundoff).
        let knots = KnotVector::periodic_uniform(6, 4).unwrap();
        let sampler = CurveSampler::new(&knots, 17).unwrap();
        for k in 0..sampler.sample_count() {
            let (indices, values, derivatives) = sampler.basis_at(k);
            assert!(indices.iter().all(|&i| (i as usize) < 6));
            assert!((values.iter().sum::<f32>() - 1.0).abs() <= 1e-5);
            let scale: f32 = derivatives.iter().map(|d| d.abs()).sum();
            assert!(derivatives.iter().sum::<f32>().abs() <= 1e-5 * scale);
        }
    }

    #[test]
    fn bad_sizes_are_errors() {
        let knots = KnotVector::clamped_uniform(5, 3).unwrap();
        assert!(matches!(
            CurveSampler::new(&knots, 1),
            Err(HairError::InvalidParameter {
                name: "samples",
                ..
            })
        ));
        let sampler = CurveSampler::new(&knots, 8).unwrap();
        let mut positions = vec![Vec3::ZERO; 8];
        let mut short = vec![Vec3::ZERO; 7];
        let what = |result: Result<()>| match result.unwrap_err() {
            HairError::SizeMismatch { what, .. } => what,
            HairError::InvalidParameter { name, .. } => name,
            other => panic!("unexpected {other}"),
        };
        assert_eq!(
            what(sampler.evaluate(&points(4), &mut positions, None)),
            "control_points"
        );
        assert_eq!(
            what(sampler.evaluate(&points(5), &mut short, None)),
            "positions"
        );
        assert_eq!(
            what(sampler.evaluate(&points(5), &mut positions, Some(&mut short))),
            "tangents"
        );
        assert_eq!(
            what(sampler.evaluate_rational(&points(5), &[1.0; 4], &mut positions, None)),
            "weights"
        );
        assert_eq!(
            what(sampler.evaluate_rational(
                &points(5),
                &[1.0, 1.0, 0.0, 1.0, 1.0],
                &mut positions,
                None
            )),
            "weights"
        );
    }
}
