//! Frame-budget mode: a controller that raises or lowers the selector's pixel tolerance so that
//! the frame's cost meets a time budget.
//!
//! **The law.** After frame `n`, whose measured cost is `c_n` [s], with budget `B` [s]:
//!
//! ```text
//! s_n       = (1 − α)·s_{n−1} + α·c_n                 (smoothed cost; s_0 = c_0)
//! log τ_n+1 = log τ_n + g·log(s_n / (m·B))           (integral control in log space)
//! τ_n+1     ∈ [τ_min, τ_max]                          (clamped)
//! ```
//!
//! with smoothing `α`, gain `g` and margin `m < 1` (the controller aims a little under the
//! budget so that frame-to-frame noise does not push most frames over it). The tolerance is left
//! unchanged while `s_n` is within `±dead_band` (relative) of `m·B`, so a met budget does not make
//! the levels dither.
//!
//! **Lag.** A lower tolerance adds detail that is blended in over the LOD blend time, so its
//! cost shows only after it. With `hold_frames = h`, a lowering of `τ` is followed by `h` frames
//! in which `τ` may rise but not fall again, so the controller does not keep lowering on costs
//! that do not yet include its last step.
//!
//! Why log space: the cost falls roughly as a power of the tolerance (`c ≈ a + b·τ^−p`, the drawn
//! detail shrinks as the limits grow with `τ`). Near the fixed point the log-error then evolves as
//! `e_n+1 ≈ (1 − g·p')·e_n` with `p'` the local slope `−d log c / d log τ ≤ p`, which converges
//! for `0 < g·p' < 2`: the default `g = 0.5` is stable for slopes up to 4 and needs no model of the
//! scene. Costs that no tolerance can meet (below the cost of patches only) drive `τ` to `τ_max`,
//! and the report says how often the budget was met.

use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result, require_positive};

crate::named_enum! {
    /// How a frame budget is met.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum BudgetMethod {
        /// Levels chosen every frame to minimise the total estimated error within the budget
        /// ([`LodSelector::select_within_budget`](super::LodSelector::select_within_budget): greedy
        /// refinement by error saved per unit cost, costs from a [`CostModel`](super::CostModel)
        /// calibrated as the run goes). The pixel tolerance plays no part.
        #[default]
        Greedy = "greedy",
        /// The pixel tolerance steered by a [`BudgetController`] (the law below).
        Tolerance = "tolerance",
    }
}

/// Settings of a frame budget: its method, and the law of the [`BudgetController`] (used by
/// [`BudgetMethod::Tolerance`]; the greedy method uses only `budget` and `margin`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BudgetSettings {
    /// Time budget per frame [s].
    pub budget: f64,
    /// Gain `g` of the log-space integral law (0 < g ≤ 1).
    pub gain: f64,
    /// Smoothing `α` of the measured cost (0 < α ≤ 1; 1: no smoothing).
    pub smoothing: f64,
    /// Margin `m`: the controller aims at `m·budget` (0 < m ≤ 1).
    pub margin: f64,
    /// Relative dead band around the aim inside which the tolerance stays put (≥ 0).
    pub dead_band: f64,
    /// Smallest tolerance the controller may choose [pixels].
    pub min_tolerance: f32,
    /// Largest tolerance the controller may choose [pixels].
    pub max_tolerance: f32,
    /// Frames after a lowering of the tolerance during which it is not lowered again (it may
    /// still rise). The detail a lower tolerance adds is drawn over the old level for the blend
    /// time, so its cost shows only afterwards: set this to the blend time in frames. 0: no hold.
    #[serde(default)]
    pub hold_frames: usize,
    /// How the budget is met.
    #[serde(default)]
    pub method: BudgetMethod,
}

