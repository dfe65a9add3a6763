//! `hairlod stability`: the stability map of the skeleton integrators over time step, stiffness,
//! wind and head shake, and the substeps each needs at 60 Hz frames with what they cost; printed
//! as tables and optionally written as JSON, drawn as one heat map per integrator and as error
//! against cost per simulated second for every scenario.

use std::path::{Path, PathBuf};

use crate::charts::{register_chart_font, write_atomically, write_png_through};
use anyhow::{Context, Result};
use clap::Args;
use hairlod::core::dynamics::IntegratorKind;
use hairlod::core::dynamics::SimulationSettings;
use hairlod::core::dynamics::stability::{Outcome, StabilityReport, SweepConfig, run_sweep};
use plotters::prelude::*;

/// Arguments of `hairlod stability`.
#[derive(Debug, Args)]
pub struct StabilityArgs {
    /// Write every run (class, position error, motion ratio, failure message) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Draw one heat map per integrator (rows: chain × scenario, columns: time step) into FILE.png.
    #[arg(long, value_name = "FILE.png")]
    pub chart: Option<PathBuf>,
    /// Draw the substep study (error against cost per simulated second, one panel per chain and
    /// scenario, one line per integrator) into FILE.png.
    #[arg(long, value_name = "FILE.png")]
    pub cost_chart: Option<PathBuf>,
    /// Simulated time per run [s].
    #[arg(long, default_value_t = 3.0)]
    pub duration: f32,
}

