//! `hairlod stability`: the stability map of the three skeleton integrators over time step,
//! stiffness, wind and head shake, printed as a table and optionally written as JSON and drawn as
//! one heat map per integrator.

use std::path::{Path, PathBuf};

use crate::charts::{recompress_png, register_chart_font};
use anyhow::{Context, Result};
use clap::Args;
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
    println!(
        "({} runs in {:.1} s)",
        report.runs.len(),
        started.elapsed().as_secs_f32()
    );
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&report)?;
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.chart {
        draw_chart(&report, path)?;
        println!("wrote {}", path.display());
    }
    Ok(())
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
        .with_context(|| format!("writing {}", path.display()))?;
    drop(root);
    recompress_png(path)
}
