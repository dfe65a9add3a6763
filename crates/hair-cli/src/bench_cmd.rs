//! `hairlod bench SCENE`: any scene run in LODs and in each fixed level over the same frames, in
//! the layout of the paper's Tables 1 and 2 (§8.2), with the speedup of LODs over Strands, the
//! popping measure and the SSIM of each mode against Strands. `hairlod bench paper [--wind]` is
//! the shorthand for `scenes/paper-table1.toml` (`-2`), printed next to the paper's own figures.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use hairlod::Scene;
use hairlod::benchmark::{
    AgainstStrands, BudgetedAgainstStrands, PaperOptions, PaperRun, PaperRuns, SimulationCosts,
    paper_figures, run_budgeted_against, run_paper_tables,
};
use hairlod::core::lod::{BudgetMethod, BudgetSettings, ErrorModel, LodSettings};
use hairlod::pipeline::PipelineRenderer;
use hairlod::popping::{ExcessPopping, Popping};
use hairlod::render::RendererOptions;
use hairlod::run::ModeRun;
use hairlod::scene_file::SceneFile;
use hairlod::shot::Shot;
use serde::Serialize;

use crate::charts::{ModelSeries, ModelSizeChart, write_png_and_svg};
use crate::report::{PaperShotArgs, Speedups, print_table, progress_bar, write_json};

/// Arguments of `hairlod bench`: a scene file, or one of the built-in benchmarks.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub which: Option<BenchKind>,
    /// Scene file to run in LODs and in each fixed level (its [lod] settings are the LODs').
    #[arg(value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    /// Write every number (per mode, per stage, per frame) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Also run the LODs in frame-budget mode at MS milliseconds (default: the scene's
    /// lod.budget_ms, if any).
    #[arg(long, value_name = "MS")]
    pub budget_ms: Option<f64>,
    /// Chart the simulated nodes and drawn segments per frame of LODs and Strands to FILE.png
    /// and FILE.svg.
    #[arg(long, value_name = "FILE")]
    pub chart: Option<PathBuf>,
}

/// The benchmarks.
#[derive(Debug, Subcommand)]
pub enum BenchKind {
    /// The paper's benchmark (§8.2): paper-curly, camera zooming out; LODs vs Strands, Clusters,
    /// Patches.
    Paper(PaperArgs),
    /// Where a paper-table frame's time goes, LODs against Strands: each stage, and the frame
    /// rendered with and without shadows, textures and full-size maps, and empty.
    Costs(crate::bench_costs::CostsArgs),
    /// Strand-line shading: render cost against image error for per-vertex and per-fragment
    /// shading at several tessellations, against a converged render.
    Shading(crate::bench_shading::ShadingArgs),
    /// Sub-pixel strand coverage: strands drawn with lines covering whole pixels and covering
    /// their width, against a supersampled reference, by SSIM.
    Coverage(crate::bench_coverage::CoverageArgs),
}

