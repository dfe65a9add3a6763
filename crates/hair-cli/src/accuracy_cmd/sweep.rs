//! The points of `hairlod accuracy`: one configuration's frames summarised as its median cost and
//! mean errors, the Pareto fronts of cost against each error, and the chart's scatter points.

use hairlod::accuracy::{GeometricError, PhysicalError};
use serde::Serialize;

use crate::charts::ScatterPoint;
use crate::pareto::pareto_front;

/// What a configuration is, for the chart's colours: fixed levels, LODs, integrators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Group {
    /// The reference: the yardstick, on no front.
    Reference,
    /// The fixed levels (Strands, Clusters, Patches).
    FixedLevel,
    /// Automatic levels at one pixel tolerance.
    Lods,
    /// Strands with another integrator or step.
    Integrator,
}

impl Group {
    /// The chart's colour group.
    fn colour_index(self) -> usize {
        match self {
            Group::FixedLevel | Group::Reference => 0,
            Group::Lods => 1,
            Group::Integrator => 2,
        }
    }
}

/// One frame of one configuration against the reference.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FrameErrors {
    /// Total cost of the frame (LOD, dynamics, collision, rendering) [s].
    pub cost: f64,
    /// SSIM against the reference frame.
    pub ssim: f64,
    /// PSNR against the reference frame [dB] (`null` in JSON when infinite).
    pub psnr: f64,
    /// Screen-space error of the hair samples the viewer sees [pixels].
    pub geometric: GeometricError,
    /// Segment-length error and penetration depth.
    pub physical: PhysicalError,
}

/// One configuration of the sweep.
#[derive(Debug, Clone, Serialize)]
pub struct Point {
    /// `Reference`, `Strands`, `Clusters`, `Patches`, `LODs 1px`, `position-based ×4`...
    pub label: String,
    /// Fixed level, LODs or integrator.
    pub group: Group,
    /// Median total cost per frame [s].
    pub median_cost: f64,
    /// 1 − mean SSIM against the reference.
    pub ssim_loss: f64,
    /// Mean over frames of the mean pixel error [pixels].
    pub mean_pixel_error: f64,
    /// Mean over frames of the 95th-percentile pixel error [pixels].
    pub mean_p95_pixel_error: f64,
    /// Worst segment-length error and penetration over the run.
    pub physical: PhysicalError,
    /// On the Pareto front of (median cost, SSIM loss): no other point is at least as cheap and
    /// at least as accurate and better in one.
    pub pareto_ssim: bool,
    /// On the Pareto front of (median cost, mean pixel error).
    pub pareto_pixels: bool,
    /// Why the configuration could not finish (an unstable integrator step), if it failed; a
    /// failed configuration has no errors and is on no front.
    pub failed: Option<String>,
    /// Every frame.
    pub frames: Vec<FrameErrors>,
}

impl Point {
    /// Summarises `frames` of configuration `label`.
    pub fn new(label: String, group: Group, frames: Vec<FrameErrors>) -> Point {
        let n = frames.len().max(1) as f64;
        let mut costs: Vec<f64> = frames.iter().map(|f| f.cost).collect();
        costs.sort_by(f64::total_cmp);
        let median_cost = costs.get(costs.len() / 2).copied().unwrap_or(0.0);
        let physical = frames
            .iter()
            .fold(PhysicalError::default(), |worst, f| worst.max(f.physical));
        Point {
            label,
            group,
            median_cost,
            ssim_loss: 1.0 - frames.iter().map(|f| f.ssim).sum::<f64>() / n,
            mean_pixel_error: frames.iter().map(|f| f.geometric.mean_pixels).sum::<f64>() / n,
            mean_p95_pixel_error: frames.iter().map(|f| f.geometric.p95_pixels).sum::<f64>() / n,
            physical,
            pareto_ssim: false,
            pareto_pixels: false,
            failed: None,
            frames,
        }
    }

    /// A configuration that failed with `reason`.
    pub fn failed(label: String, group: Group, reason: String) -> Point {
        Point {
            failed: Some(reason),
            ..Point::new(label, group, Vec::new())
        }
    }

    /// The point as the chart draws it (costs in milliseconds).
    pub fn scatter(&self) -> ScatterPoint {
        ScatterPoint {
            label: self.label.clone(),
            cost_ms: 1e3 * self.median_cost,
            errors: [self.ssim_loss, self.mean_pixel_error],
            pareto: [self.pareto_ssim, self.pareto_pixels],
            group: self.group.colour_index(),
        }
    }
}

/// Marks the finished points that no other finished point dominates, in (median cost, SSIM loss)
/// and in (median cost, mean pixel error) separately. The reference is the yardstick (zero error
/// by definition) and takes part in neither front.
pub fn mark_pareto(points: &mut [Point]) {
    let ssim = front(points, |p| p.ssim_loss);
    let pixels = front(points, |p| p.mean_pixel_error);
    for ((point, on_ssim), on_pixels) in points.iter_mut().zip(ssim).zip(pixels) {
        point.pareto_ssim = on_ssim;
        point.pareto_pixels = on_pixels;
    }
}

/// For each point, whether it is on the front of cost against `error` (failed points and the
/// reference never are).
fn front(points: &[Point], error: impl Fn(&Point) -> f64) -> Vec<bool> {
    let keys: Vec<Option<(f64, f64)>> = points
        .iter()
        .map(|p| {
            (p.failed.is_none() && p.group != Group::Reference).then(|| (p.median_cost, error(p)))
        })
        .collect();
    pareto_front(&keys)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(label: &str, cost: f64, ssim_loss: f64, pixels: f64) -> Point {
        Point {
            median_cost: cost,
            ssim_loss,
            mean_pixel_error: pixels,
            ..Point::new(label.into(), Group::Lods, Vec::new())
        }
    }

    #[test]
    fn the_front_holds_exactly_the_undominated_points() {
        let mut points = vec![
            point("a", 1.0, 0.10, 1.0),
            point("b", 2.0, 0.05, 3.0),
            point("c", 3.0, 0.06, 0.5), // dominated by b in SSIM, on the pixel front
            point("d", 4.0, 0.00, 0.0),
            point("e", 1.0, 0.20, 2.0), // as cheap as a and worse in both
            Point::failed("f".into(), Group::Integrator, "unstable".into()),
            Point {
                group: Group::Reference,
                ..point("reference", 0.5, 0.0, 0.0)
            },
        ];
        mark_pareto(&mut points);
        let on: Vec<(bool, bool)> = points
            .iter()
            .map(|p| (p.pareto_ssim, p.pareto_pixels))
            .collect();
        assert_eq!(
            on,
            [
                (true, true),
                (true, false),
                (false, true),
                (true, true),
                (false, false),
                (false, false),
                (false, false)
            ]
        );
    }

    #[test]
    fn the_summary_is_the_median_cost_and_the_mean_errors() {
        let frame = |cost: f64, ssim: f64, mean_pixels: f64| FrameErrors {
            cost,
            ssim,
            psnr: 30.0,
            geometric: GeometricError {
                mean_pixels,
                ..GeometricError::default()
            },
            physical: PhysicalError::default(),
        };
        let p = Point::new(
            "x".into(),
            Group::Lods,
            vec![
                frame(0.3, 0.9, 1.0),
                frame(0.1, 1.0, 2.0),
                frame(0.2, 0.8, 3.0),
            ],
        );
        assert_eq!(p.median_cost, 0.2);
        assert!((p.ssim_loss - 0.1).abs() < 1e-12);
        assert!((p.mean_pixel_error - 2.0).abs() < 1e-12);
    }
}
