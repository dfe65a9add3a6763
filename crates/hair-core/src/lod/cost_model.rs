//! What a section costs at each level [s], from a model calibrated while the pipeline runs: the
//! cost side of the frame budget that minimises error ([`refine_within_budget`]).
//!
//! A section at level `l` costs
//!
//! ```text
//! c_l(s) = a_l · n_l(s) + [visible] · (b_l · d_l(s) + f_l · A(s))
//! ```
//!
//! with `n_l(s)` its skeleton nodes at that level (dynamics and collision), `d_l(s)` the segments
//! it draws there (a strand group draws each of its strands) and `A(s)` the screen area it covers
//! [pixels] (its bounding sphere's disc, at most the image): seconds per node `a_l`, per drawn
//! segment `b_l` (vertex work) and per covered pixel `f_l` (fill: a close-up cluster fills many
//! pixels on a CPU rasteriser). A frame's cost adds an overhead `c₀`.
//!
//! **Calibration.** The dynamics and collision of each level are timed apart, so `a_l` is the
//! measured time per node of that level's block, smoothed (exponentially, weight
//! [`CostModel::SMOOTHING`]). Rendering draws all levels at once, so `(b_l, f_l, c₀)` are fitted
//! by recursive least squares to each frame's rendering time against its drawn segments and
//! covered pixels per level, with forgetting factor [`CostModel::FORGETTING`] and starting from
//! prior rates (so that a level not yet drawn has a sensible cost). A rate the frames cannot
//! separate from the others can drift anywhere along the fit's null space; each is kept at
//! least [`CostModel::FLOOR`] of its prior, so that no level ever looks free.

use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result};

/// Costs per unit of work [s]: the model's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CostRates {
    /// Dynamics and collision per skeleton node per frame at each level [s].
    pub per_node: [f64; 3],
    /// Rendering per drawn segment at each level [s].
    pub per_drawn_segment: [f64; 3],
    /// Rendering per covered pixel at each level [s].
    pub per_pixel: [f64; 3],
    /// Rendering overhead per frame [s].
    pub overhead: f64,
}

impl Default for CostRates {
    /// Priors of the order measured on the 2-core development machine (paper-curly,
    /// linear-implicit ×4, lavapipe at 640×360): about 1 µs per node-frame at every level;
    /// 0.5 µs per strand segment and 5 µs per cluster or patch segment; 0.2 µs per covered pixel
    /// for clusters and patches and 0.1 µs for strands; 5 ms a frame.
    fn default() -> Self {
        CostRates {
            per_node: [1e-6; 3],
            per_drawn_segment: [5e-6, 5e-6, 0.5e-6],
            per_pixel: [0.2e-6, 0.2e-6, 0.1e-6],
            overhead: 5e-3,
        }
    }
}

/// The work a section does at each level: skeleton nodes and drawn segments (indexed by level
/// rank: patch, clusters, strand groups).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SectionWork {
    /// Skeleton nodes at each level.
    pub nodes: [usize; 3],
    /// Segments drawn at each level.
    pub drawn_segments: [usize; 3],
}

/// Parameters of the rendering fit: per-segment and per-pixel rates of the three levels, and
/// the overhead.
const FIT: usize = 7;

/// The calibrated cost model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostModel {
    rates: CostRates,
    prior: CostRates,
    /// Inverse-information matrix of the rendering fit, in scaled units (see `SCALE`).
    covariance: [[f64; FIT]; FIT],
    /// Whether each level's per-node rate has been measured yet.
    measured_nodes: [bool; 3],
}

/// Drawn segments and covered pixels are counted in units of `SCALE` in the fit, so that its
/// parameters are of order one.
const SCALE: f64 = 1e5;

impl CostModel {
    /// Weight of a new measurement of a level's per-node rate.
    pub const SMOOTHING: f64 = 0.2;
    /// Forgetting factor of the rendering fit (older frames weigh `FORGETTING^age`).
    pub const FORGETTING: f64 = 0.95;
    /// Smallest fraction of its prior a rate may fall to.
    pub const FLOOR: f64 = 0.1;

    /// A model starting from `prior` rates (all finite and ≥ 0).
    pub fn new(prior: CostRates) -> Result<CostModel> {
        let values = prior
            .per_node
            .iter()
            .chain(&prior.per_drawn_segment)
            .chain(&prior.per_pixel)
            .chain([&prior.overhead]);
        for &value in values {
            if !(value.is_finite() && value >= 0.0) {
                return Err(HairError::invalid(
                    "cost model prior rate (s)",
                    value,
                    "finite and >= 0",
                ));
            }
        }
        // Prior uncertainty: ten times the prior's own size (a rate may be off by far).
        let mut covariance = [[0.0; FIT]; FIT];
        for (k, (row, value)) in covariance
            .iter_mut()
            .zip(Self::parameters(&prior))
            .enumerate()
        {
            row[k] = value.max(1e-4).powi(2) * 1e2;
        }
        Ok(CostModel {
            rates: prior,
            prior,
            covariance,
            measured_nodes: [false; 3],
        })
    }

