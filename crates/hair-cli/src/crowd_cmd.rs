//! Crowd scenes (scene files with `[[character]]` tables) in `hairlod render` and `hairlod
//! bench`: every character simulated, collided and drawn in one frame, levels chosen across the
//! crowd. The bench runs LODs, all-strands, all-clusters and all-patches in the paper's table
//! layout, interleaved frame by frame, then the frame budget (greedy and tolerance controller,
//! side by side) at a tenth of the all-strands cost, with SSIM and luma error of every mode
//! against the all-strands frames.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use hairlod::benchmark::{SimulationCosts, paper_modes};
use hairlod::core::lod::{BudgetMethod, BudgetReport, BudgetSettings};
use hairlod::crowd::{Crowd, CrowdModel, CrowdRenderer, run_crowd};
use hairlod::metrics::{luma, luma_difference, ssim};
use hairlod::pipeline::{Checkpoint, DrawStyle, LodMode, PipelineSettings};
use hairlod::render::RendererOptions;
use hairlod::run::{FrameLoop, ModeRun, RunOptions, View};
use hairlod::shot::Shot;
use serde::Serialize;

use crate::frame_writer::FrameWriter;
use crate::report::{print_table, progress_bar, write_json};

/// Builds the crowd, saying how big it is.
fn build(shot: &Shot) -> Result<CrowdModel> {
    let started = Instant::now();
    let model = CrowdModel::build(shot).context("could not build the crowd's grooms")?;
    let sections: usize = model
        .members
        .iter()
        .map(|m| m.scene.groom.section_count())
        .sum();
    eprintln!(
        "crowd: {} characters, {sections} sections, {} strands (built in {:.1} s)",
        model.members.len(),
        model.strand_count(),
        started.elapsed().as_secs_f64()
    );
    Ok(model)
}

/// Where a crowd render's frames come from and where its state goes: the frames to draw, the
/// checkpoint they resume from and the folder the state at their end is written to.
pub struct CrowdFrames {
    /// The frames to draw, within the shot.
    pub frames: std::ops::Range<usize>,
    /// The checkpoint the frames resume from (its frame is where they start).
    pub resume: Option<Checkpoint>,
    /// Write the state at the end of the frames to DIR/checkpoint_<frame>.json.
    pub checkpoint: Option<PathBuf>,
}

/// `hairlod render` on a crowd scene: `frames` of the shot (from the start or from a
/// checkpoint), in each view asked for, to `out` (one folder per view when there are several),
/// with a contact sheet and JSON report when asked, and the state at the end as a checkpoint
/// when asked.
pub fn render(
    shot: &Shot,
    out: &Path,
    json: Option<PathBuf>,
    options: &RendererOptions,
    style: DrawStyle,
    frames: CrowdFrames,
) -> Result<()> {
    anyhow::ensure!(
        !(shot.outputs.hair || shot.outputs.usd),
        "crowd scenes write images only: leave out --hair / --usd (output.hair, output.usd)"
    );
    let model = build(shot)?;
    let views = View::of_outputs(&shot.outputs);
    let mut writer = FrameWriter::new(
        out,
        &views,
        frames.frames.clone(),
        shot.frames,
        shot.outputs.contact_sheet,
    )?;
    let mut renderer = CrowdRenderer::new(options, &model)?;
    renderer.set_style(style);
    eprintln!("adapter: {}", renderer.renderer().adapter_report());
    let bar = progress_bar(frames.frames.len(), shot.settings.lod.column_name());
    let CrowdFrames {
        frames,
        resume,
        checkpoint,
    } = frames;
    let run = RunOptions {
        frames: frames.clone(),
        resume,
        ..RunOptions::whole(shot, shot.settings)
    };
    let result = run_crowd(&model, run, Some((&mut renderer, &views)), |frame| {
        writer.write(frame.report.frame, frame.images)?;
        let [p, c, s] = frame.report.sections_at;
        bar.set_message(format!("{s} strand groups, {c} clusters, {p} patches"));
        bar.inc(1);
        Ok(())
    })
    .context("the crowd run stopped")?;
    bar.finish();
    writer.finish()?;
    if let Some(dir) = &checkpoint {
        let path = dir.join(format!("checkpoint_{:05}.json", frames.end));
        result.pipeline.checkpoint()?.write(&path)?;
        eprintln!(
            "wrote {} (resume with --resume {} --frames {}..)",
            path.display(),
            path.display(),
            frames.end
        );
    }
    if let Some(path) = json {
        write_json(&path, &serde_json::to_value(&result.run)?)?;
    }
    let mean = &result.run.mean;
    eprintln!(
        "wrote {} frame(s) to {}; per frame: lod {:.1} ms, dynamics {:.1} ms, collision {:.1} \
         ms, render {:.1} ms",
        result.run.frames.len(),
        out.display(),
        1e3 * mean.lod,
        1e3 * mean.dynamics,
        1e3 * mean.collision,
        1e3 * mean.rendering
    );
    Ok(())
}

