//! `hairlod bench paper`: the paper's Tables 1 and 2 (§8.2) measured on this machine, next to the
//! paper's own figures, with the speedup of LODs over Strands and the popping measure.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use hairlod::benchmark::{
    ExcessPopping, ModeRun, PAPER_TABLE_1, PAPER_TABLE_2, PaperBenchmark, Popping, PoppingMeter,
    excess_popping, luma, paper_modes, run_mode, ssim,
};
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::RendererOptions;
use hairlod::{Pipeline, Scene};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

/// Arguments of `hairlod bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub which: BenchKind,
}

/// The benchmarks.
#[derive(Debug, Subcommand)]
pub enum BenchKind {
    /// The paper's benchmark (§8.2): paper-curly, camera zooming out; LODs vs Strands, Clusters,
    /// Patches.
    Paper(PaperArgs),
}

/// Arguments of `hairlod bench paper`.
#[derive(Debug, Args)]
pub struct PaperArgs {
    /// Blow a gusting wind (Table 2) instead of calm air (Table 1).
    #[arg(long)]
    pub wind: bool,
    /// Frames per mode.
    #[arg(long, default_value_t = 60)]
    pub frames: usize,
    /// Image size WIDTHxHEIGHT [pixels].
    #[arg(long, default_value = "1280x720")]
    pub size: String,
    /// Write every number (per mode, per stage, per frame) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Screen-space error tolerance of the LOD selector [pixels]: larger means coarser levels.
    #[arg(long, default_value_t = 1.0)]
    pub pixel_tolerance: f32,
}

/// Parses `WIDTHxHEIGHT`.
pub fn parse_size(text: &str) -> Result<(u32, u32)> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .with_context(|| format!("size `{text}` is not WIDTHxHEIGHT (for example 1280x720)"))?;
    let parse = |s: &str| -> Result<u32> {
        let value: u32 = s
            .trim()
            .parse()
            .with_context(|| format!("size `{text}`: `{s}` is not a whole number of pixels"))?;
        anyhow::ensure!(
            (16..=8192).contains(&value),
            "size `{text}`: {value} pixels is outside 16..=8192"
        );
        Ok(value)
    };
    Ok((parse(w)?, parse(h)?))
}

#[derive(Serialize)]
struct PaperReport<'a> {
    benchmark: PaperBenchmark,
    adapter: String,
    table: &'static str,
    modes: &'a [ModeRun],
    speedup_lods_over_strands: Speedups,
    popping_blended: Popping,
    popping_instant: Popping,
    excess_popping_blended: ExcessPopping,
    excess_popping_instant: ExcessPopping,
    pixel_tolerance: f32,
    mean_ssim_against_strands: SsimAgainstStrands,
    paper_seconds_per_frame: [[f64; 4]; 3],
}

#[derive(Serialize, Clone, Copy)]
struct SsimAgainstStrands {
    lods: f64,
    clusters: f64,
    patches: f64,
}

#[derive(Serialize, Clone, Copy)]
struct Speedups {
    dynamics: f64,
    collision: f64,
    rendering: f64,
    total: f64,
}

/// Runs `hairlod bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    match &args.which {
        BenchKind::Paper(paper) => run_paper(paper),
    }
}

fn run_paper(args: &PaperArgs) -> Result<()> {
    anyhow::ensure!(
        args.frames >= 2,
        "--frames must be at least 2 (got {})",
        args.frames
    );
    let (width, height) = parse_size(&args.size)?;
    let benchmark = PaperBenchmark {
        frames: args.frames,
        wind: args.wind,
        width,
        height,
        ..PaperBenchmark::default()
    };
    let report = paper_tables(&benchmark, args.pixel_tolerance)?;
    if let Some(path) = &args.json {
        write_json(path, &report)?;
    }
    Ok(())
}