    /// The current rates.
    pub fn rates(&self) -> &CostRates {
        &self.rates
    }

    /// The fit's parameters in scaled units.
    fn parameters(rates: &CostRates) -> [f64; FIT] {
        let r = rates;
        [
            r.per_drawn_segment[0] * SCALE,
            r.per_drawn_segment[1] * SCALE,
            r.per_drawn_segment[2] * SCALE,
            r.per_pixel[0] * SCALE,
            r.per_pixel[1] * SCALE,
            r.per_pixel[2] * SCALE,
            r.overhead,
        ]
    }

    /// The predicted cost [s] of a section doing `work` at each level; when drawn, it covers
    /// `pixels` of the image (`None`: not drawn).
    pub fn section_costs(&self, work: &SectionWork, drawn_pixels: Option<f64>) -> [f64; 3] {
        std::array::from_fn(|level| {
            let dynamics = self.rates.per_node[level] * work.nodes[level] as f64;
            let drawing = match drawn_pixels {
                Some(pixels) => {
                    self.rates.per_drawn_segment[level] * work.drawn_segments[level] as f64
                        + self.rates.per_pixel[level] * pixels
                }
                None => 0.0,
            };
            dynamics + drawing
        })
    }

    /// Records one frame: `level_seconds` [s] of dynamics and collision per level for
    /// `level_nodes` nodes, and `render` (`None`: the frame was not rendered): the rendering
    /// time [s] for the drawn segments and covered pixels per level. Non-finite or negative
    /// times are ignored.
    pub fn observe(
        &mut self,
        level_seconds: [f64; 3],
        level_nodes: [usize; 3],
        render: Option<RenderSample>,
    ) {
        for level in 0..3 {
            let (seconds, nodes) = (level_seconds[level], level_nodes[level]);
            if nodes == 0 || !(seconds.is_finite() && seconds >= 0.0) {
                continue;
            }
            let rate = seconds / nodes as f64;
            let old = &mut self.rates.per_node[level];
            *old = if self.measured_nodes[level] {
                (1.0 - Self::SMOOTHING) * *old + Self::SMOOTHING * rate
            } else {
                rate
            }
            .max(Self::FLOOR * self.prior.per_node[level]);
            self.measured_nodes[level] = true;
        }
        if let Some(sample) = render
            && sample.seconds.is_finite()
            && sample.seconds >= 0.0
        {
            self.fit_render(&sample);
        }
    }

    /// One recursive-least-squares step of the rendering fit.
    fn fit_render(&mut self, sample: &RenderSample) {
        let (d, a) = (sample.drawn_segments, sample.pixels);
        let x = [
            d[0] as f64 / SCALE,
            d[1] as f64 / SCALE,
            d[2] as f64 / SCALE,
            a[0] / SCALE,
            a[1] / SCALE,
            a[2] / SCALE,
            1.0,
        ];
        let mut theta = Self::parameters(&self.rates);
        let floors = Self::parameters(&self.prior).map(|value| Self::FLOOR * value);
        let p = &mut self.covariance;
        let px: [f64; FIT] = std::array::from_fn(|i| (0..FIT).map(|j| p[i][j] * x[j]).sum());
        let xpx: f64 = (0..FIT).map(|i| x[i] * px[i]).sum();
        let lambda = Self::FORGETTING;
        let gain: [f64; FIT] = std::array::from_fn(|i| px[i] / (lambda + xpx));
        let residual = sample.seconds - (0..FIT).map(|i| x[i] * theta[i]).sum::<f64>();
        for ((value, gain), floor) in theta.iter_mut().zip(gain).zip(floors) {
            *value = (*value + gain * residual).max(floor);
        }
        for (i, row) in p.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                *entry = (*entry - gain[i] * px[j]) / lambda;
            }
        }
        for level in 0..3 {
            self.rates.per_drawn_segment[level] = theta[level] / SCALE;
            self.rates.per_pixel[level] = theta[3 + level] / SCALE;
        }
        self.rates.overhead = theta[6];
    }
}

