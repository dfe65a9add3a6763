//! The stability sweep: where each integrator is stable, stable but wrong, or unstable, over time
//! step, spring stiffness, wind speed and head-shake speed, on a straight and a curly test chain.
//!
//! **Runs.** Each run simulates one test chain for [`SweepConfig::duration`] seconds from its rest
//! shape (roots horizontal, so gravity makes it fall and swing) under one *scenario* (a stiffness,
//! a gusting wind, a head shake) with one integrator at one time step (one substep per step,
//! failures are errors).
//!
//! **Reference.** The same scenario and model run with the linear-implicit integrator at a substep
//! of at most [`SweepConfig::reference_substep`] and at most a tenth of the period of the fastest
//! spring mode, in steps of [`SweepConfig::frame_step`] (the wind, sampled once per step, is held
//! over a frame as in the frame study), so that it has converged (the explicit integrator would need far smaller steps for
//! the stiffest scenarios: its stiffness-proportional damping alone limits it to `h < 2/(β·ω²)`).
//!
//! **Classes.**
//! - *unstable*: the run returned an error (a non-finite value, or a kinetic energy per unit mass
//!   above `½·(50 m/s)²`), or its motion ratio `ρ` (below) exceeds [`SweepConfig::blow_up_ratio`]:
//!   a bounded blow-up, energy pumped in by the integrator and kept finite only by the length
//!   projection (explicit springs at `h·ω > 2` saturate this way instead of overflowing).
//! - *damped-wrong*: it finished, but either the early position error
//!   `e = √(mean over nodes and the samples up to` [`SweepConfig::early_window`] `of |x − x_ref|²) / L`
//!   (samples every [`SweepConfig::sample_interval`] s, `L` the chain length) exceeds
//!   [`SweepConfig::error_tolerance`], or the motion ratio `ρ = (D + 0.02 L)/(D_ref + 0.02 L)`
//!   (`D` the RMS distance from the head-carried rest shape over the whole run) is outside
//!   [`SweepConfig::motion_ratio_range`]: the motion is wrong, typically over-damped or frozen
//!   (`ρ < 1`). The early window and the ratio make the measure robust to the chaotic divergence
//!   of a whipping chain, which makes later trajectories incomparable even between two correct
//!   runs.
//! - *stable*: finished with both measures within their tolerances.
//!
//! This module holds what the sweep covers (the test chains, scenarios and [`SweepConfig`]);
//! `report` the results' types, `sweep` the runs and their classes, `cost` the cost measurement.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::dynamics::head_motion::HeadMotion;
use crate::dynamics::params::{DynamicsParams, IntegratorKind};
use crate::dynamics::simulation::Environment;
use crate::dynamics::wind::WindField;
use crate::frame::Frame;
use crate::skeleton::SkeletonRest;
use crate::style::{HairStyle, StyleKind};

mod cost;
mod report;
mod sweep;

pub use report::{IntegratorSummary, Outcome, RunResult, StabilityReport, StepCost, SubstepNeed};
pub use sweep::run_sweep;

/// The test chains of the sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TestChain {
    /// Straight hair, 0.25 m, 2 cm segments.
    Straight,
    /// Ringlet curls, 0.25 m, curl factor 50°, radius 1 cm.
    Curly,
}

impl TestChain {
    /// Both chains.
    pub const ALL: [TestChain; 2] = [TestChain::Straight, TestChain::Curly];

    /// The chain's style.
    pub fn style(self) -> HairStyle {
        match self {
            TestChain::Straight => HairStyle::straight(0.02),
            TestChain::Curly => HairStyle::curly(50.0, 0.01, 0.02),
        }
    }

    /// Name.
    pub fn name(self) -> &'static str {
        self.style().kind.name()
    }

    /// Chain length [m].
    pub const LENGTH: f32 = 0.25;

    /// A rest model with this chain rooted at the top front of a head-sized sphere, growing
    /// horizontally forward (+Z), its normal up (+Y).
    pub fn rest(self) -> SkeletonRest {
        let mut rest = SkeletonRest::default();
        let frame = Frame::from_tangent_and_normal(Vec3::Z, Vec3::Y).expect("axes are orthogonal");
        let angles = self
            .style()
            .chain_angles(Self::LENGTH)
            .expect("the test styles are valid");
        rest.push_chain(Vec3::new(0.0, 0.1, 0.1), frame, &angles)
            .expect("the test chain is valid");
        rest
    }
}

/// One disturbance of the test chain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scenario {
    /// Short label for charts.
    pub label: String,
    /// Bending stiffness per unit mass `EI/λ` [m³/s²]; `None`: the chain's style default.
    pub stiffness_per_mass: Option<f32>,
    /// Mean speed of a gusting wind across the hair (+X) [m/s]; gusts of a third of it.
    pub wind_speed: f32,
    /// Peak angular speed of a head shake (amplitude 0.5 rad) [rad/s].
    pub shake_speed: f32,
}