/// Runs the four modes (and the LODs again with instant switching for the popping measure),
/// prints the table and returns the report.
pub fn paper_tables(benchmark: &PaperBenchmark, pixel_tolerance: f32) -> Result<serde_json::Value> {
    let scene = Scene::preset("paper-curly")?;
    let options = RendererOptions::from_env()?;
    let lod = hairlod::core::lod::LodSettings {
        pixel_tolerance,
        ..benchmark.lod_settings()
    };
    lod.validate()?;
    let first = Pipeline::new(
        scene.clone(),
        benchmark.environment(),
        PipelineSettings::default(),
    )?;
    let mut renderer = PipelineRenderer::new(&options, &first)?;
    drop(first);
    let adapter = renderer.renderer().adapter_report().to_string();
    println!("rendering on {adapter}");
    let mut modes = Vec::new();
    let mut popping_blended = Popping::default();
    let instant = LodMode::Auto(hairlod::core::lod::LodSettings {
        blend_time: 0.0,
        ..lod
    });
    let runs: Vec<(LodMode, &str)> = paper_modes(lod)
        .into_iter()
        .map(|mode| (mode, mode.column_name()))
        .chain([(instant, "LODs, instant switching")])
        .collect();
    let mut popping_instant = Popping::default();
    // Luma of the LODs and Strands frames, for SSIM against Strands (the finest level).
    let mut lod_frames = Vec::new();
    let mut strand_frames = Vec::new();
    let mut instant_frames = Vec::new();
    let mut instant_switched = Vec::new();
    let mut ssim_sums = [0.0f64; 4];
    for (index, (mode, label)) in runs.iter().enumerate() {
        let bar = ProgressBar::new(benchmark.frames as u64).with_style(
            ProgressStyle::with_template("{prefix:>26} [{bar:30}] {pos}/{len} frames {elapsed}")
                .expect("a valid template")
                .progress_chars("=> "),
        );
        bar.set_prefix(label.to_string());
        let settings = PipelineSettings {
            lod: *mode,
            ..PipelineSettings::default()
        };
        let mut meter = PoppingMeter::default();
        let run = run_mode(
            benchmark,
            &scene,
            settings,
            Some(&mut renderer),
            |report, image| {
                if let Some(image) = image {
                    meter.add(image, report.level_changes > 0);
                    let frame = report.frame;
                    match index {
                        0 => lod_frames.push(luma(image)),
                        1 => {
                            let gray = luma(image);
                            ssim_sums[0] += ssim(&lod_frames[frame], &gray);
                            strand_frames.push(gray);
                        }
                        2 | 3 => ssim_sums[index] += ssim(&strand_frames[frame], &luma(image)),
                        _ => {
                            instant_frames.push(luma(image));
                            instant_switched.push(report.level_changes > 0);
                        }
                    }
                }
                bar.inc(1);
            },
        )
        .with_context(|| format!("the {label} run failed"))?;
        bar.finish();
        match index {
            0 => popping_blended = meter.popping(),
            4 => popping_instant = meter.popping(),
            _ => {}
        }
        if index < 4 {
            modes.push(run);
        }
    }
    let (title, paper) = if benchmark.wind {
        (
            "Table 2: wind blowing through the hair as the camera zooms out",
            PAPER_TABLE_2,
        )
    } else {
        ("Table 1: camera zooming out from the head", PAPER_TABLE_1)
    };
    let speedups = print_table(title, &modes, &paper, benchmark);
    let blended_switched: Vec<bool> = modes[0]
        .frames
        .iter()
        .map(|f| f.level_changes > 0)
        .collect();
    let excess_blended = excess_popping(&lod_frames, &strand_frames, &blended_switched);
    let excess_instant = excess_popping(&instant_frames, &strand_frames, &instant_switched);
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
    let frames = benchmark.frames as f64;
    let mean_ssim = SsimAgainstStrands {
        lods: ssim_sums[0] / frames,
        clusters: ssim_sums[2] / frames,
        patches: ssim_sums[3] / frames,
    };
    println!(
        "mean SSIM against Strands, frame by frame: LODs {:.4}, Clusters {:.4}, Patches {:.4} \
         (LOD pixel tolerance {pixel_tolerance} px)",
        mean_ssim.lods, mean_ssim.clusters, mean_ssim.patches
    );
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
    let report = PaperReport {
        benchmark: *benchmark,
        adapter,
        table: title,
        modes: &modes,
        speedup_lods_over_strands: speedups,
        popping_blended,
        popping_instant,
        excess_popping_blended: excess_blended,
        excess_popping_instant: excess_instant,
        pixel_tolerance,
        mean_ssim_against_strands: mean_ssim,
        paper_seconds_per_frame: paper,
    };
    Ok(serde_json::to_value(&report)?)
}

/// Prints the table in the paper's layout (ours, paper's in brackets) and returns the speedups.
fn print_table(
    title: &str,
    modes: &[ModeRun],
    paper: &[[f64; 4]; 3],
    benchmark: &PaperBenchmark,
) -> Speedups {
    println!();
    println!(
        "{title} ({} frames, {}x{}; seconds per frame, mean; the paper's in brackets)",
        benchmark.frames, benchmark.width, benchmark.height
    );
    print!("{:<12}", "Breakdown");
    for run in modes {
        print!("{:>20}", run.mode);
    }
    println!("{:>14}", "LODs speedup");
    type Row = (&'static str, fn(&ModeRun) -> f64);
    let rows: [Row; 3] = [
        ("Dyn Sim", |r| r.mean.dynamics),
        ("Col Detect", |r| r.mean.collision),
        ("Rendering", |r| r.mean.rendering),
    ];
    let mut speedup = [0.0; 4];
    for (row, (name, value)) in rows.iter().enumerate() {
        print!("{name:<12}");
        for (column, run) in modes.iter().enumerate() {
            print!("{:>11.4} ({:.3})", value(run), paper[row][column]);
        }
        speedup[row] = value(&modes[1]) / value(&modes[0]).max(1e-12);
        println!("{:>13.2}×", speedup[row]);
    }
    print!("{:<12}", "Total");
    for (column, run) in modes.iter().enumerate() {
        let paper_total: f64 = paper.iter().map(|row| row[column]).sum();
        let total = run.mean.dynamics + run.mean.collision + run.mean.rendering;
        print!("{total:>11.4} ({paper_total:.3})");
    }
    let total = |run: &ModeRun| run.mean.dynamics + run.mean.collision + run.mean.rendering;
    speedup[3] = total(&modes[1]) / total(&modes[0]).max(1e-12);
    println!("{:>13.2}×", speedup[3]);
    let paper_speedup =
        paper.iter().map(|r| r[1]).sum::<f64>() / paper.iter().map(|r| r[0]).sum::<f64>();
    println!(
        "(the paper's LODs speedup in total: {paper_speedup:.2}×; LOD level selection took {:.4} s per frame)",
        modes[0].mean.lod
    );
    Speedups {
        dynamics: speedup[0],
        collision: speedup[1],
        rendering: speedup[2],
        total: speedup[3],
    }
}

pub fn write_json(path: &std::path::Path, value: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    let temporary = path.with_extension("json.partial");
    std::fs::write(&temporary, text).with_context(|| format!("writing {}", temporary.display()))?;
    std::fs::rename(&temporary, path).with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}
