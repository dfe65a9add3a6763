//! `hairlod accuracy`: speed against accuracy (issue 7). Runs the reference (every section at
//! strand level) and a sweep of configurations (fixed clusters and patches, LODs at several pixel
//! tolerances) over the paper benchmark's camera path and control inputs, and prints for each the
//! median cost per frame against its error: mean SSIM loss and mean screen-space pixel error
//! against the reference, frame by frame (see `hairlod::accuracy`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use hairlod::accuracy::{
    GeometricError, PhysicalError, geometric_error, head_body, image_error, sample_skeletons,
    strand_skeletons,
};
use hairlod::benchmark::{PaperBenchmark, SETTLE_TIME};
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::{RendererOptions, ShadingMode};
use hairlod::{Level, Pipeline, Scene};
use serde::Serialize;

use crate::bench_cmd::parse_size;

/// Samples per strand-group skeleton for the geometric error.
const SAMPLES_PER_SKELETON: usize = 8;

/// Arguments of `hairlod accuracy`.
#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// Groom preset.
    #[arg(long, default_value = "paper-curly")]
    pub preset: String,
    /// Blow the benchmark's gusting wind.
    #[arg(long)]
    pub wind: bool,
    /// Frames per configuration (the benchmark's zoom-out path over that many frames).
    #[arg(long, default_value_t = 30)]
    pub frames: usize,
    /// Image size WIDTHxHEIGHT [pixels].
    #[arg(long, default_value = "640x360")]
    pub size: String,
    /// LOD pixel tolerances to sweep [pixels], comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "0.5,1,2,4")]
    pub tolerances: Vec<f32>,
    /// Write every point (and every frame's errors) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// One frame of one configuration against the reference.
#[derive(Debug, Clone, Copy, Serialize)]
struct FrameErrors {
    /// Total cost of the frame (LOD, dynamics, collision, rendering) [s].
    cost: f64,
    /// SSIM against the reference frame.
    ssim: f64,
    /// PSNR against the reference frame [dB] (`null` in JSON when infinite).
    psnr: f64,
    /// Screen-space error of the hair samples [pixels].
    geometric: GeometricError,
    /// Segment-length error and penetration depth.
    physical: PhysicalError,
}

/// One configuration of the sweep.
#[derive(Debug, Clone, Serialize)]
struct Point {
    /// `Strands` (the reference), `Clusters`, `Patches`, `LODs 1px`...
    label: String,
    /// Median total cost per frame [s].
    median_cost: f64,
    /// 1 − mean SSIM against the reference.
    ssim_loss: f64,
    /// Mean over frames of the mean pixel error [pixels].
    mean_pixel_error: f64,
    /// Mean over frames of the 95th-percentile pixel error [pixels].
    mean_p95_pixel_error: f64,
    /// Worst segment-length error and penetration over the run.
    physical: PhysicalError,
    /// On the Pareto front of (median cost, SSIM loss): no other point is at least as cheap and
    /// at least as accurate and better in one.
    pareto: bool,
    /// Every frame.
    frames: Vec<FrameErrors>,
}

/// What the reference leaves per frame for the others to be compared with.
struct ReferenceFrame {
    image: image::RgbaImage,
    samples: Vec<glam::Vec3>,
}

