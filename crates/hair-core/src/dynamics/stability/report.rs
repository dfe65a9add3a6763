//! The stability sweep's results: each run's class and measures, the per-integrator summaries,
//! the substep study's needs and the measured costs.

use serde::{Deserialize, Serialize};

use crate::dynamics::params::IntegratorKind;
use crate::dynamics::stability::{SweepConfig, TestChain};

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// Finished, position error within the tolerance.
    Stable,
    /// Finished, position error above the tolerance.
    DampedWrong,
    /// Failed with an error.
    Unstable,
}

impl Outcome {
    /// Name as in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Stable => "stable",
            Outcome::DampedWrong => "damped-wrong",
            Outcome::Unstable => "unstable",
        }
    }
}

/// One run of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Test chain.
    pub chain: TestChain,
    /// Index into [`SweepConfig::scenarios`].
    pub scenario: usize,
    /// Time step [s].
    pub time_step: f32,
    /// Substeps per step (1 in the map, the tried count in the substep study).
    pub substeps: u32,
    /// Class.
    pub outcome: Outcome,
    /// Early position error `e` (fraction of the chain length), when it finished.
    pub position_error: Option<f32>,
    /// Motion ratio `ρ`, when it finished.
    pub motion_ratio: Option<f32>,
    /// Largest relative segment length error seen at the samples.
    pub max_length_error: Option<f32>,
    /// The error message, when it failed.
    pub failure: Option<String>,
    /// Substeps per step, mean over the run's steps, when it finished (above `substeps` where
    /// the settings' adaptive substeps added some).
    #[serde(default)]
    pub mean_substeps: Option<f32>,
}

/// Per-integrator summary.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IntegratorSummary {
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Runs per class.
    pub stable: usize,
    /// Runs per class.
    pub damped_wrong: usize,
    /// Runs per class.
    pub unstable: usize,
    /// The largest time step [s] at which every run (all chains, all scenarios) is stable, if any.
    pub largest_all_stable_step: Option<f32>,
    /// The largest time step [s] at which no run is unstable, if any.
    pub largest_never_unstable_step: Option<f32>,
}

/// The sweep's result: configuration, every run and a summary per integrator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StabilityReport {
    /// What was swept.
    pub config: SweepConfig,
    /// The runs, integrator-major, then chain, scenario, time step.
    pub runs: Vec<RunResult>,
    /// One per integrator.
    pub summaries: Vec<IntegratorSummary>,
    /// The integrator with the most stable runs (ties: the larger all-stable step).
    pub widest_stable_region: IntegratorKind,
    /// The substep study's runs: every integrator, chain and scenario at
    /// [`SweepConfig::frame_step`] with each of [`SweepConfig::frame_substeps`].
    pub frame_runs: Vec<RunResult>,
    /// What each integrator needs at [`SweepConfig::frame_step`], per chain and scenario.
    pub frame_needs: Vec<SubstepNeed>,
    /// With the substep study: every integrator, chain and scenario at
    /// [`SweepConfig::frame_step`] with the integrator's recommended settings
    /// ([`SimulationSettings::recommended`](crate::dynamics::SimulationSettings::recommended),
    /// adaptive substeps included).
    #[serde(default)]
    pub recommended_runs: Vec<RunResult>,
    /// The measured cost of each integrator and substep count.
    pub costs: Vec<StepCost>,
}

/// How many substeps per frame one integrator needs in one scenario, and what that costs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SubstepNeed {
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Test chain.
    pub chain: TestChain,
    /// Index into [`SweepConfig::scenarios`].
    pub scenario: usize,
    /// The smallest tried substep count from which every larger tried count is stable; `None`
    /// when even the largest is not.
    pub substeps: Option<u32>,
    /// The early position error at that count (fraction of the chain length).
    pub position_error: Option<f32>,
    /// Its cost: one core's time per node per simulated second [µs], from [`StepCost`].
    pub microseconds_per_node_second: Option<f32>,
}

/// The measured cost of one integrator at one substep count per frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepCost {
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Substeps per frame.
    pub substeps: u32,
    /// One core's wall time per node and substep [ns].
    pub nanoseconds_per_node_substep: f32,
    /// One core's wall time per node per simulated second [µs] at [`SweepConfig::frame_step`].
    pub microseconds_per_node_second: f32,
}

impl StabilityReport {
    /// What `integrator` needs on `chain` in scenario `scenario` at 60 Hz, if studied.
    pub fn frame_need(
        &self,
        integrator: IntegratorKind,
        chain: TestChain,
        scenario: usize,
    ) -> Option<&SubstepNeed> {
        self.frame_needs
            .iter()
            .find(|n| n.integrator == integrator && n.chain == chain && n.scenario == scenario)
    }

    /// The run of `integrator` on `chain` in scenario `scenario` at time step index `step`.
    pub fn run(
        &self,
        integrator: IntegratorKind,
        chain: TestChain,
        scenario: usize,
        step: usize,
    ) -> Option<&RunResult> {
        let time_step = *self.config.time_steps.get(step)?;
        self.runs.iter().find(|r| {
            r.integrator == integrator
                && r.chain == chain
                && r.scenario == scenario
                && r.time_step == time_step
        })
    }
}