/// One mode's frames against the all-strands frames.
#[derive(Debug, Clone, Serialize)]
struct AgainstStrands {
    mode: String,
    /// Mean cost per frame [s] (level selection, dynamics, collision, rendering).
    mean_cost: f64,
    /// Median cost per frame [s].
    median_cost: f64,
    /// Mean SSIM of the luma against the all-strands frame.
    mean_ssim: f64,
    /// Mean absolute luma difference from the all-strands frame, in [0, 1].
    mean_luma_error: f64,
}

#[derive(Serialize)]
struct CrowdReport<'a> {
    shot: &'a Shot,
    adapter: String,
    characters: Vec<String>,
    strands: usize,
    modes: &'a [ModeRun],
    against_strands: &'a [AgainstStrands],
    budgets: Vec<(BudgetReport, AgainstStrands)>,
    /// Per mode, the simulation's cost per level (nodes, dynamics, collision, ns per node).
    simulation_costs: Vec<SimulationCosts>,
}

/// Mean cost per frame [s] of a run, all stages.
fn mean_cost(run: &ModeRun) -> f64 {
    run.frames.iter().map(|f| f.times.total()).sum::<f64>() / run.frames.len().max(1) as f64
}

/// `hairlod bench` on a crowd scene.
pub fn bench(shot: &Shot, budget_ms: Option<f64>, json: Option<&Path>) -> Result<()> {
    let model = build(shot)?;
    let options = RendererOptions::from_env()?;
    let mut renderer = CrowdRenderer::new(&options, &model)?;
    renderer.set_style(shot.outputs.style());
    let adapter = renderer.renderer().adapter_report().to_string();
    println!("rendering on {adapter}");
    let views = [View::Shaded];
    let lod = shot.lod_settings();
    let [lods, strands, clusters, patches] = paper_modes(lod);
    let mut strand_frames: Vec<image::GrayImage> = Vec::new();
    // The all-strands run first in each frame: every other mode is measured against its frame.
    let runs = [strands, lods, clusters, patches]
        .into_iter()
        .map(|mode| CrowdRun {
            label: mode.column_name().to_string(),
            settings: PipelineSettings {
                lod: mode,
                ..shot.settings
            },
            budget: None,
        })
        .collect();
    let mut runs: Vec<(ModeRun, AgainstStrands)> =
        run_interleaved(&model, &mut renderer, &views, runs, &mut strand_frames)?
            .into_iter()
            .map(|(result, against)| (result.run, against))
            .collect();
    // Back to the paper's column order: LODs, Strands, Clusters, Patches.
    runs.swap(0, 1);
    let (modes, against): (Vec<ModeRun>, Vec<AgainstStrands>) = runs.into_iter().unzip();
    print_table("The crowd in each mode", &modes, None, shot);
    let simulation_costs: Vec<SimulationCosts> = modes.iter().map(SimulationCosts::of).collect();
    crate::report::print_simulation_costs(&simulation_costs);
    println!();
    println!(
        "{:<28}{:>12}{:>12}{:>12}{:>14}",
        "mode", "mean [ms]", "median [ms]", "SSIM", "luma error"
    );
    for a in &against {
        println!(
            "{:<28}{:>12.1}{:>12.1}{:>12.4}{:>14.5}",
            a.mode,
            1e3 * a.mean_cost,
            1e3 * a.median_cost,
            a.mean_ssim,
            a.mean_luma_error
        );
    }
    let strands_cost = against[1].mean_cost;
    println!(
        "LODs: {:.1}× cheaper than all-strands at mean SSIM {:.4}; against all-clusters: cost \
         {:.2}×, SSIM {:.4} vs {:.4}",
        strands_cost / against[0].mean_cost.max(1e-12),
        against[0].mean_ssim,
        against[0].mean_cost / against[2].mean_cost.max(1e-12),
        against[0].mean_ssim,
        against[2].mean_ssim
    );
    let budget = budget_ms.map_or(strands_cost / 10.0, |ms| ms / 1e3);
    let mut budgets = Vec::new();
    if let LodMode::Auto(lod) = lods {
        // Both methods side by side, frame by frame, so their costs are measured under the same
        // load (they are compared at the same cost).
        let mut runs = Vec::new();
        for method in [BudgetMethod::Greedy, BudgetMethod::Tolerance] {
            let frame_time = shot.settings.dynamics.time_step;
            let settings = BudgetSettings {
                hold_frames: (lod.blend_time / frame_time).round() as usize,
                method,
                ..BudgetSettings::new(budget)
            };
            settings.validate()?;
            runs.push(CrowdRun {
                label: format!("LODs, budget ({method})"),
                settings: PipelineSettings {
                    lod: lods,
                    ..shot.settings
                },
                budget: Some(settings),
            });
        }
        for ((result, against), method) in
            run_interleaved(&model, &mut renderer, &views, runs, &mut strand_frames)?
                .into_iter()
                .zip([BudgetMethod::Greedy, BudgetMethod::Tolerance])
        {
            let report = result.budget.context("a budgeted run keeps its tally")?;
            println!(
                "frame budget {:.1} ms ({method}): met in {} of {} frames, mean cost {:.1} ms, \
                 mean SSIM {:.4}, mean luma error {:.5}",
                1e3 * budget,
                report.met,
                report.frames,
                1e3 * against.mean_cost,
                against.mean_ssim,
                against.mean_luma_error
            );
            budgets.push((report, against));
        }
    }
    if let Some(path) = json {
        let report = CrowdReport {
            shot,
            adapter,
            characters: model
                .members
                .iter()
                .map(|m| m.character.name.clone())
                .collect(),
            strands: model.strand_count(),
            modes: &modes,
            against_strands: &against,
            budgets,
            simulation_costs,
        };
        write_json(path, &serde_json::to_value(&report)?)?;
    }
    Ok(())
}