/// Arguments of `hairlod bench paper`.
#[derive(Debug, Args)]
pub struct PaperArgs {
    /// The shot: air, frames, image size.
    #[command(flatten)]
    pub shot: PaperShotArgs,
    /// Write every number (per mode, per stage, per frame) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Screen-space error tolerance of the LOD selector [pixels]: larger means coarser levels.
    #[arg(long, default_value_t = 1.0)]
    pub pixel_tolerance: f32,
    /// How the LODs estimate a level's error (the paper's tables use `chord`, the paper's rule;
    /// `deviation` is the library's default).
    #[arg(long, default_value_t = ErrorModel::Chord)]
    pub error_model: ErrorModel,
    /// Duration of the LODs' blend between levels [s] (default: the library's, 0.25 s; 0 switches
    /// instantly, as the paper does). The table always adds a row of the LODs switching instantly.
    #[arg(long, value_name = "SECONDS")]
    pub blend_time: Option<f32>,
    /// How far ahead the LODs' level choice looks, as a fraction of the blend time, 0..=1
    /// (default: the library's, 0.5; 0: the current frame only).
    #[arg(long, value_name = "FRACTION")]
    pub blend_lead: Option<f32>,
    /// Strand thinning of the LODs: strands drawn per pixel of a strand group's screen width, ≥ 0
    /// (default: the library's, 0: every strand; see docs/render.md, "Strand thinning"). The
    /// fixed levels always draw every strand.
    #[arg(long, value_name = "K")]
    pub strands_per_pixel: Option<f32>,
    /// With --strands-per-pixel: widen each strand the LODs draw to stand for those left out
    /// (1/φ its width for a drawn fraction φ, at most its group's width on screen), so that a
    /// thinned group covers what all its strands cover.
    #[arg(long)]
    pub raise_thinned_widths: bool,
    /// Also run the LODs in frame-budget mode: levels chosen so that a frame costs at most MS
    /// milliseconds (see --budget-method).
    #[arg(long, value_name = "MS")]
    pub budget_ms: Option<f64>,
    /// How the budget is met: `greedy` (least total estimated error within it) or `tolerance`
    /// (the pixel tolerance, starting from --pixel-tolerance, steered to meet it); comma-separated
    /// to run both.
    #[arg(long, value_delimiter = ',', default_value = "greedy")]
    pub budget_method: Vec<BudgetMethod>,
    /// Chart the simulated nodes and drawn segments per frame under LODs and Strands against the
    /// camera distance, to FILE.png and FILE.svg.
    #[arg(long, value_name = "FILE")]
    pub chart: Option<PathBuf>,
}

/// What `bench paper` runs beyond the four modes: the library's options and a chart.
#[derive(Debug, Clone, Default)]
pub struct PaperExtras {
    /// Overrides of the LODs and the frame-budget runs.
    pub options: PaperOptions,
    /// Model-size chart path.
    pub chart: Option<PathBuf>,
}

#[derive(Serialize)]
struct PaperReport<'a> {
    shot: &'a Shot,
    adapter: String,
    table: &'static str,
    modes: &'a [ModeRun],
    /// The LODs again with instant switching (the paper's transitions; `blend_time` 0), timed
    /// like the four modes.
    lods_instant_switching: &'a ModeRun,
    /// How collision found the hair near the head (`field-contacts`, `hierarchies` or
    /// `distance-field`).
    broad_phase: hairlod::collide::BroadPhase,
    /// How the levels were drawn (`level`: each as itself; `strands`: all as strands).
    drawn_as: hairlod::pipeline::DrawnAs,
    speedup_lods_over_strands: Speedups,
    popping_blended: Popping,
    popping_instant: Popping,
    excess_popping_blended: ExcessPopping,
    excess_popping_instant: ExcessPopping,
    popping_lod_stage: hairlod::popping::PoppingComparison,
    pixel_tolerance: f32,
    /// The LODs' strand thinning [strands per pixel of a group's width; 0: every strand].
    strands_per_pixel: f32,
    /// Whether the LODs' thinned strands were widened for those left out.
    raise_thinned_widths: bool,
    error_model: ErrorModel,
    mean_ssim_against_strands: AgainstStrands,
    mean_pixel_error_against_strands: AgainstStrands,
    paper_seconds_per_frame: Option<[[f64; 4]; 3]>,
    budgeted: Vec<BudgetedAgainstStrands>,
    /// Per mode, the simulation's cost per level: nodes, dynamics and collision per frame, and
    /// nanoseconds per node.
    simulation_costs: Vec<SimulationCosts>,
}

/// Runs `hairlod bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    match (&args.which, &args.scene) {
        (Some(BenchKind::Paper(paper)), _) => run_paper(paper),
        (Some(BenchKind::Shading(shading)), _) => crate::bench_shading::run(shading),
        (Some(BenchKind::Costs(costs)), _) => crate::bench_costs::run(costs),
        (Some(BenchKind::Coverage(coverage)), _) => crate::bench_coverage::run(coverage),
        (None, Some(path)) => run_scene(path, args),
        (None, None) => anyhow::bail!(
            "bench what? give a scene file (hairlod bench scenes/paper-table1.toml), or `paper` \
             or `shading`"
        ),
    }
}

