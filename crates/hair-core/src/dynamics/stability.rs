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

use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::dynamics::error::DynamicsError;
use crate::dynamics::head_motion::HeadMotion;
use crate::dynamics::model::DynamicsModel;
use crate::dynamics::params::{DynamicsParams, IntegratorKind, SimulationSettings};
use crate::dynamics::simulation::{Environment, Simulation};
use crate::dynamics::state::SimulationState;
use crate::dynamics::wind::WindField;
use crate::frame::Frame;
use crate::skeleton::SkeletonRest;
use crate::style::{HairStyle, StyleKind};

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

/// Positions of every node at every sample time (sample-major).
struct Trajectory {
    samples: Vec<Vec<Vec3>>,
    max_length_error: f32,
}

/// Runs one chain in one scenario with `settings`, recording the positions every
/// `sample_interval` seconds (the time step must divide it).
fn simulate(
    chain: TestChain,
    scenario: &Scenario,
    settings: SimulationSettings,
    config: &SweepConfig,
) -> Result<Trajectory, DynamicsError> {
    let style = chain.style();
    let model = DynamicsModel::new(chain.rest(), scenario.params(&style))?;
    let environment = scenario.environment();
    let mut simulation = Simulation::new(model, settings)?;
    let mut state = simulation.rest_state(&environment, 0.0);
    let steps_per_sample = (config.sample_interval / settings.time_step)
        .round()
        .max(1.0) as usize;
    let sample_count = (config.duration / config.sample_interval).round() as usize;
    let mut samples = Vec::with_capacity(sample_count);
    let mut max_length_error = 0.0f32;
    for _ in 0..sample_count {
        simulation.run(&mut state, &environment, steps_per_sample)?;
        max_length_error = max_length_error.max(state.max_length_error(&simulation.model().rest));
        samples.push(state.node_positions.clone());
    }
    Ok(Trajectory {
        samples,
        max_length_error,
    })
}