/// One rendered frame, for the rendering fit.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RenderSample {
    /// Rendering time [s].
    pub seconds: f64,
    /// Segments drawn at each level.
    pub drawn_segments: [usize; 3],
    /// Pixels covered by the sections drawn at each level (their bounding discs).
    pub pixels: [f64; 3],
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    #[test]
    fn the_fit_recovers_rates_from_noisy_frames() {
        // Frames drawn from known rates with uniform ±0.2 % noise on a render of about 0.13 s
        // (σ ≈ 0.15 ms). The fit remembers about 1 / (1 − 0.95) = 20 frames, so a rate whose
        // feature spreads by s (standard deviation) is known to about σ / (s·√20): the weakest,
        // the patches' per-pixel rate (s ≈ 14,000 px, 0.1 µs), to about 2.3 %; every rate must
        // land within 10 % (over 4σ), the overhead within 0.5 ms.
        let truth = CostRates {
            per_node: [2e-6, 1.5e-6, 1e-6],
            per_drawn_segment: [20e-6, 6e-6, 0.3e-6],
            per_pixel: [0.1e-6, 0.3e-6, 0.05e-6],
            overhead: 3e-3,
        };
        let mut model = CostModel::new(CostRates::default()).unwrap();
        let mut rng = SplitMix64::new(5);
        for _ in 0..400 {
            let drawn = [
                (rng.range(0.0, 2000.0)) as usize,
                (rng.range(0.0, 6000.0)) as usize,
                (rng.range(0.0, 400_000.0)) as usize,
            ];
            let nodes = [
                rng.range(100.0, 1200.0) as usize,
                rng.range(100.0, 3600.0) as usize,
                rng.range(100.0, 6000.0) as usize,
            ];
            let noise =
                |value: f64, rng: &mut SplitMix64| value * f64::from(rng.range(0.998, 1.002));
            let level_seconds =
                std::array::from_fn(|l| noise(truth.per_node[l] * nodes[l] as f64, &mut rng));
            let pixels = [
                f64::from(rng.range(0.0, 50_000.0)),
                f64::from(rng.range(0.0, 150_000.0)),
                f64::from(rng.range(0.0, 200_000.0)),
            ];
            let render: f64 = (0..3)
                .map(|l| {
                    truth.per_drawn_segment[l] * drawn[l] as f64 + truth.per_pixel[l] * pixels[l]
                })
                .sum::<f64>()
                + truth.overhead;
            let sample = RenderSample {
                seconds: noise(render, &mut rng),
                drawn_segments: drawn,
                pixels,
            };
            model.observe(level_seconds, nodes, Some(sample));
        }
        let rates = model.rates();
        let close = |a: f64, b: f64| (a - b).abs() <= 0.1 * b;
        for level in 0..3 {
            assert!(
                close(rates.per_node[level], truth.per_node[level]),
                "{rates:?}"
            );
            assert!(
                close(
                    rates.per_drawn_segment[level],
                    truth.per_drawn_segment[level]
                ),
                "{rates:?}"
            );
            assert!(
                close(rates.per_pixel[level], truth.per_pixel[level]),
                "{rates:?}"
            );
        }
        assert!((rates.overhead - truth.overhead).abs() < 5e-4, "{rates:?}");
    }

    #[test]
    fn hidden_sections_cost_only_their_dynamics() {
        let model = CostModel::new(CostRates::default()).unwrap();
        let work = SectionWork {
            nodes: [13, 39, 65],
            drawn_segments: [12, 36, 4980],
        };
        let hidden = model.section_costs(&work, None);
        let shown = model.section_costs(&work, Some(1000.0));
        for level in 0..3 {
            assert_eq!(hidden[level], 1e-6 * work.nodes[level] as f64);
            assert!(shown[level] > hidden[level]);
        }
    }

    #[test]
    fn no_level_ever_looks_free() {
        // Frames that cost nothing at all drive every rate down, but not below a tenth of its
        // prior: a refinement never looks free to the budget.
        let prior = CostRates::default();
        let mut model = CostModel::new(prior).unwrap();
        for _ in 0..200 {
            let sample = RenderSample {
                seconds: 0.0,
                drawn_segments: [1000, 3000, 400_000],
                pixels: [1e4, 3e4, 1e5],
            };
            model.observe([0.0; 3], [100, 300, 500], Some(sample));
        }
        let rates = model.rates();
        for level in 0..3 {
            assert_eq!(rates.per_node[level], 0.1 * prior.per_node[level]);
            assert!(rates.per_drawn_segment[level] >= 0.1 * prior.per_drawn_segment[level]);
            assert!(rates.per_pixel[level] >= 0.1 * prior.per_pixel[level]);
        }
    }

    #[test]
    fn bad_priors_are_refused() {
        let prior = CostRates {
            overhead: f64::NAN,
            ..CostRates::default()
        };
        assert!(CostModel::new(prior).is_err());
    }
}