/// One run of the crowd: its label, settings and frame budget.
struct CrowdRun {
    label: String,
    settings: PipelineSettings,
    budget: Option<BudgetSettings>,
}

/// Runs `runs` of the crowd interleaved frame by frame (each makes frame k before any makes
/// k + 1, in the order given, on one renderer), so that every run sees the same machine load,
/// and measures each frame against `strand_frames`, which the first run fills when it is empty
/// (an all-strands run). Returns each run's result and its frames against the all-strands ones.
fn run_interleaved(
    model: &CrowdModel,
    renderer: &mut CrowdRenderer,
    views: &[View],
    runs: Vec<CrowdRun>,
    strand_frames: &mut Vec<image::GrayImage>,
) -> Result<Vec<(hairlod::run::RunResult<Crowd>, AgainstStrands)>> {
    let shot = &model.shot;
    let fills_reference = strand_frames.is_empty();
    let mut loops = Vec::with_capacity(runs.len());
    for run in &runs {
        let crowd = Crowd::new(model, run.settings)
            .with_context(|| format!("the crowd's {} run failed to start", run.label))?;
        loops.push(FrameLoop::new(shot, crowd, 0..shot.frames, run.budget)?);
    }
    let names: Vec<&str> = runs.iter().map(|r| r.label.as_str()).collect();
    let bar = progress_bar(shot.frames * runs.len(), &names.join(", "));
    let mut sums = vec![(0.0, 0.0); runs.len()];
    for frame in 0..shot.frames {
        for (index, (frame_loop, run)) in loops.iter_mut().zip(&runs).enumerate() {
            let label = &run.label;
            let output = frame_loop
                .step(Some((&mut *renderer, views)))
                .with_context(|| format!("the crowd's {label} run failed at frame {frame}"))?
                .with_context(|| format!("the crowd's {label} run ended before frame {frame}"))?;
            let gray = luma(&output.images[0]);
            let (ssim_sum, luma_sum) = &mut sums[index];
            if fills_reference && index == 0 {
                strand_frames.push(gray);
                *ssim_sum += 1.0;
            } else if let Some(strands) = strand_frames.get(frame) {
                *ssim_sum += ssim(strands, &gray);
                *luma_sum += luma_difference(strands, &gray);
            }
            bar.inc(1);
        }
    }
    bar.finish();
    let frames = shot.frames.max(1) as f64;
    Ok(loops
        .into_iter()
        .zip(runs)
        .zip(sums)
        .map(|((frame_loop, run), (ssim_sum, luma_sum))| {
            let result = frame_loop.finish();
            let against = AgainstStrands {
                mode: run.label,
                mean_cost: mean_cost(&result.run),
                median_cost: result.run.median_total,
                mean_ssim: ssim_sum / frames,
                mean_luma_error: luma_sum / frames,
            };
            (result, against)
        })
        .collect())
}