/// Runs `hairlod stability`.
pub fn run(args: &StabilityArgs) -> Result<()> {
    if !(args.duration.is_finite() && args.duration >= 0.6) {
        anyhow::bail!("--duration must be at least 0.6 s (got {})", args.duration);
    }
    let config = SweepConfig {
        duration: args.duration,
        ..SweepConfig::default()
    };
    let started = std::time::Instant::now();
    let report = run_sweep(&config).context("the stability sweep failed")?;
    print_table(&report);
    print_substep_table(&report);
    println!(
        "({} runs in {:.1} s)",
        report.runs.len(),
        started.elapsed().as_secs_f32()
    );
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&report)?;
        write_atomically(path, text.as_bytes())?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.chart {
        write_png_through(path, |scratch| draw_chart(&report, scratch))?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.cost_chart {
        write_png_through(path, |scratch| draw_cost_chart(&report, scratch))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The substep study: per chain and scenario, the substeps each integrator needs at 60 Hz frames
/// to be stable (within the error tolerance, motion ratio in range) and what that costs.
fn print_substep_table(report: &StabilityReport) {
    let config = &report.config;
    if report.frame_needs.is_empty() {
        return;
    }
    println!(
        "\nsubsteps needed at {:.0} Hz frames to be stable (tried {:?}), early error, and cost \
         [µs of one core per node per simulated second]:",
        1.0 / config.frame_step,
        config.frame_substeps
    );
    let header: String = report
        .summaries
        .iter()
        .map(|s| format!("{:>28}", s.integrator.name()))
        .collect();
    println!("{:26}{header}", "");
    for &chain in &config.chains {
        for (s, scenario) in config.scenarios.iter().enumerate() {
            let cells: String = report
                .summaries
                .iter()
                .map(|summary| {
                    let cell = match report.frame_need(summary.integrator, chain, s) {
                        Some(need) => match (
                            need.substeps,
                            need.position_error,
                            need.microseconds_per_node_second,
                        ) {
                            (Some(n), Some(e), Some(c)) => {
                                format!("{n} ({:.1}%, {c:.1} µs)", 100.0 * e)
                            }
                            (Some(n), Some(e), None) => format!("{n} ({:.1}%, ?)", 100.0 * e),
                            _ => "none".to_string(),
                        },
                        None => "?".to_string(),
                    };
                    format!("{cell:>28}")
                })
                .collect();
            println!("{:>9} {:16}{cells}", chain.name(), scenario.label);
        }
    }
    println!("\ncost per node-substep [ns, one core]:");
    for summary in &report.summaries {
        let costs: String = report
            .costs
            .iter()
            .filter(|c| c.integrator == summary.integrator)
            .map(|c| format!("  ×{}: {:.1}", c.substeps, c.nanoseconds_per_node_substep))
            .collect();
        println!("{:>20}{costs}", summary.integrator.name());
    }
    print_recommended(report);
}

/// The recommended settings of each integrator at 60 Hz (XPBD's adaptive substeps included):
/// how many of the chains and scenarios they hold, and the substeps they took.
fn print_recommended(report: &StabilityReport) {
    if report.recommended_runs.is_empty() {
        return;
    }
    println!(
        "
the recommended settings at 60 Hz (SimulationSettings::recommended):"
    );
    for summary in &report.summaries {
        let integrator = summary.integrator;
        let settings = SimulationSettings::recommended(integrator);
        let runs: Vec<_> = report
            .recommended_runs
            .iter()
            .filter(|r| r.integrator == integrator)
            .collect();
        let stable = runs.iter().filter(|r| r.outcome == Outcome::Stable).count();
        let unstable = runs
            .iter()
            .filter(|r| r.outcome == Outcome::Unstable)
            .count();
        let worst = runs
            .iter()
            .filter_map(|r| r.position_error)
            .fold(0.0f32, f32::max);
        let substeps = runs
            .iter()
            .filter_map(|r| r.mean_substeps)
            .fold(None, |most: Option<f32>, n| {
                Some(most.map_or(n, |m| m.max(n)))
            });
        let count = settings.substeps_label();
        println!(
            "{:>20} {count:>16}: stable in {stable} of {}, unstable in {unstable}; largest early \
             error {:.1}%; substeps per frame, the largest run's mean: {}",
            integrator.name(),
            runs.len(),
            100.0 * worst,
            substeps.map_or("?".to_string(), |n| format!("{n:.1}"))
        );
    }
}

/// One letter per class: `.` stable, `d` damped-wrong, `X` unstable.
fn symbol(outcome: Outcome) -> char {
    match outcome {
        Outcome::Stable => '.',
        Outcome::DampedWrong => 'd',
        Outcome::Unstable => 'X',
    }
}

fn step_label(step: f32) -> String {
    format!("1/{:.0}", 1.0 / step)
}

fn print_table(report: &StabilityReport) {
    let config = &report.config;
    println!(
        "classes: . stable (early error <= {:.0}% of the length, motion ratio within {:.2}..{:.2}), \
         d damped-wrong, X unstable (error, or motion ratio > {:.1})",
        100.0 * config.error_tolerance,
        config.motion_ratio_range.0,
        config.motion_ratio_range.1,
        config.blow_up_ratio
    );
    let header: String = config
        .time_steps
        .iter()
        .map(|&s| format!("{:>7}", step_label(s)))
        .collect();
    for summary in &report.summaries {
        println!(
            "\n{}  (stable {}, damped-wrong {}, unstable {})",
            summary.integrator, summary.stable, summary.damped_wrong, summary.unstable
        );
        println!("{:26}{header}", "");
        for &chain in &config.chains {
            for (s, scenario) in config.scenarios.iter().enumerate() {
                let cells: String = (0..config.time_steps.len())
                    .map(|k| {
                        report
                            .run(summary.integrator, chain, s, k)
                            .map_or("      ?".to_string(), |run| {
                                format!("{:>7}", symbol(run.outcome))
                            })
                    })
                    .collect();
                println!("{:>9} {:16}{cells}", chain.name(), scenario.label);
            }
        }
    }
    println!("\nwidest stable region: {}", report.widest_stable_region);
}

fn outcome_colour(outcome: Outcome) -> RGBColor {
    match outcome {
        Outcome::Stable => RGBColor(76, 175, 80),
        Outcome::DampedWrong => RGBColor(255, 179, 0),
        Outcome::Unstable => RGBColor(229, 57, 53),
    }
}

/// One heat map per integrator, side by side.
fn draw_chart(report: &StabilityReport, path: &Path) -> Result<()> {
    register_chart_font()?;
    let config = &report.config;
    let rows: Vec<(usize, String)> = config
        .chains
        .iter()
        .flat_map(|chain| {
            config
                .scenarios
                .iter()
                .enumerate()
                .map(move |(s, scenario)| (s, format!("{} {}", chain.name(), scenario.label)))
        })
        .collect();
    let columns = config.time_steps.len();
    let (label_width, cell_width, cell_height, top, bottom) = (190i32, 52i32, 22i32, 70i32, 60i32);
    let panel_width = label_width + cell_width * columns as i32 + 20;
    let width = panel_width * report.summaries.len() as i32;
    let height = top + cell_height * rows.len() as i32 + bottom;
    let root = BitMapBackend::new(path, (width as u32, height as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let title = ("sans-serif", 18).into_font();
    let small = ("sans-serif", 12).into_font();
    let tiny = ("sans-serif", 10).into_font();
    for (p, summary) in report.summaries.iter().enumerate() {
        let x0 = p as i32 * panel_width;
        root.draw(&Text::new(
            format!(
                "{}: {} stable, {} damped-wrong, {} unstable",
                summary.integrator, summary.stable, summary.damped_wrong, summary.unstable
            ),
            (x0 + 10, 10),
            title.clone(),
        ))?;
        for (k, &step) in config.time_steps.iter().enumerate() {
            root.draw(&Text::new(
                step_label(step),
                (x0 + label_width + k as i32 * cell_width + 8, top - 20),
                small.clone(),
            ))?;
        }
        for (r, (scenario, label)) in rows.iter().enumerate() {
            let y = top + r as i32 * cell_height;
            root.draw(&Text::new(label.clone(), (x0 + 8, y + 5), small.clone()))?;
            let chain = config.chains[r / config.scenarios.len()];
            for k in 0..columns {
                let x = x0 + label_width + k as i32 * cell_width;
                let Some(run) = report.run(summary.integrator, chain, *scenario, k) else {
                    continue;
                };
                root.draw(&Rectangle::new(
                    [(x, y), (x + cell_width - 2, y + cell_height - 2)],
                    outcome_colour(run.outcome).filled(),
                ))?;
                let text = match run.position_error {
                    Some(error) if run.outcome != Outcome::Unstable => {
                        format!("{:.0}%", 100.0 * error)
                    }
                    _ => "X".to_string(),
                };
                root.draw(&Text::new(text, (x + 6, y + 6), tiny.clone()))?;
            }
        }
    }
    let legend_y = top + cell_height * rows.len() as i32 + 15;
    for (i, (outcome, text)) in [
        (Outcome::Stable, "stable"),
        (Outcome::DampedWrong, "damped-wrong"),
        (Outcome::Unstable, "unstable"),
    ]
    .into_iter()
    .enumerate()
    {
        let x = 10 + i as i32 * 160;
        root.draw(&Rectangle::new(
            [(x, legend_y), (x + 16, legend_y + 16)],
            outcome_colour(outcome).filled(),
        ))?;
        root.draw(&Text::new(text, (x + 22, legend_y + 2), small.clone()))?;
    }
    root.draw(&Text::new(
        format!(
            "cells: early position error vs. the converged reference (% of chain length); columns: time step [s], one substep; widest stable region: {}",
            report.widest_stable_region
        ),
        (500, legend_y + 2),
        small,
    ))?;
    root.present()
        .with_context(|| format!("drawing {}", path.display()))?;
    Ok(())
}

fn integrator_colour(integrator: IntegratorKind) -> RGBColor {
    match integrator {
        IntegratorKind::SemiImplicitEuler => RGBColor(30, 136, 229),
        IntegratorKind::PositionBased => RGBColor(255, 143, 0),
        IntegratorKind::LinearImplicit => RGBColor(142, 36, 170),
        IntegratorKind::Xpbd => RGBColor(46, 125, 50),
    }
}

/// Error against cost per simulated second (drawn into the PNG file `path`): one panel per chain and scenario, one line per
/// integrator through its substep counts (runs that failed are left out), log-log, with the error
/// tolerance as a dashed line.
fn draw_cost_chart(report: &StabilityReport, path: &Path) -> Result<()> {
    register_chart_font()?;
    let config = &report.config;
    let cases: Vec<_> = config
        .chains
        .iter()
        .flat_map(|&chain| (0..config.scenarios.len()).map(move |s| (chain, s)))
        .collect();
    let columns = 5usize;
    let rows = cases.len().div_ceil(columns).max(1);
    let (panel_width, panel_height, header) = (360u32, 280u32, 60u32);
    let root = BitMapBackend::new(
        path,
        (
            panel_width * columns as u32,
            header + panel_height * rows as u32,
        ),
    )
    .into_drawing_area();
    root.fill(&WHITE)?;
    let cost = |integrator: IntegratorKind, substeps: u32| {
        report
            .costs
            .iter()
            .find(|c| c.integrator == integrator && c.substeps == substeps)
            .map(|c| c.microseconds_per_node_second as f64)
    };
    let points = |chain, s| {
        report
            .frame_runs
            .iter()
            .filter(move |r| r.chain == chain && r.scenario == s)
            .filter_map(move |r| {
                let error = r.position_error? as f64;
                Some((
                    r.integrator,
                    r.substeps,
                    cost(r.integrator, r.substeps)?,
                    error.max(1e-4),
                ))
            })
    };
    let all: Vec<(f64, f64)> = cases
        .iter()
        .flat_map(|&(chain, s)| points(chain, s).map(|(_, _, c, e)| (c, e)))
        .collect();
    if all.is_empty() {
        anyhow::bail!("the substep study has no finished run with a measured cost to draw");
    }
    let (mut low, mut high) = (f64::INFINITY, 0.0f64);
    let (mut bottom, mut top) = (f64::INFINITY, 0.0f64);
    for &(c, e) in &all {
        low = low.min(c);
        high = high.max(c);
        bottom = bottom.min(e);
        top = top.max(e);
    }
    let (low, high) = (low / 1.5, high * 1.5);
    let (bottom, top) = (bottom / 1.5, top.max(config.error_tolerance as f64) * 1.5);
    root.draw(&Text::new(
        format!(
            "early position error (fraction of the chain length) against cost [µs of one core per node per simulated second], {:.0} Hz frames, substeps {:?}",
            1.0 / config.frame_step,
            config.frame_substeps
        ),
        (10, 8),
        ("sans-serif", 16).into_font(),
    ))?;
    for (i, integrator) in report.summaries.iter().map(|s| s.integrator).enumerate() {
        let x = 10 + 200 * i as i32;
        root.draw(&Rectangle::new(
            [(x, 34), (x + 24, 38)],
            integrator_colour(integrator).filled(),
        ))?;
        root.draw(&Text::new(
            integrator.name(),
            (x + 30, 28),
            ("sans-serif", 13).into_font(),
        ))?;
    }
    let body = root.margin(header, 0, 0, 0);
    let panels = body.split_evenly((rows, columns));
    for (&(chain, s), area) in cases.iter().zip(panels.iter()) {
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!("{} {}", chain.name(), config.scenarios[s].label),
                ("sans-serif", 13),
            )
            .margin(8)
            .x_label_area_size(28)
            .y_label_area_size(44)
            .build_cartesian_2d((low..high).log_scale(), (bottom..top).log_scale())
            .map_err(|e| anyhow::anyhow!("drawing the cost chart: {e}"))?;
        chart
            .configure_mesh()
            .x_labels(4)
            .y_labels(4)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 10))
            .draw()
            .map_err(|e| anyhow::anyhow!("drawing the cost chart: {e}"))?;
        let tolerance = config.error_tolerance as f64;
        chart
            .draw_series(DashedLineSeries::new(
                [(low, tolerance), (high, tolerance)],
                4,
                4,
                BLACK.stroke_width(1),
            ))
            .map_err(|e| anyhow::anyhow!("drawing the cost chart: {e}"))?;
        for integrator in report.summaries.iter().map(|s| s.integrator) {
            // Joined in the order of the substep counts (a cost need not grow with them: a
            // Newton solver iterates more at long substeps).
            let mut line: Vec<(u32, f64, f64)> = points(chain, s)
                .filter(|p| p.0 == integrator)
                .map(|(_, n, c, e)| (n, c, e))
                .collect();
            line.sort_by_key(|p| p.0);
            let line: Vec<(f64, f64)> = line.into_iter().map(|(_, c, e)| (c, e)).collect();
            let colour = integrator_colour(integrator);
            chart
                .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))
                .map_err(|e| anyhow::anyhow!("drawing the cost chart: {e}"))?;
            chart
                .draw_series(line.into_iter().map(|p| Circle::new(p, 3, colour.filled())))
                .map_err(|e| anyhow::anyhow!("drawing the cost chart: {e}"))?;
        }
    }
    root.present()
        .with_context(|| format!("drawing {}", path.display()))?;
    Ok(())
}