/// `hairlod bench SCENE`.
fn run_scene(path: &std::path::Path, args: &BenchArgs) -> Result<()> {
    let shot = SceneFile::read(path)?.resolve()?;
    anyhow::ensure!(
        shot.frames >= 2,
        "{}: [frames] count must be at least 2 to benchmark (got {})",
        path.display(),
        shot.frames
    );
    if shot.is_crowd() {
        return crate::crowd_cmd::bench(&shot, args.budget_ms, args.json.as_deref());
    }
    let extras = PaperExtras {
        options: PaperOptions {
            budget_ms: args.budget_ms,
            ..PaperOptions::default()
        },
        chart: args.chart.clone(),
    };
    let pixel_tolerance = shot.lod_settings().pixel_tolerance;
    let report = paper_tables(&shot, pixel_tolerance, &extras)?;
    if let Some(path) = &args.json {
        write_json(path, &report)?;
    }
    Ok(())
}

fn run_paper(args: &PaperArgs) -> Result<()> {
    let shot = args.shot.shot()?;
    let extras = PaperExtras {
        options: PaperOptions {
            budget_ms: args.budget_ms,
            budget_methods: args.budget_method.clone(),
            error_model: Some(args.error_model),
            blend_time: args.blend_time,
            blend_lead: args.blend_lead,
            strands_per_pixel: args.strands_per_pixel,
            raise_thinned_widths: args.raise_thinned_widths.then_some(true),
        },
        chart: args.chart.clone(),
    };
    let report = paper_tables(&shot, args.pixel_tolerance, &extras)?;
    if let Some(path) = &args.json {
        write_json(path, &report)?;
    }
    Ok(())
}