/// Runs `hairlod accuracy`.
pub fn run(args: &AccuracyArgs) -> Result<()> {
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
    let scene = Scene::preset(&args.preset)?;
    let mut configurations = vec![
        ("Strands".to_string(), LodMode::Fixed(Level::StrandGroup)),
        ("Clusters".to_string(), LodMode::Fixed(Level::Cluster)),
        ("Patches".to_string(), LodMode::Fixed(Level::Patch)),
    ];
    for &tolerance in &args.tolerances {
        let lod = hairlod::core::lod::LodSettings {
            pixel_tolerance: tolerance,
            ..benchmark.lod_settings()
        };
        lod.validate()?;
        configurations.push((format!("LODs {tolerance}px"), LodMode::Auto(lod)));
    }
    let first = Pipeline::new(
        scene.clone(),
        benchmark.environment(),
        PipelineSettings::default(),
    )?;
    let mut renderer = PipelineRenderer::new(&RendererOptions::from_env()?, &first)?;
    drop(first);
    println!(
        "rendering on {}; {} frames at {width}x{height} of {}",
        renderer.renderer().adapter_report(),
        args.frames,
        args.preset
    );
    let mut reference: Vec<ReferenceFrame> = Vec::with_capacity(args.frames);
    let mut points = Vec::new();
    for (label, mode) in configurations {
        let settings = PipelineSettings {
            lod: mode,
            ..PipelineSettings::default()
        };
        let mut pipeline = Pipeline::new(scene.clone(), benchmark.environment(), settings)?;
        pipeline.settle(SETTLE_TIME)?;
        renderer.bind(&pipeline)?;
        let is_reference = reference.is_empty();
        let mut frames = Vec::with_capacity(args.frames);
        for frame in 0..args.frames {
            let camera = benchmark.camera(frame);
            let report = pipeline.advance(&camera)?;
            let (image, seconds) =
                renderer.render(&mut pipeline, &camera, width, height, ShadingMode::Shaded)?;
            let samples = sample_skeletons(
                &pipeline.scene().groom,
                &strand_skeletons(&pipeline)?,
                SAMPLES_PER_SKELETON,
            );
            let physical = PhysicalError::of(&pipeline, &head_body(&pipeline)?);
            if is_reference {
                reference.push(ReferenceFrame { image, samples });
                let reference = &reference[frame];
                frames.push(FrameErrors {
                    cost: report.times.total() - report.times.rendering + seconds,
                    ssim: 1.0,
                    psnr: f64::INFINITY,
                    geometric: geometric_error(
                        &camera,
                        width,
                        height,
                        &reference.samples,
                        &reference.samples,
                    ),
                    physical,
                });
                continue;
            }
            let reference = &reference[frame];
            let image_errors = image_error(&reference.image, &image);
            frames.push(FrameErrors {
                cost: report.times.total() - report.times.rendering + seconds,
                ssim: image_errors.ssim,
                psnr: image_errors.psnr,
                geometric: geometric_error(&camera, width, height, &reference.samples, &samples),
                physical,
            });
        }
        let point = summarise(label, frames);
        println!(
            "{:>14}: {:8.2} ms/frame  SSIM loss {:.4}  pixel error {:.2} (p95 {:.2})",
            point.label,
            1e3 * point.median_cost,
            point.ssim_loss,
            point.mean_pixel_error,
            point.mean_p95_pixel_error
        );
        points.push(point);
    }
    mark_pareto(&mut points);
    println!("\nPareto front (cost against SSIM loss):");
    for point in points.iter().filter(|p| p.pareto) {
        println!(
            "  {:>14}: {:8.2} ms/frame  SSIM {:.4}",
            point.label,
            1e3 * point.median_cost,
            1.0 - point.ssim_loss
        );
    }
    if let Some(path) = &args.json {
        let report = serde_json::json!({
            "preset": args.preset,
            "frames": args.frames,
            "width": width,
            "height": height,
            "wind": args.wind,
            "reference": "Strands",
            "points": points,
        });
        let text = serde_json::to_string_pretty(&report)?;
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn summarise(label: String, frames: Vec<FrameErrors>) -> Point {
    let n = frames.len().max(1) as f64;
    let mut costs: Vec<f64> = frames.iter().map(|f| f.cost).collect();
    costs.sort_by(f64::total_cmp);
    let median_cost = costs.get(costs.len() / 2).copied().unwrap_or(0.0);
    let physical = frames
        .iter()
        .fold(PhysicalError::default(), |worst, f| worst.max(f.physical));
    Point {
        label,
        median_cost,
        ssim_loss: 1.0 - frames.iter().map(|f| f.ssim).sum::<f64>() / n,
        mean_pixel_error: frames.iter().map(|f| f.geometric.mean_pixels).sum::<f64>() / n,
        mean_p95_pixel_error: frames.iter().map(|f| f.geometric.p95_pixels).sum::<f64>() / n,
        physical,
        pareto: false,
        frames,
    }
}

/// Marks the points that no other point dominates in (median cost, SSIM loss).
fn mark_pareto(points: &mut [Point]) {
    let keys: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (p.median_cost, p.ssim_loss))
        .collect();
    for (i, point) in points.iter_mut().enumerate() {
        let (cost, loss) = keys[i];
        point.pareto = !keys
            .iter()
            .enumerate()
            .any(|(j, &(c, l))| j != i && c <= cost && l <= loss && (c < cost || l < loss));
    }
}