/// RMS distance [m] of a trajectory from the rest shape carried by the head.
fn motion_from_rest(
    trajectory: &Trajectory,
    chain: TestChain,
    scenario: &Scenario,
    config: &SweepConfig,
) -> f32 {
    let rest = chain.rest();
    let environment = scenario.environment();
    let mut sum = 0.0f64;
    let mut count = 0usize;
    for (k, sample) in trajectory.samples.iter().enumerate() {
        let time = (k + 1) as f64 * config.sample_interval as f64;
        let carried = SimulationState::at_rest(&rest, &environment.head.transform_at(time), time);
        for (a, b) in sample.iter().zip(&carried.node_positions) {
            sum += (*a - *b).length_squared() as f64;
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt() as f32
}

/// The reference substep for a scenario [s]: at most `reference_substep`, at most a tenth of the
/// fastest spring's period, and dividing the sample interval.
fn reference_settings(
    chain: TestChain,
    scenario: &Scenario,
    config: &SweepConfig,
) -> SimulationSettings {
    let model = DynamicsModel::new(chain.rest(), scenario.params(&chain.style()))
        .expect("sweep parameters are valid");
    // Highest mode of the bending chain ≈ 4·ω_joint (alternating bends), period 2π/(4ω).
    let fastest = 4.0 * model.max_joint_frequency();
    let wanted = config
        .reference_substep
        .min(std::f32::consts::TAU / fastest.max(1e-6) / 10.0);
    // The wind is sampled once per step and held over its substeps, so the reference steps at
    // the frame step (60 Hz), as the frame study's runs do: stepping at the sample interval, its
    // gusts were held for 0.2 s, and no integrator converged to it in wind (measured:
    // linear-implicit with 64 substeps per frame 13 % and 27 % off on the straight chain at 10
    // and 25 m/s, its error growing with the substeps at 25 m/s; with the wind held per frame,
    // 0.1 % and 0.2 %).
    let ratio = config.sample_interval / config.frame_step;
    let step = if config.frame_step > 0.0 && (ratio - ratio.round()).abs() < 1e-3 {
        config.frame_step.min(config.sample_interval)
    } else {
        config.sample_interval
    };
    let substeps = (step / wanted).ceil().max(1.0) as u32;
    SimulationSettings::new(IntegratorKind::LinearImplicit, step, substeps)
}

/// Runs one integrator on one chain and scenario with `settings` and classifies the run against
/// the reference `(trajectory, motion)` of that case.
fn classify(
    integrator: IntegratorKind,
    chain: TestChain,
    s: usize,
    settings: SimulationSettings,
    reference: &(Trajectory, f32),
    config: &SweepConfig,
) -> RunResult {
    let scenario = &config.scenarios[s];
    let mut result = RunResult {
        integrator,
        chain,
        scenario: s,
        time_step: settings.time_step,
        substeps: settings.substeps,
        outcome: Outcome::Unstable,
        position_error: None,
        motion_ratio: None,
        max_length_error: None,
        failure: None,
    };
    match simulate(chain, scenario, settings, config) {
        Err(error) => result.failure = Some(error.to_string()),
        Ok(trajectory) => {
            let (reference, reference_motion) = reference;
            let early = (config.early_window / config.sample_interval)
                .round()
                .max(1.0) as usize;
            let mut sum = 0.0f64;
            let mut count = 0usize;
            for (a, b) in trajectory
                .samples
                .iter()
                .zip(&reference.samples)
                .take(early)
            {
                for (p, q) in a.iter().zip(b) {
                    sum += (*p - *q).length_squared() as f64;
                    count += 1;
                }
            }
            let error = (sum / count.max(1) as f64).sqrt() as f32 / TestChain::LENGTH;
            let motion = motion_from_rest(&trajectory, chain, scenario, config);
            // A floor of 2% of the length keeps the ratio meaningful for stiff hair whose
            // reference barely moves from the head-carried rest shape.
            let floor = 0.02 * TestChain::LENGTH;
            let ratio = (motion + floor) / (reference_motion + floor);
            result.position_error = Some(error);
            result.motion_ratio = Some(ratio);
            result.max_length_error = Some(trajectory.max_length_error);
            let (low, high) = config.motion_ratio_range;
            result.outcome = if ratio > config.blow_up_ratio {
                Outcome::Unstable
            } else if error <= config.error_tolerance && (low..=high).contains(&ratio) {
                Outcome::Stable
            } else {
                Outcome::DampedWrong
            };
        }
    }
    result
}

/// Checks that `step` [s] divides the sample interval.
fn check_divides(step: f32, config: &SweepConfig, what: &'static str) -> Result<(), DynamicsError> {
    let ratio = config.sample_interval / step;
    if step > 0.0 && (ratio - ratio.round()).abs() < 1e-3 {
        Ok(())
    } else {
        Err(DynamicsError::invalid(
            what,
            step,
            "a step > 0 s that divides the sample interval",
        ))
    }
}

/// Runs the sweep (in parallel over runs; the classes do not depend on the thread count), then
/// the substep study and the cost measurement (one thread, one integrator at a time).
pub fn run_sweep(config: &SweepConfig) -> Result<StabilityReport, DynamicsError> {
    for &step in &config.time_steps {
        check_divides(step, config, "sweep time step")?;
    }
    if !config.frame_substeps.is_empty() {
        check_divides(config.frame_step, config, "frame step")?;
        if config.frame_substeps.iter().any(|&n| n == 0 || n > 1 << 16) {
            return Err(DynamicsError::invalid(
                "frame substeps",
                format!("{:?}", config.frame_substeps),
                "counts in 1..=65536",
            ));
        }
    }
    // References, one per chain and scenario.
    let cases: Vec<(TestChain, usize)> = config
        .chains
        .iter()
        .flat_map(|&chain| (0..config.scenarios.len()).map(move |s| (chain, s)))
        .collect();
    let references: Vec<(Trajectory, f32)> = cases
        .par_iter()
        .map(|&(chain, s)| {
            let scenario = &config.scenarios[s];
            let trajectory = simulate(
                chain,
                scenario,
                reference_settings(chain, scenario, config),
                config,
            )?;
            let motion = motion_from_rest(&trajectory, chain, scenario, config);
            Ok((trajectory, motion))
        })
        .collect::<Result<_, DynamicsError>>()?;
    let mut jobs = Vec::new();
    let mut frame_jobs = Vec::new();
    for &integrator in &config.integrators {
        for (case, &(chain, s)) in cases.iter().enumerate() {
            for &time_step in &config.time_steps {
                jobs.push((integrator, case, chain, s, time_step, 1));
            }
            for &substeps in &config.frame_substeps {
                frame_jobs.push((integrator, case, chain, s, config.frame_step, substeps));
            }
        }
    }
    let run_jobs = |jobs: &[(IntegratorKind, usize, TestChain, usize, f32, u32)]| {
        jobs.par_iter()
            .map(|&(integrator, case, chain, s, time_step, substeps)| {
                let settings = SimulationSettings::new(integrator, time_step, substeps);
                classify(integrator, chain, s, settings, &references[case], config)
            })
            .collect::<Vec<RunResult>>()
    };
    let runs = run_jobs(&jobs);
    let frame_runs = run_jobs(&frame_jobs);
    let summaries: Vec<IntegratorSummary> = config
        .integrators
        .iter()
        .map(|&integrator| summarise(integrator, &runs, config))
        .collect();
    let widest_stable_region = summaries
        .iter()
        .max_by(|a, b| {
            a.stable.cmp(&b.stable).then(
                a.largest_all_stable_step
                    .unwrap_or(0.0)
                    .total_cmp(&b.largest_all_stable_step.unwrap_or(0.0)),
            )
        })
        .map(|s| s.integrator)
        .unwrap_or(IntegratorKind::PositionBased);
    let costs = if config.frame_substeps.is_empty() {
        Vec::new()
    } else {
        measure_costs(config)?
    };
    let mut frame_needs = Vec::new();
    for &integrator in &config.integrators {
        for &(chain, s) in &cases {
            let mine: Vec<&RunResult> = frame_runs
                .iter()
                .filter(|r| r.integrator == integrator && r.chain == chain && r.scenario == s)
                .collect();
            // The smallest count from which every larger count is stable too.
            let mut need: Option<&RunResult> = None;
            for run in mine.iter().rev() {
                if run.outcome != Outcome::Stable {
                    break;
                }
                need = Some(run);
            }
            let cost = need.and_then(|run| {
                costs
                    .iter()
                    .find(|c| c.integrator == integrator && c.substeps == run.substeps)
                    .map(|c| c.microseconds_per_node_second)
            });
            frame_needs.push(SubstepNeed {
                integrator,
                chain,
                scenario: s,
                substeps: need.map(|run| run.substeps),
                position_error: need.and_then(|run| run.position_error),
                microseconds_per_node_second: cost,
            });
        }
    }
    Ok(StabilityReport {
        config: config.clone(),
        runs,
        summaries,
        widest_stable_region,
        frame_runs,
        frame_needs,
        costs,
    })
}

/// Chains in the cost measurement.
const COST_CHAINS: usize = 256;

/// Measures every integrator's cost at every substep count of the study: 256 copies of the curly
/// test chain in a 3 rad/s head shake and a 3 m/s wind, 0.1 s of 60 Hz frames after a 0.05 s
/// warm-up, on one thread, the best of three runs (wall time, so a busy machine reads slower).
fn measure_costs(config: &SweepConfig) -> Result<Vec<StepCost>, DynamicsError> {
    let chain = TestChain::Curly;
    let single = chain.rest();
    let mut rest = SkeletonRest::default();
    for _ in 0..COST_CHAINS {
        rest.push_chain_from(&single, 0)?;
    }
    let scenario = Scenario {
        label: String::new(),
        stiffness_per_mass: None,
        wind_speed: 3.0,
        shake_speed: 3.0,
    };
    let environment = scenario.environment();
    let model = DynamicsModel::new(rest, scenario.params(&chain.style()))?;
    let nodes = model.node_count();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|_| DynamicsError::invalid("thread pool", 1, "a pool of one thread"))?;
    let frames = (0.1 / config.frame_step).round().max(1.0) as usize;
    let warm_up = (0.05 / config.frame_step).round().max(1.0) as usize;
    let mut costs = Vec::new();
    for &integrator in &config.integrators {
        for &substeps in &config.frame_substeps {
            let settings = SimulationSettings::new(integrator, config.frame_step, substeps);
            let mut simulation = Simulation::new(model.clone(), settings)?;
            let seconds = pool.install(|| -> Result<f64, DynamicsError> {
                let mut best = f64::INFINITY;
                for _ in 0..3 {
                    let mut state = simulation.rest_state(&environment, 0.0);
                    simulation.run(&mut state, &environment, warm_up)?;
                    let started = std::time::Instant::now();
                    simulation.run(&mut state, &environment, frames)?;
                    best = best.min(started.elapsed().as_secs_f64());
                }
                Ok(best)
            });
            // An integrator that fails in this mild scene has no cost to report.
            let Ok(seconds) = seconds else { continue };
            let node_substeps = (nodes * frames * substeps as usize) as f64;
            let per_node_substep = seconds / node_substeps;
            let substeps_per_second = substeps as f64 / config.frame_step as f64;
            costs.push(StepCost {
                integrator,
                substeps,
                nanoseconds_per_node_substep: (per_node_substep * 1e9) as f32,
                microseconds_per_node_second: (per_node_substep * substeps_per_second * 1e6) as f32,
            });
        }
    }
    Ok(costs)
}

fn summarise(
    integrator: IntegratorKind,
    runs: &[RunResult],
    config: &SweepConfig,
) -> IntegratorSummary {
    let mine: Vec<&RunResult> = runs.iter().filter(|r| r.integrator == integrator).collect();
    let count = |outcome| mine.iter().filter(|r| r.outcome == outcome).count();
    let largest = |accept: &dyn Fn(Outcome) -> bool| {
        config
            .time_steps
            .iter()
            .copied()
            .filter(|&step| {
                mine.iter()
                    .filter(|r| r.time_step == step)
                    .all(|r| accept(r.outcome))
            })
            .fold(None, |best: Option<f32>, step| {
                Some(best.map_or(step, |b| b.max(step)))
            })
    };
    IntegratorSummary {
        integrator,
        stable: count(Outcome::Stable),
        damped_wrong: count(Outcome::DampedWrong),
        unstable: count(Outcome::Unstable),
        largest_all_stable_step: largest(&|o| o == Outcome::Stable),
        largest_never_unstable_step: largest(&|o| o != Outcome::Unstable),
    }
}