/// `hairlod accuracy --crowd SCENE`: the crowd's speed against accuracy. The all-strands run is
/// the reference; every fixed level and the LODs at each of `tolerances` [pixels] are measured
/// against it frame by frame (mean SSIM loss and luma error), with their median cost per frame.
pub fn accuracy(
    shot: &Shot,
    tolerances: &[f32],
    strands_per_pixel: &[f32],
    json: Option<&Path>,
) -> Result<()> {
    let model = build(shot)?;
    let options = RendererOptions::from_env()?;
    let mut renderer = CrowdRenderer::new(&options, &model)?;
    renderer.set_style(shot.outputs.style());
    println!("rendering on {}", renderer.renderer().adapter_report());
    let views = [View::Shaded];
    let lod = shot.lod_settings();
    let [_, strands, clusters, patches] = paper_modes(lod);
    let mut modes: Vec<(String, LodMode)> = vec![
        ("Strands (reference)".into(), strands),
        ("Clusters".into(), clusters),
        ("Patches".into(), patches),
    ];
    for &tolerance in tolerances {
        for &thinning in strands_per_pixel {
            let lod = hairlod::core::lod::LodSettings {
                pixel_tolerance: tolerance,
                strands_per_pixel: thinning,
                ..lod
            };
            lod.validate()?;
            let thinned = crate::report::thinning_label(&lod);
            modes.push((format!("LODs {tolerance} px{thinned}"), LodMode::Auto(lod)));
        }
    }
    let runs = modes
        .into_iter()
        .map(|(label, mode)| CrowdRun {
            label,
            settings: PipelineSettings {
                lod: mode,
                ..shot.settings
            },
            budget: None,
        })
        .collect();
    let mut strand_frames = Vec::new();
    let points: Vec<AgainstStrands> =
        run_interleaved(&model, &mut renderer, &views, runs, &mut strand_frames)?
            .into_iter()
            .map(|(_, against)| against)
            .collect();
    println!();
    println!(
        "{:<24}{:>14}{:>14}{:>12}{:>14}",
        "configuration", "median [ms]", "cost ratio", "SSIM loss", "luma error"
    );
    let reference_cost = points[0].median_cost;
    for point in &points {
        println!(
            "{:<24}{:>14.1}{:>13.3}×{:>12.4}{:>14.5}",
            point.mode,
            1e3 * point.median_cost,
            point.median_cost / reference_cost.max(1e-12),
            1.0 - point.mean_ssim,
            point.mean_luma_error
        );
    }
    if let Some(path) = json {
        write_json(path, &serde_json::to_value(&points)?)?;
    }
    Ok(())
}
