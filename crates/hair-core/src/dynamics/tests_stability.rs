//! Tests of the stability sweep's 60 Hz substep study on the scenarios that need the most.

use crate::dynamics::IntegratorKind;
use crate::dynamics::stability::{SweepConfig, TestChain, run_sweep};

/// The default sweep reduced to the strong-wind and fast-shake scenarios, the frame study only.
fn strong_scenarios(integrators: Vec<IntegratorKind>, substeps: Vec<u32>) -> SweepConfig {
    let full = SweepConfig::default();
    SweepConfig {
        integrators,
        time_steps: Vec::new(),
        scenarios: full
            .scenarios
            .iter()
            .filter(|s| s.wind_speed >= 10.0 || s.shake_speed >= 10.0)
            .cloned()
            .collect(),
        frame_substeps: substeps,
        ..full
    }
}

#[test]
#[ignore = "diagnostic: prints the frame study's errors on the strong scenarios"]
fn print_strong_scenarios() {
    let config = strong_scenarios(
        vec![IntegratorKind::Xpbd, IntegratorKind::LinearImplicit],
        vec![4, 8, 16, 32, 64],
    );
    let report = run_sweep(&config).unwrap();
    for run in &report.frame_runs {
        println!(
            "{:>16} {:>8} {:>16} ×{:<3} {:>12} e {:.3} ρ {:.2}",
            run.integrator.name(),
            run.chain.name(),
            config.scenarios[run.scenario].label,
            run.substeps,
            run.outcome.name(),
            run.position_error.unwrap_or(f32::NAN),
            run.motion_ratio.unwrap_or(f32::NAN),
        );
    }
    let _ = TestChain::ALL;
}