/// Runs `shot` in the four modes (LODs at `pixel_tolerance`, then the fixed levels; and the LODs
/// again with instant switching, for the popping measure and a row of its own), prints the table in the paper's layout
/// (with the paper's figures when the shot is one of its tables) and returns the report.
pub fn paper_tables(
    shot: &Shot,
    pixel_tolerance: f32,
    extras: &PaperExtras,
) -> Result<serde_json::Value> {
    let mut shot = shot.clone();
    let scene = crate::scene_build::build_scene(&mut shot)?;
    let shot = &shot;
    let options = RendererOptions::from_env()?;
    let lod = extras.options.lod(shot, pixel_tolerance)?;
    let budgets = extras.options.budgets(shot, &lod)?;
    let mut renderer = PipelineRenderer::new(&options, &scene)?;
    renderer.set_style(shot.outputs.style());
    // The modes share this renderer: none pays for compiling the pipelines.
    renderer.warm_up(&scene)?;
    let adapter = renderer.renderer().adapter_report().to_string();
    let broad_phase = shot.settings.broad_phase;
    let drawn_as = shot.settings.drawn_as;
    println!(
        "rendering on {adapter}; collision broad phase: {broad_phase}; levels drawn as: {drawn_as}"
    );
    let bar = progress_bar(
        shot.frames * PaperRun::ALL.len(),
        "LODs, Strands, Clusters, Patches, LODs instant, frame by frame",
    );
    let runs = run_paper_tables(shot, &scene, lod, &mut renderer, |_, _| bar.inc(1))?;
    bar.finish();
    let PaperRuns {
        modes,
        instant: instant_run,
        mean_ssim,
        mean_pixels,
        popping_blended,
        popping_instant,
        excess_blended,
        excess_instant,
        strand_frames,
    } = runs;
    let paper = shot.paper_table.and_then(paper_figures);
    let title = match shot.paper_table {
        Some(1) => "Table 1: camera zooming out from the head",
        Some(2) => "Table 2: wind blowing through the hair as the camera zooms out",
        _ => "The scene in each mode",
    };
    let speedups = print_table(title, &modes, paper.as_ref(), shot);
    println!(
        "popping beyond the camera's motion (mean |Δluma| between frames, LODs minus Strands): \
         blended {:.5} at {} switch frames ({:.5} elsewhere), instant {:.5} at {} ({:.5} elsewhere)",
        excess_blended.at_switches,
        excess_blended.switch_frames,
        excess_blended.elsewhere,
        excess_instant.at_switches,
        excess_instant.switch_frames,
        excess_instant.elsewhere
    );
    let bar = progress_bar(2 * shot.frames, "popping, blended and instant");
    let popping_lod_stage =
        hairlod::popping::measure_popping(shot, &scene, lod, &mut renderer, || bar.inc(1))?;
    bar.finish();
    let (blended, instant) = (popping_lod_stage.blended, popping_lod_stage.instant);
    println!(
        "popping, what level decisions change with camera and skeletons still (mean |Δluma| at \
         {} frames where a level or visibility switch starts): blended {:.6}, instant {:.6}; \
         popping ratio to the hair's own motion: blended {:.4}, instant {:.4}; largest frame: \
         blended {:.6}, instant {:.6}",
        blended.switch_frames,
        blended.lod_change,
        instant.lod_change,
        blended.ratio,
        instant.ratio,
        blended.peak_lod_change,
        instant.peak_lod_change
    );
    println!(
        "mean SSIM against Strands, frame by frame: LODs {:.4}, Clusters {:.4}, Patches {:.4} \
         (LOD pixel tolerance {pixel_tolerance} px{})",
        mean_ssim.lods,
        mean_ssim.clusters,
        mean_ssim.patches,
        crate::report::thinning_label(&lod)
    );
    print_drawn(&modes);
    let simulation_costs: Vec<SimulationCosts> = modes.iter().map(SimulationCosts::of).collect();
    crate::report::print_simulation_costs(&simulation_costs);
    print_where_lods_sit(
        &modes,
        &instant_run,
        &mean_ssim,
        &mean_pixels,
        lod.error_model,
    );
    for warning in modes.iter().filter_map(ModeRun::stretch_warning) {
        eprintln!("{warning}");
    }
    println!(
        "popping (mean |Δimage| between frames, changing / steady): blended {:.3} ({:.5} / {:.5}), \
         instant {:.3} ({:.5} / {:.5})",
        popping_blended.ratio,
        popping_blended.changing,
        popping_blended.steady,
        popping_instant.ratio,
        popping_instant.changing,
        popping_instant.steady
    );
    let mut budgeted = Vec::new();
    for budget in budgets {
        budgeted.push(budgeted_run(
            shot,
            &scene,
            lod,
            budget,
            &mut renderer,
            &strand_frames,
        )?);
    }
    if let Some(path) = &extras.chart {
        model_size_chart(path, shot, &modes)?;
    }
    let report = PaperReport {
        shot,
        adapter,
        table: title,
        modes: &modes,
        lods_instant_switching: &instant_run,
        broad_phase,
        drawn_as,
        speedup_lods_over_strands: speedups,
        popping_blended,
        popping_instant,
        excess_popping_blended: excess_blended,
        excess_popping_instant: excess_instant,
        popping_lod_stage,
        pixel_tolerance,
        strands_per_pixel: lod.strands_per_pixel,
        raise_thinned_widths: lod.raise_thinned_widths,
        error_model: lod.error_model,
        mean_ssim_against_strands: mean_ssim,
        mean_pixel_error_against_strands: mean_pixels,
        paper_seconds_per_frame: paper,
        budgeted,
        simulation_costs,
    };
    Ok(serde_json::to_value(&report)?)
}

/// Runs the LODs under a frame budget and prints how often it was met and the SSIM it paid.
fn budgeted_run(
    shot: &Shot,
    scene: &Scene,
    lod: LodSettings,
    budget: BudgetSettings,
    renderer: &mut PipelineRenderer,
    strand_frames: &[image::GrayImage],
) -> Result<BudgetedAgainstStrands> {
    let bar = progress_bar(
        shot.frames,
        &format!("LODs, frame budget ({})", budget.method),
    );
    let budgeted = run_budgeted_against(
        shot,
        scene,
        lod,
        budget,
        renderer,
        strand_frames,
        |tolerance| {
            bar.set_message(format!("τ {tolerance:.2} px"));
            bar.inc(1);
        },
    )
    .context("the frame-budget run failed")?;
    bar.finish();
    let mean_ssim = budgeted.mean_ssim_against_strands;
    let b = &budgeted.run.budget;
    println!(
        "frame budget {:.1} ms ({}): met in {} of {} frames ({:.0} %), mean cost {:.1} ms, mean \
         tolerance {:.2} px (largest {:.2}), mean SSIM against Strands {:.4}",
        1e3 * b.budget,
        b.method,
        b.met,
        b.frames,
        100.0 * b.met_fraction,
        1e3 * b.mean_cost,
        b.mean_tolerance,
        b.max_tolerance,
        mean_ssim
    );
    Ok(budgeted)
}