impl BudgetSettings {
    /// A budget of `budget` seconds per frame met by the greedy method, aiming at 0.9 of it; the
    /// controller's law (for [`BudgetMethod::Tolerance`]): gain 0.5, smoothing 0.5, margin 0.9,
    /// dead band 5 %, tolerance between 0.25 and 64 pixels, no hold.
    pub fn new(budget: f64) -> Self {
        BudgetSettings {
            budget,
            gain: 0.5,
            smoothing: 0.5,
            margin: 0.9,
            dead_band: 0.05,
            min_tolerance: 0.25,
            max_tolerance: 64.0,
            hold_frames: 0,
            method: BudgetMethod::Greedy,
        }
    }

    /// Checks every setting, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        if !(self.budget.is_finite() && self.budget > 0.0) {
            return Err(HairError::invalid(
                "frame budget (s)",
                self.budget,
                "a positive number of seconds",
            ));
        }
        let unit = |name: &'static str, value: f64| {
            if value > 0.0 && value <= 1.0 {
                Ok(())
            } else {
                Err(HairError::invalid(name, value, "0 < value <= 1"))
            }
        };
        unit("budget controller gain", self.gain)?;
        unit("budget controller smoothing", self.smoothing)?;
        unit("budget controller margin", self.margin)?;
        if !(self.dead_band.is_finite() && (0.0..0.5).contains(&self.dead_band)) {
            return Err(HairError::invalid(
                "budget controller dead band",
                self.dead_band,
                "0 <= band < 0.5",
            ));
        }
        require_positive("minimum pixel tolerance (pixels)", self.min_tolerance)?;
        require_positive("maximum pixel tolerance (pixels)", self.max_tolerance)?;
        if self.max_tolerance < self.min_tolerance {
            return Err(HairError::invalid(
                "maximum pixel tolerance (pixels)",
                self.max_tolerance,
                "at least the minimum pixel tolerance",
            ));
        }
        Ok(())
    }
}

/// How a budgeted run went.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct BudgetReport {
    /// Budget per frame [s].
    pub budget: f64,
    /// Frames measured.
    pub frames: usize,
    /// Frames whose cost was at most the budget.
    pub met: usize,
    /// `met / frames`.
    pub met_fraction: f64,
    /// Mean cost per frame [s].
    pub mean_cost: f64,
    /// Mean pixel tolerance the frames ran at [pixels].
    pub mean_tolerance: f64,
    /// Largest pixel tolerance chosen [pixels].
    pub max_tolerance: f32,
    /// How the budget was met.
    #[serde(default)]
    pub method: BudgetMethod,
}

/// The frame-budget controller (see the module documentation for the law).
#[derive(Debug, Clone)]
pub struct BudgetController {
    settings: BudgetSettings,
    tolerance: f32,
    smoothed: Option<f64>,
    frames: usize,
    met: usize,
    cost_sum: f64,
    tolerance_sum: f64,
    max_seen: f32,
    /// Frames left before the tolerance may be lowered again.
    hold_left: usize,
}

