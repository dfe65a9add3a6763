//! `hairlod bench shading`: the strand level's render cost against its image error, for lines
//! shaded at the curve points (`LineShading::PerVertex`) and per fragment, at several
//! tessellations, against a converged render (per fragment, many segments per strand). The groom
//! is paper-curly (37,765 strands) in its rest pose, as in the criterion render bench.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use glam::Vec3;
use hairlod::core::{Level, Scene};
use hairlod::metrics::{luma, luma_difference, ssim};
use hairlod::render::settings::MAX_SEGMENTS_LIMIT;
use hairlod::render::{
    ActiveSkeletons, Camera, FrameSettings, LineShading, Renderer, RendererOptions,
};
use indicatif::{ProgressBar, ProgressStyle};
use plotters::style::RGBColor;
use serde::Serialize;

use crate::charts::{ParetoChart, ScatterPoint, write_png_and_svg};
use crate::pareto::pareto_front;
use crate::report::write_json;

/// Arguments of `hairlod bench shading`.
#[derive(Debug, Args)]
pub struct ShadingArgs {
    /// Image size WIDTHxHEIGHT [pixels].
    #[arg(long, default_value = "1280x720", value_parser = crate::cli_args::size)]
    pub size: (u32, u32),
    /// Segments per strand to measure, comma-separated.
    #[arg(long, default_value = "16,32,64,128", value_delimiter = ',')]
    pub segments: Vec<u32>,
    /// Segments per strand of the converged reference (shaded per fragment).
    #[arg(long, default_value_t = 256)]
    pub reference_segments: u32,
    /// Timed renders per configuration (the median is reported).
    #[arg(long, default_value_t = 5)]
    pub repeats: usize,
    /// Write every number as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Chart cost against error to FILE.png and FILE.svg.
    #[arg(long, value_name = "FILE")]
    pub chart: Option<PathBuf>,
}

/// One configuration's measurement.
#[derive(Debug, Clone, Serialize)]
struct ShadingPoint {
    shading: &'static str,
    segments: u32,
    /// Median render time (upload, draw, readback) [ms].
    median_ms: f64,
    /// Every timed render [ms].
    times_ms: Vec<f64>,
    /// 1 − SSIM (luma) against the reference.
    ssim_loss: f64,
    /// Mean absolute luma difference against the reference [8-bit levels].
    mean_luma_difference: f64,
    pareto_ssim: bool,
    pareto_luma: bool,
}

#[derive(Serialize)]
struct ShadingReport<'a> {
    adapter: String,
    width: u32,
    height: u32,
    strands: usize,
    reference_segments: u32,
    reference_ms: f64,
    points: &'a [ShadingPoint],
}

fn shading_name(shading: LineShading) -> &'static str {
    match shading {
        LineShading::PerVertex => "per-vertex",
        LineShading::PerFragment => "per-fragment",
    }
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted[sorted.len() / 2]
}

fn check_args(args: &ShadingArgs) -> Result<()> {
    anyhow::ensure!(args.repeats >= 1, "--repeats must be at least 1");
    anyhow::ensure!(
        !args.segments.is_empty(),
        "--segments needs at least one count"
    );
    for &segments in args.segments.iter().chain([&args.reference_segments]) {
        anyhow::ensure!(
            (1..=MAX_SEGMENTS_LIMIT).contains(&segments),
            "{segments} segments per strand is outside 1..={MAX_SEGMENTS_LIMIT}"
        );
    }
    Ok(())
}

