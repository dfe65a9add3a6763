//! `hairlod demo`: the default scene and main job. The paper's benchmark scene (paper-curly,
//! wind, camera zooming out) simulated with automatic levels of detail and rendered to `./out` as
//! shaded and colour-coded image sequences (like the paper's Fig. 6), then the Table 2 comparison
//! of LODs against the fixed levels.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use hairlod::benchmark::{PaperOptions, paper_shot, resized};
use hairlod::core::lod::{ErrorModel, LodSettings};
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::RendererOptions;
use hairlod::render::output::{frame_path, write_png_atomic};
use hairlod::run::{RunOptions, View, run_shot};
use indicatif::{ProgressBar, ProgressStyle};

use crate::bench_cmd::{PaperExtras, paper_tables};
use crate::report::write_json;

/// Arguments of `hairlod demo` (also writes `side_by_side.png`: a frame a quarter through, shaded |
/// colour-coded).
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output folder: `shaded/` and `levels/` image sequences and `bench.json`.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Frames of the sequence (and of each benchmark mode).
    #[arg(long, default_value_t = 36)]
    pub frames: usize,
    /// Image size WIDTHxHEIGHT [pixels].
    #[arg(long, default_value = "640x360", value_parser = crate::cli_args::size)]
    pub size: (u32, u32),
    /// Only write the image sequences; skip the four-mode comparison.
    #[arg(long)]
    pub no_bench: bool,
    /// Screen-space error tolerance of the LOD selector [pixels]: larger means coarser levels
    /// (the library's default, with error-driven selection).
    #[arg(long, default_value_t = LodSettings::default().pixel_tolerance)]
    pub pixel_tolerance: f32,
}

/// Runs `hairlod demo`.
pub fn run(args: &DemoArgs) -> Result<()> {
    anyhow::ensure!(
        args.frames >= 2,
        "--frames must be at least 2 (got {})",
        args.frames
    );
    let (width, height) = args.size;
    let shot = resized(&paper_shot(true), args.frames, width, height);
    let scene = shot.build_scene()?;
    let lod = LodSettings {
        pixel_tolerance: args.pixel_tolerance,
        error_model: ErrorModel::Deviation,
        ..shot.lod_settings()
    };
    let settings = PipelineSettings {
        lod: LodMode::Auto(lod),
        ..shot.settings
    };
    let mut renderer = PipelineRenderer::new(&RendererOptions::from_env()?, &scene)?;
    println!("rendering on {}", renderer.renderer().adapter_report());
    let shaded_dir = args.out.join("shaded");
    let levels_dir = args.out.join("levels");
    for dir in [&shaded_dir, &levels_dir] {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let bar = ProgressBar::new(args.frames as u64).with_style(
        ProgressStyle::with_template("demo [{bar:30}] {pos}/{len} frames {elapsed} {msg}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    let views = [View::Shaded, View::LevelColors];
    let frames = args.frames as u64;
    run_shot(
        &shot,
        &scene,
        RunOptions::whole(&shot, settings),
        Some((&mut renderer, &views)),
        |frame| {
            let index = frame.report.frame;
            write_png_atomic(
                &frame.images[0],
                &frame_path(&shaded_dir, index as u64, frames),
            )?;
            write_png_atomic(
                &frame.images[1],
                &frame_path(&levels_dir, index as u64, frames),
            )?;
            if index == args.frames / 4 {
                // One picture like the paper's Fig. 6: shaded | colour-coded.
                let mut pair = image::RgbaImage::new(2 * width, height);
                image::imageops::replace(&mut pair, &frame.images[0], 0, 0);
                image::imageops::replace(&mut pair, &frame.images[1], i64::from(width), 0);
                write_png_atomic(&pair, &args.out.join("side_by_side.png"))?;
            }
            let [p, c, s] = frame.report.sections_at;
            bar.set_message(format!("{s} strand groups, {c} clusters, {p} patches"));
            bar.inc(1);
            Ok(())
        },
    )?;
    bar.finish();
    println!(
        "wrote {} frames to {} and {} (strands yellow, clusters red, patches blue)",
        args.frames,
        shaded_dir.display(),
        levels_dir.display()
    );
    if !args.no_bench {
        let extras = PaperExtras {
            options: PaperOptions {
                error_model: Some(ErrorModel::Deviation),
                ..PaperOptions::default()
            },
            chart: Some(args.out.join("model_size.png")),
        };
        let report = paper_tables(&shot, args.pixel_tolerance, &extras)?;
        write_json(&args.out.join("bench.json"), &report)?;
    }
    Ok(())
}