impl BudgetController {
    /// A controller starting from `initial_tolerance` [pixels] (clamped to the settings' range).
    pub fn new(settings: BudgetSettings, initial_tolerance: f32) -> Result<Self> {
        settings.validate()?;
        require_positive("initial pixel tolerance (pixels)", initial_tolerance)?;
        let tolerance = initial_tolerance.clamp(settings.min_tolerance, settings.max_tolerance);
        Ok(BudgetController {
            settings,
            tolerance,
            smoothed: None,
            frames: 0,
            met: 0,
            cost_sum: 0.0,
            tolerance_sum: 0.0,
            max_seen: tolerance,
            hold_left: 0,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &BudgetSettings {
        &self.settings
    }

    /// The tolerance for the next frame [pixels].
    pub fn tolerance(&self) -> f32 {
        self.tolerance
    }

    /// Records the cost [s] of the frame that ran at [`tolerance`](Self::tolerance) and returns
    /// the tolerance for the next frame (unchanged under [`BudgetMethod::Greedy`], for which the
    /// controller only counts). A negative or non-finite cost is an error.
    pub fn update(&mut self, cost: f64) -> Result<f32> {
        if !(cost.is_finite() && cost >= 0.0) {
            return Err(HairError::invalid(
                "measured frame cost (s)",
                cost,
                "a finite, non-negative number of seconds",
            ));
        }
        let s = &self.settings;
        self.frames += 1;
        if cost <= s.budget {
            self.met += 1;
        }
        self.cost_sum += cost;
        self.tolerance_sum += f64::from(self.tolerance);
        let smoothed = match self.smoothed {
            Some(previous) => (1.0 - s.smoothing) * previous + s.smoothing * cost,
            None => cost,
        };
        self.smoothed = Some(smoothed);
        if s.method == BudgetMethod::Greedy {
            // The greedy method chooses levels itself: the controller only keeps the tally.
            return Ok(self.tolerance);
        }
        let aim = s.margin * s.budget;
        let ratio = smoothed.max(1e-12) / aim;
        let holding = self.hold_left > 0;
        self.hold_left = self.hold_left.saturating_sub(1);
        // Over the aim: raise at once. Under it: lower, unless a recent lowering's cost has not
        // shown yet.
        if (ratio - 1.0).abs() > s.dead_band && (ratio > 1.0 || !holding) {
            let next = ((f64::from(self.tolerance) * ratio.powf(s.gain)) as f32)
                .clamp(s.min_tolerance, s.max_tolerance);
            if next < self.tolerance {
                self.hold_left = s.hold_frames;
            }
            self.tolerance = next;
        }
        self.max_seen = self.max_seen.max(self.tolerance);
        Ok(self.tolerance)
    }

    /// How the frames so far went.
    pub fn report(&self) -> BudgetReport {
        let n = self.frames.max(1) as f64;
        BudgetReport {
            budget: self.settings.budget,
            frames: self.frames,
            met: self.met,
            met_fraction: self.met as f64 / n,
            mean_cost: self.cost_sum / n,
            mean_tolerance: self.tolerance_sum / n,
            max_tolerance: self.max_seen,
            method: self.settings.method,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The controller's law (the tolerance method) for a budget of `budget` seconds.
    fn law(budget: f64) -> BudgetSettings {
        BudgetSettings {
            method: BudgetMethod::Tolerance,
            ..BudgetSettings::new(budget)
        }
    }

    /// A synthetic scene whose frame costs `a + b/τ` seconds at tolerance `τ`.
    fn plant(a: f64, b: f64) -> impl Fn(f32) -> f64 {
        move |tolerance| a + b / f64::from(tolerance)
    }

    /// A scene whose cost answers a tolerance change `lag` frames late (the blend): the frame
    /// at step `n` costs `a + b/τ_{n−lag}`. Starting cheap (τ = 16 px against an equilibrium of
    /// 4.5 px), the plain law lowers τ every frame on stale costs and overshoots into frames far
    /// over the budget; holding for the lag lowers once per lag and stays within it.
    #[test]
    fn holding_for_the_lag_stops_the_overshoot() {
        let cost = plant(0.002, 0.040);
        let lag = 15;
        let run = |hold_frames: usize| {
            let settings = BudgetSettings {
                hold_frames,
                ..law(0.012)
            };
            let mut controller = BudgetController::new(settings, 16.0).unwrap();
            let mut history = vec![16.0f32; lag];
            let mut worst = 0.0f64;
            for _ in 0..300 {
                history.push(controller.tolerance());
                let c = cost(history[history.len() - 1 - lag]);
                worst = worst.max(c);
                controller.update(c).unwrap();
            }
            (worst, controller.tolerance())
        };
        let (plain_worst, _) = run(0);
        let (held_worst, held_tolerance) = run(lag);
        eprintln!("worst frame: plain {plain_worst} s, held {held_worst} s (τ {held_tolerance})");
        // τ* = 4.545 px costs the aim 10.8 ms; the plain law goes past τ* on stale costs and
        // pays for it: more than the 12 ms budget.
        assert!(
            plain_worst > 0.012,
            "plain law: worst frame {plain_worst} s"
        );
        assert!(held_worst <= 0.012, "held: worst frame {held_worst} s");
        // And the held controller still gets close to the tolerance that meets the aim.
        let expected = 0.040 / (0.9 * 0.012 - 0.002);
        assert!(
            (f64::from(held_tolerance) / expected - 1.0).abs() < 0.1,
            "{held_tolerance} against {expected}"
        );
    }

    #[test]
    fn converges_to_the_tolerance_that_meets_the_aim() {
        // cost = a + b/τ = m·B  ⇒  τ* = b / (m·B − a) = 0.040 / (0.9·0.012 − 0.002) = 4.545 px.
        let cost = plant(0.002, 0.040);
        let settings = BudgetSettings {
            dead_band: 0.0,
            ..law(0.012)
        };
        let mut controller = BudgetController::new(settings, 1.0).unwrap();
        for _ in 0..60 {
            let c = cost(controller.tolerance());
            controller.update(c).unwrap();
        }
        let expected = 0.040 / (0.9 * 0.012 - 0.002);
        let tolerance = f64::from(controller.tolerance());
        // Local slope p' = b/(τ·c) = 0.040/(4.545·0.0108) ≈ 0.81, so the error shrinks by about
        // (1 − 0.5·0.81) = 0.59 per frame (slower with the smoothing); after 60 frames from a
        // factor 4.5 off, it is far below 0.1 %.
        assert!(
            (tolerance / expected - 1.0).abs() < 1e-3,
            "{tolerance} against {expected}"
        );
        // The first frames at τ = 1 px cost 42 ms > 12 ms; the rest meet the budget.
        let report = controller.report();
        assert_eq!(report.frames, 60);
        assert!(report.met >= 50, "{report:?}");
        assert!(report.met < 60, "{report:?}");
    }

    #[test]
    fn a_steep_cost_curve_still_converges() {
        // cost = b/τ²: slope p' = 2, g·p' = 1, the log-error vanishes in one step without
        // smoothing; with smoothing it converges geometrically. τ* = sqrt(b / (m·B)).
        let settings = BudgetSettings {
            dead_band: 0.0,
            ..law(0.010)
        };
        let mut controller = BudgetController::new(settings, 16.0).unwrap();
        for _ in 0..80 {
            let t = f64::from(controller.tolerance());
            controller.update(0.050 / (t * t)).unwrap();
        }
        let expected = (0.050f64 / 0.009).sqrt();
        let tolerance = f64::from(controller.tolerance());
        assert!((tolerance / expected - 1.0).abs() < 1e-3, "{tolerance}");
    }

    #[test]
    fn an_unreachable_budget_saturates_and_says_so() {
        // The fixed cost a = 20 ms is above the 10 ms budget whatever the tolerance.
        let cost = plant(0.020, 0.010);
        let mut controller = BudgetController::new(law(0.010), 1.0).unwrap();
        for _ in 0..60 {
            let c = cost(controller.tolerance());
            controller.update(c).unwrap();
        }
        assert_eq!(controller.tolerance(), 64.0);
        assert_eq!(controller.report().met, 0);
    }

    #[test]
    fn the_dead_band_holds_a_met_budget_still() {
        let mut controller = BudgetController::new(law(0.010), 3.0).unwrap();
        // 0.0092 s is within 5 % of the aim 0.009 s.
        for _ in 0..10 {
            assert_eq!(controller.update(0.0092).unwrap(), 3.0);
        }
    }

    #[test]
    fn bad_inputs_are_named_errors() {
        let error = BudgetController::new(law(-1.0), 1.0).unwrap_err();
        assert!(error.to_string().contains("frame budget"), "{error}");
        let error = BudgetController::new(law(f64::NAN), 1.0).unwrap_err();
        assert!(error.to_string().contains("frame budget"), "{error}");
        let mut controller = BudgetController::new(law(0.01), 1.0).unwrap();
        let error = controller.update(f64::NAN).unwrap_err();
        assert!(error.to_string().contains("frame cost"), "{error}");
        let settings = BudgetSettings {
            gain: 0.0,
            ..law(0.01)
        };
        assert!(BudgetController::new(settings, 1.0).is_err());
    }
}