/// Runs `hairlod bench shading`.
pub fn run(args: &ShadingArgs) -> Result<()> {
    check_args(args)?;
    let (width, height) = args.size;
    let scene = Scene::preset("paper-curly")?;
    let groom = &scene.groom;
    let mut renderer = Renderer::new(&RendererOptions::from_env()?)?;
    let adapter = renderer.adapter_report().to_string();
    eprintln!("adapter: {adapter}");
    renderer.upload_groom(groom)?;
    let mut active = ActiveSkeletons::new();
    active.gather_rest_pose(groom, Level::StrandGroup)?;
    let camera = Camera::orbit(
        Vec3::new(0.0, -0.01, 0.0),
        0.8,
        150f32.to_radians(),
        8f32.to_radians(),
        35f32.to_radians(),
    );
    let base = FrameSettings::new(width, height, camera);
    let settings_for = |shading: LineShading, segments: u32| {
        let mut settings = FrameSettings {
            line_shading: shading,
            ..base
        };
        settings.tessellation.max_segments = segments;
        settings.tessellation.min_segments = segments;
        settings
    };
    let mut timed = |settings: &FrameSettings| -> Result<(image::RgbaImage, f64)> {
        let start = Instant::now();
        let image = renderer.render(&active.frame(), settings)?;
        Ok((image, start.elapsed().as_secs_f64() * 1e3))
    };

    let configurations: Vec<(LineShading, u32)> =
        [LineShading::PerFragment, LineShading::PerVertex]
            .into_iter()
            .flat_map(|shading| args.segments.iter().map(move |&s| (shading, s)))
            .collect();
    let progress = ProgressBar::new((1 + configurations.len() * (args.repeats + 1)) as u64);
    progress.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} renders {msg}")
            .context("progress bar template")?,
    );
    progress.set_message("reference");
    let (reference, reference_ms) = timed(&settings_for(
        LineShading::PerFragment,
        args.reference_segments,
    ))?;
    progress.inc(1);
    let reference = luma(&reference);

    let mut points = Vec::new();
    for &(shading, segments) in &configurations {
        progress.set_message(format!("{} ×{segments}", shading_name(shading)));
        let settings = settings_for(shading, segments);
        // One untimed render first: it grows the buffers for this tessellation.
        let (image, _) = timed(&settings)?;
        progress.inc(1);
        let mut times_ms = Vec::with_capacity(args.repeats);
        for _ in 0..args.repeats {
            times_ms.push(timed(&settings)?.1);
            progress.inc(1);
        }
        let image = luma(&image);
        points.push(ShadingPoint {
            shading: shading_name(shading),
            segments,
            median_ms: median(&times_ms),
            times_ms,
            ssim_loss: 1.0 - ssim(&image, &reference),
            mean_luma_difference: 255.0 * luma_difference(&image, &reference),
            pareto_ssim: false,
            pareto_luma: false,
        });
    }
    progress.finish_and_clear();
    let fronts = [
        pareto_front(&keys(&points, |p| p.ssim_loss)),
        pareto_front(&keys(&points, |p| p.mean_luma_difference)),
    ];
    for (i, point) in points.iter_mut().enumerate() {
        point.pareto_ssim = fronts[0][i];
        point.pareto_luma = fronts[1][i];
    }

    print_table(
        &points,
        width,
        height,
        args.reference_segments,
        reference_ms,
    );
    if let Some(path) = &args.json {
        let report = ShadingReport {
            adapter,
            width,
            height,
            strands: groom.strands.strand_count(),
            reference_segments: args.reference_segments,
            reference_ms,
            points: &points,
        };
        write_json(path, &serde_json::to_value(&report)?)?;
    }
    if let Some(path) = &args.chart {
        let (png, svg) = write_chart(path, &points, width, height, args.reference_segments)?;
        println!("chart: {} and {}", png.display(), svg.display());
    }
    Ok(())
}

fn keys(points: &[ShadingPoint], error: impl Fn(&ShadingPoint) -> f64) -> Vec<Option<(f64, f64)>> {
    points
        .iter()
        .map(|p| Some((p.median_ms, error(p))))
        .collect()
}

fn print_table(
    points: &[ShadingPoint],
    width: u32,
    height: u32,
    reference_segments: u32,
    reference_ms: f64,
) {
    println!(
        "Strand lines of paper-curly at {width}x{height} against per-fragment ×{reference_segments} \
         ({reference_ms:.0} ms); * marks the SSIM front"
    );
    println!(
        "{:<14} {:>8} {:>11} {:>10} {:>14}",
        "shading", "segments", "median ms", "SSIM", "luma diff [lv]"
    );
    for p in points {
        println!(
            "{:<14} {:>8} {:>11.1} {:>10.4} {:>14.3} {}",
            p.shading,
            p.segments,
            p.median_ms,
            1.0 - p.ssim_loss,
            p.mean_luma_difference,
            if p.pareto_ssim { "*" } else { "" }
        );
    }
}

fn write_chart(
    path: &std::path::Path,
    points: &[ShadingPoint],
    width: u32,
    height: u32,
    reference_segments: u32,
) -> Result<(PathBuf, PathBuf)> {
    let scatter: Vec<ScatterPoint> = points
        .iter()
        .map(|p| ScatterPoint {
            label: format!("×{}", p.segments),
            cost_ms: p.median_ms,
            errors: [p.ssim_loss, p.mean_luma_difference],
            pareto: [p.pareto_ssim, p.pareto_luma],
            group: usize::from(p.shading == "per-vertex"),
        })
        .collect();
    let chart = ParetoChart {
        title: format!(
            "Strand lines, paper-curly {width}x{height}: per-fragment (blue) and per-vertex \
             (red) shading at N segments per strand, against per-fragment ×{reference_segments}"
        ),
        panel_names: [
            "SSIM loss (1 − SSIM vs reference, log scale)",
            "mean luma difference vs reference [levels] (log scale)",
        ],
        group_colours: &[RGBColor(33, 102, 172), RGBColor(214, 96, 77)],
        points: &scatter,
    };
    write_png_and_svg(path, (1100, 480), &chart)
}
