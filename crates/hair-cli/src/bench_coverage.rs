//! `hairlod bench coverage`: sub-pixel strand coverage against a supersampled reference. The
//! paper-curly groom, hanging at rest, drawn as strands at several camera distances with lines
//! covering whole pixels and lines covering their fibre's width, each compared by SSIM with a
//! render `factor`× larger on both axes and box-filtered down
//! ([`hairlod::benchmark::coverage`]).

use std::path::PathBuf;

use anyhow::{Context, Result, ensure};
use clap::Args;
use hairlod::benchmark::coverage::{CoverageMeasure, coverage_camera, measure_coverage};
use hairlod::benchmark::paper_shot;
use hairlod::core::Level;
use hairlod::render::{ActiveSkeletons, FrameSettings, Renderer, RendererOptions, output};
use serde::Serialize;

use crate::report::write_json;

/// Arguments of `hairlod bench coverage`.
#[derive(Debug, Args)]
pub struct CoverageArgs {
    /// Image size WIDTHxHEIGHT [pixels] (the reference is `factor` times larger on both axes).
    #[arg(long, default_value = "640x360", value_parser = crate::cli_args::size)]
    pub size: (u32, u32),
    /// Camera distances from the head [m], comma-separated.
    #[arg(long, default_value = "0.45,0.8,1.5,3,6", value_delimiter = ',')]
    pub distances: Vec<f32>,
    /// Supersampling factor of the reference on each axis (2 to 8).
    #[arg(long, default_value_t = 4)]
    pub factor: u32,
    /// Write every number as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write each distance's images (lines covering whole pixels, their width, the reference)
    /// to DIR.
    #[arg(long, value_name = "DIR")]
    pub images: Option<PathBuf>,
}

#[derive(Serialize)]
struct CoverageRow {
    distance_m: f32,
    #[serde(flatten)]
    measure: CoverageMeasure,
}

#[derive(Serialize)]
struct CoverageReport<'a> {
    adapter: String,
    width: u32,
    height: u32,
    factor: u32,
    rows: &'a [CoverageRow],
}

/// Runs `hairlod bench coverage`.
pub fn run(args: &CoverageArgs) -> Result<()> {
    ensure!(
        (2..=8).contains(&args.factor),
        "--factor {} must be 2 to 8",
        args.factor
    );
    for &distance in &args.distances {
        ensure!(
            distance.is_finite() && distance > 0.1,
            "--distances: {distance} m must be finite and above 0.1 m (the head's size)"
        );
    }
    let (width, height) = args.size;
    if let Some(dir) = &args.images {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create image folder {}", dir.display()))?;
    }
    eprintln!("hanging the paper-curly groom at rest…");
    let scene = paper_shot(false).build_scene()?;
    let mut renderer = Renderer::new(&RendererOptions::from_env()?)?;
    let adapter = renderer.adapter_report().to_string();
    eprintln!("adapter: {adapter}");
    renderer.upload_groom(&scene.groom)?;
    renderer.set_head_mesh(Some(&scene.head.mesh))?;
    let mut active = ActiveSkeletons::new();
    active.gather_rest_pose(&scene.groom, Level::StrandGroup)?;

    println!(
        "paper-curly strands at rest, {width}x{height}, against a {f}x{f} supersampled reference \
         (lines covering their width; plain: whole-pixel lines at the fine size)",
        f = args.factor
    );
    println!(
        "{:>9} {:>12} {:>12} {:>14} {:>14} {:>10} {:>10}",
        "distance",
        "SSIM pixel",
        "SSIM width",
        "plain: pixel",
        "plain: width",
        "ms pixel",
        "ms width"
    );
    let mut rows = Vec::new();
    for &distance in &args.distances {
        let camera = coverage_camera(distance);
        let settings = FrameSettings::new(width, height, camera);
        let (measure, images) =
            measure_coverage(&mut renderer, &active.frame(), &settings, args.factor)?;
        println!(
            "{:>7.2} m {:>12.4} {:>12.4} {:>14.4} {:>14.4} {:>10.1} {:>10.1}",
            distance,
            measure.ssim_pixel,
            measure.ssim_width,
            measure.plain_ssim_pixel,
            measure.plain_ssim_width,
            measure.ms_pixel,
            measure.ms_width
        );
        if let Some(dir) = &args.images {
            for (name, image) in [
                ("pixel", &images.pixel),
                ("width", &images.width),
                ("reference", &images.reference),
            ] {
                let path = dir.join(format!("coverage-{distance}m-{name}.png"));
                output::write_png_atomic(image, &path)?;
            }
        }
        rows.push(CoverageRow {
            distance_m: distance,
            measure,
        });
    }
    let mean = |f: fn(&CoverageMeasure) -> f64| {
        rows.iter().map(|r| f(&r.measure)).sum::<f64>() / rows.len().max(1) as f64
    };
    println!(
        "mean SSIM against the reference: {:.4} with whole-pixel lines, {:.4} with coverage",
        mean(|m| m.ssim_pixel),
        mean(|m| m.ssim_width)
    );
    if let Some(path) = &args.json {
        let report = CoverageReport {
            adapter,
            width,
            height,
            factor: args.factor,
            rows: &rows,
        };
        write_json(path, &serde_json::to_value(&report)?)?;
    }
    Ok(())
}