impl Scenario {
    /// The environment of this scenario.
    pub fn environment(&self) -> Environment {
        let wind = if self.wind_speed > 0.0 {
            WindField::gusting(
                Vec3::X * self.wind_speed,
                self.wind_speed / 3.0,
                0.7,
                0.3,
                11,
            )
        } else {
            WindField::Calm
        };
        let head = if self.shake_speed > 0.0 {
            HeadMotion::shake(0.5, self.shake_speed)
        } else {
            HeadMotion::default()
        };
        Environment {
            head,
            wind,
            ..Environment::default()
        }
    }

    /// The material of this scenario for a chain of `style`.
    pub fn params(&self, style: &HairStyle) -> DynamicsParams {
        let mut params = DynamicsParams::for_style(style);
        if let Some(stiffness) = self.stiffness_per_mass {
            params.bending_stiffness = params.linear_density * stiffness;
        }
        params
    }
}

/// What the sweep covers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepConfig {
    /// Integrators to map.
    pub integrators: Vec<IntegratorKind>,
    /// Test chains.
    pub chains: Vec<TestChain>,
    /// Time steps [s] (one substep per step); each must divide `sample_interval`.
    pub time_steps: Vec<f32>,
    /// Scenarios (rows of the map, per chain).
    pub scenarios: Vec<Scenario>,
    /// Simulated time per run [s].
    pub duration: f32,
    /// Interval between compared samples [s].
    pub sample_interval: f32,
    /// Largest substep of the reference runs [s].
    pub reference_substep: f32,
    /// Early position error `e` (fraction of the chain length) above which a finished run is
    /// damped-wrong.
    pub error_tolerance: f32,
    /// Time over which the early position error is measured [s].
    pub early_window: f32,
    /// Allowed range of the motion ratio `ρ`.
    pub motion_ratio_range: (f32, f32),
    /// Motion ratio above which a finished run counts as unstable.
    pub blow_up_ratio: f32,
    /// The frame step of the substep study [s] (60 Hz).
    pub frame_step: f32,
    /// Substep counts per frame tried in the substep study, ascending; empty skips the study.
    pub frame_substeps: Vec<u32>,
}

/// The spring stiffness range of the styles, `EI/λ` [m³/s²]: straight to curly.
pub fn style_stiffness_range() -> (f32, f32) {
    (
        DynamicsParams::stiffness_per_mass(StyleKind::Straight),
        DynamicsParams::stiffness_per_mass(StyleKind::Curly),
    )
}

impl Default for SweepConfig {
    /// Time steps 1/1000 … 1/15 s; stiffness over the styles' range and 10× and 100× beyond (with a
    /// 3 rad/s head shake); gusting wind of 3, 10 and 25 m/s; head shakes of 1.5, 5 and 10 rad/s;
    /// 3 s per run, samples every 0.2 s, early error within 10% of the chain length over the first
    /// 0.6 s, motion ratio within 0.75..1.33, unstable above 2; the substep study at 60 Hz frames
    /// with 1, 2, 4, … 64 substeps.
    fn default() -> Self {
        let (low, high) = style_stiffness_range();
        let stiffness = |label: &str, stiffness_per_mass| Scenario {
            label: label.to_string(),
            stiffness_per_mass: Some(stiffness_per_mass),
            wind_speed: 0.0,
            shake_speed: 3.0,
        };
        let wind = |label: &str, wind_speed| Scenario {
            label: label.to_string(),
            stiffness_per_mass: None,
            wind_speed,
            shake_speed: 0.0,
        };
        let shake = |label: &str, shake_speed| Scenario {
            label: label.to_string(),
            stiffness_per_mass: None,
            wind_speed: 0.0,
            shake_speed,
        };
        SweepConfig {
            integrators: IntegratorKind::ALL.to_vec(),
            chains: TestChain::ALL.to_vec(),
            time_steps: vec![
                1.0 / 1000.0,
                1.0 / 500.0,
                1.0 / 250.0,
                1.0 / 120.0,
                1.0 / 60.0,
                1.0 / 30.0,
                1.0 / 15.0,
            ],
            scenarios: vec![
                stiffness("k straight", low),
                stiffness("k curly", high),
                stiffness("k 10x", 10.0 * high),
                stiffness("k 100x", 100.0 * high),
                wind("wind 3 m/s", 3.0),
                wind("wind 10 m/s", 10.0),
                wind("wind 25 m/s", 25.0),
                shake("shake 1.5 rad/s", 1.5),
                shake("shake 5 rad/s", 5.0),
                shake("shake 10 rad/s", 10.0),
            ],
            duration: 3.0,
            sample_interval: 0.2,
            reference_substep: 1.0 / 6000.0,
            error_tolerance: 0.10,
            early_window: 0.6,
            motion_ratio_range: (0.75, 1.33),
            blow_up_ratio: 2.0,
            frame_step: 1.0 / 60.0,
            frame_substeps: vec![1, 2, 4, 8, 16, 32, 64],
        }
    }
}