/// Charts the simulated nodes and drawn segments per frame of the LODs and Strands runs with the
/// camera distance.
fn model_size_chart(path: &std::path::Path, shot: &Shot, modes: &[ModeRun]) -> Result<()> {
    let distances: Vec<f64> = (0..shot.frames)
        .map(|f| {
            f64::from({
                let camera = shot.camera(f);
                camera.position.distance(camera.target)
            })
        })
        .collect();
    let series: Vec<ModelSeries> = modes
        .iter()
        .take(2)
        .map(|run| ModelSeries {
            label: run.mode.to_string(),
            nodes: run
                .frames
                .iter()
                .map(|f| f.simulated_nodes as f64)
                .collect(),
            segments: run.frames.iter().map(|f| f.drawn_segments as f64).collect(),
        })
        .collect();
    let title = format!(
        "Model size over the camera path ({}): LODs against Strands",
        if shot.environment.wind == hairlod::core::dynamics::WindField::Calm {
            "calm"
        } else {
            "wind"
        }
    );
    let chart = ModelSizeChart {
        title,
        distances: &distances,
        series: &series,
    };
    let (png, svg) = write_png_and_svg(path, (1000, 560), &chart)?;
    println!("wrote {} and {}", png.display(), svg.display());
    Ok(())
}

/// Prints the table in the paper's layout (ours, paper's in brackets) and returns the speedups.
/// Where the LODs sit against the fixed levels: cost per frame (mean and median), its ratio to
/// Strands, SSIM and pixel error against the Strands frames, side by side. `modes` are LODs,
/// Strands, Clusters, Patches.
fn print_where_lods_sit(
    modes: &[ModeRun],
    instant: &ModeRun,
    ssim: &AgainstStrands,
    pixels: &AgainstStrands,
    error_model: ErrorModel,
) {
    let strands_mean = modes[1].mean.total();
    println!();
    println!("where the LODs ({error_model} error model) sit, against Strands frame by frame:");
    println!(
        "{:<25}{:>14}{:>16}{:>14}{:>10}{:>16}",
        "mode", "ms/frame mean", "ms/frame median", "vs Strands", "SSIM", "pixel error"
    );
    let rows = [
        (&modes[0], ssim.lods, pixels.lods),
        (
            instant,
            ssim.lods_instant_switching,
            pixels.lods_instant_switching,
        ),
        (&modes[1], 1.0, 0.0),
        (&modes[2], ssim.clusters, pixels.clusters),
        (&modes[3], ssim.patches, pixels.patches),
    ];
    for (run, ssim, pixels) in rows {
        let mean = run.mean.total();
        println!(
            "{:<25}{:>14.1}{:>16.1}{:>13.2}×{:>10.4}{:>16.2}",
            run.mode,
            1e3 * mean,
            1e3 * run.median_total,
            strands_mean / mean.max(f64::MIN_POSITIVE),
            ssim,
            pixels
        );
    }
}

/// Prints each mode's mean strands and strand segments drawn per frame, as the renderer drew them
/// (after thinning and dissolves), beside its mean nodes simulated and the substeps its dynamics
/// took (the most of any block, which the adaptive substeps raise where the hair moves fast).
fn print_drawn(modes: &[ModeRun]) {
    let mean = |run: &ModeRun, of: fn(&hairlod::pipeline::FrameReport) -> usize| {
        run.frames.iter().map(of).sum::<usize>() as f64 / run.frames.len().max(1) as f64
    };
    let parts: Vec<String> = modes
        .iter()
        .map(|run| {
            format!(
                "{} {:.0} strands, {:.0} segments, {:.0} nodes, {:.1} substeps",
                run.mode,
                mean(run, |f| f.rendered_strands),
                mean(run, |f| f.rendered_strand_segments),
                mean(run, |f| f.simulated_nodes),
                mean(run, |f| f.max_substeps as usize)
            )
        })
        .collect();
    println!(
        "drawn per frame, mean (after thinning), beside the nodes simulated and their substeps: {}",
        parts.join("; ")
    );
}
