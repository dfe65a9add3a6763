//! `hairlod accuracy`: speed against accuracy (issue 7). Runs the reference (every section at
//! strand level, linear-implicit at 1/6000 s: `hairlod::accuracy::reference_settings`) and a
//! sweep of configurations over the paper benchmark's camera path and control inputs: the fixed
//! levels (Strands, Clusters, Patches at the default integrator), LODs at several pixel
//! tolerances, and strands under each integrator at several steps. For each it prints the median
//! cost per frame against its error (mean SSIM loss and mean screen-space pixel error against the
//! reference, frame by frame), marks the Pareto fronts, and can chart them (`--chart`). The
//! configurations run interleaved frame by frame (`configuration_run`), so that every frame's
//! costs are measured under the same machine load.
//!
//! A configuration whose integrator fails (an unstable step, detected by the dynamics) is
//! reported as failed with the error, and the sweep goes on.

mod configuration_run;
mod sweep;

use configuration_run::{ConfigurationRun, ReferenceFrame};

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use hairlod::Level;
use hairlod::accuracy::reference_settings;
use hairlod::benchmark::{paper_shot, resized};
use hairlod::core::dynamics::{IntegratorKind, SimulationSettings};
use hairlod::core::lod::{ErrorModel, OcclusionTest};
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::RendererOptions;
use hairlod::shot::Shot;

use crate::charts::{ACCURACY_PANELS, GROUP_COLOURS, ParetoChart, write_png_and_svg};
use crate::cli_args::choice;
use crate::report::{progress_bar, thinning_label, write_json};
use hairlod::core::GroomPreset;
use sweep::{Group, Point, mark_pareto};

/// The integrator sweep: each integrator at a coarser and a finer step around its recommended
/// substeps per 60 Hz frame (16, 4, 4, 8), linear-implicit (the default until 2026-11-28) at its
/// own, and XPBD fixed at 8 and at 16 (the default until 2026-12-06). XPBD ×8–32 adaptive, the
/// default, is the `Strands` point itself.
const INTEGRATOR_SWEEP: [(IntegratorKind, u32); 12] = [
    (IntegratorKind::SemiImplicitEuler, 4),
    (IntegratorKind::SemiImplicitEuler, 16),
    (IntegratorKind::SemiImplicitEuler, 64),
    (IntegratorKind::PositionBased, 1),
    (IntegratorKind::PositionBased, 16),
    (IntegratorKind::LinearImplicit, 1),
    (IntegratorKind::LinearImplicit, 4),
    (IntegratorKind::LinearImplicit, 16),
    (IntegratorKind::Xpbd, 2),
    (IntegratorKind::Xpbd, 8),
    (IntegratorKind::Xpbd, 16),
    (IntegratorKind::Xpbd, 32),
];

/// The dynamics of the levels: `--substeps` fixed, else the integrator's recommended settings.
fn levels_dynamics(args: &AccuracyArgs) -> SimulationSettings {
    match args.substeps {
        Some(substeps) => SimulationSettings::new(args.integrator, 1.0 / 60.0, substeps),
        None => SimulationSettings::recommended(args.integrator),
    }
}

/// The accuracy target: the mean SSIM a cheap configuration must keep.
const TARGET_SSIM: f64 = 0.95;

/// Arguments of `hairlod accuracy`.
#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// Groom preset.
    #[arg(long, default_value = "paper-curly", value_parser = choice::<GroomPreset>())]
    pub preset: GroomPreset,
    /// Blow the benchmark's gusting wind.
    #[arg(long)]
    pub wind: bool,
    /// Frames per configuration (the benchmark's zoom-out path over that many frames).
    #[arg(long, default_value_t = 40)]
    pub frames: usize,
    /// Image size WIDTHxHEIGHT [pixels].
    #[arg(long, default_value = "640x360", value_parser = crate::cli_args::size)]
    pub size: (u32, u32),
    /// LOD pixel tolerances to sweep [pixels], comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "0.5,1,2,4,8,16")]
    pub tolerances: Vec<f32>,
    /// How the LODs estimate a level's error: `deviation` (measured per section, the default),
    /// `chord` (the paper's rule), comma-separated to run the LODs with each.
    #[arg(long, value_delimiter = ',', default_value = "deviation")]
    pub error_models: Vec<ErrorModel>,
    /// How the LODs find a section hidden behind the head: `section` (all of it, the default),
    /// `ends` (the paper's root-and-tip test), comma-separated to run the LODs with each.
    #[arg(long, value_delimiter = ',', default_value = "section")]
    pub occlusion_tests: Vec<OcclusionTest>,
    /// How far ahead the LODs' level choice looks, as fractions of the blend time in 0..=1,
    /// comma-separated to run the LODs with each (default: the library's, 0.5; 0: the current
    /// frame only).
    #[arg(long, value_delimiter = ',', value_name = "FRACTIONS")]
    pub blend_leads: Vec<f32>,
    /// Strand thinning of the LODs: strands drawn per pixel of a strand group's screen width,
    /// comma-separated to run the LODs with each (0: every strand).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0",
        value_name = "STRANDS"
    )]
    pub strands_per_pixel: Vec<f32>,
    /// Integrator of the fixed levels and the LODs (the integrator sweep tries the others).
    #[arg(long, default_value_t = IntegratorKind::DEFAULT)]
    pub integrator: IntegratorKind,
    /// Substeps per 60 Hz frame of that integrator, fixed (default: the integrator's recommended
    /// settings, XPBD's adaptive substeps included).
    #[arg(long)]
    pub substeps: Option<u32>,
    /// Leave out the integrator sweep (each integrator at several steps, at strand level).
    #[arg(long)]
    pub no_integrators: bool,
    /// Write every point (and every frame's errors) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Chart error against cost with the Pareto fronts to FILE.png and FILE.svg.
    #[arg(long, value_name = "FILE")]
    pub chart: Option<PathBuf>,
    /// Measure a crowd scene instead (for example scenes/crowd.toml): the fixed levels and the
    /// LODs at each of --tolerances (and of --strands-per-pixel) against the crowd's
    /// all-strands frames.
    #[arg(long, value_name = "SCENE.toml")]
    pub crowd: Option<PathBuf>,
}

/// One configuration to run.
pub(crate) struct Configuration {
    label: String,
    group: Group,
    settings: PipelineSettings,
}

/// The sweep's configurations, the reference first.
fn configurations(args: &AccuracyArgs, shot: &Shot) -> Result<Vec<Configuration>> {
    let dynamics = levels_dynamics(args);
    dynamics.validate()?;
    let fixed = |label: &str, level: Level| Configuration {
        label: label.to_string(),
        group: Group::FixedLevel,
        settings: PipelineSettings {
            lod: LodMode::Fixed(level),
            dynamics,
            ..PipelineSettings::default()
        },
    };
    let mut list = vec![
        Configuration {
            label: "Reference".into(),
            group: Group::Reference,
            settings: reference_settings(),
        },
        fixed("Strands", Level::StrandGroup),
        fixed("Clusters", Level::Cluster),
        fixed("Patches", Level::Patch),
    ];
    let default_lead = shot.lod_settings().blend_lead;
    let leads = if args.blend_leads.is_empty() {
        vec![default_lead]
    } else {
        args.blend_leads.clone()
    };
    for ((((&tolerance, &error_model), &blend_lead), &occlusion_test), &strands_per_pixel) in args
        .tolerances
        .iter()
        .flat_map(|t| args.error_models.iter().map(move |m| (t, m)))
        .flat_map(|pair| leads.iter().map(move |lead| (pair, lead)))
        .flat_map(|triple| args.occlusion_tests.iter().map(move |o| (triple, o)))
        .flat_map(|four| args.strands_per_pixel.iter().map(move |k| (four, k)))
    {
        let lod = hairlod::core::lod::LodSettings {
            pixel_tolerance: tolerance,
            error_model,
            blend_lead,
            occlusion_test,
            strands_per_pixel,
            ..shot.lod_settings()
        };
        lod.validate()?;
        let mut model = match error_model {
            ErrorModel::Deviation => String::new(),
            other => format!(" ({other})"),
        };
        if occlusion_test != OcclusionTest::default() {
            model.push_str(&format!(" ({occlusion_test} occlusion)"));
        }
        model.push_str(&thinning_label(&lod));
        let lead = if blend_lead == default_lead {
            String::new()
        } else {
            format!(" lead {blend_lead}")
        };
        list.push(Configuration {
            label: format!("LODs{model}{lead} {tolerance}px"),
            group: Group::Lods,
            settings: PipelineSettings {
                lod: LodMode::Auto(lod),
                dynamics,
                ..PipelineSettings::default()
            },
        });
    }
    if !args.no_integrators {
        // The Strands point already runs the levels' own integrator and substeps.
        let own = args.substeps.map(|substeps| (args.integrator, substeps));
        for (integrator, substeps) in INTEGRATOR_SWEEP
            .into_iter()
            .filter(|&pair| Some(pair) != own)
        {
            list.push(Configuration {
                label: format!("{integrator} ×{substeps}"),
                group: Group::Integrator,
                settings: PipelineSettings {
                    lod: LodMode::Fixed(Level::StrandGroup),
                    dynamics: SimulationSettings::new(integrator, 1.0 / 60.0, substeps),
                    ..PipelineSettings::default()
                },
            });
        }
    }
    Ok(list)
}

/// Runs `hairlod accuracy`.
pub fn run(args: &AccuracyArgs) -> Result<()> {
    if let Some(path) = &args.crowd {
        let shot = hairlod::scene_file::SceneFile::read(path)?.resolve()?;
        anyhow::ensure!(
            shot.is_crowd(),
            "{}: not a crowd (it has no [[character]] tables)",
            path.display()
        );
        return crate::crowd_cmd::accuracy(
            &shot,
            &args.tolerances,
            &args.strands_per_pixel,
            args.json.as_deref(),
        );
    }
    anyhow::ensure!(
        args.frames >= 2,
        "--frames must be at least 2 (got {})",
        args.frames
    );
    let (width, height) = args.size;
    let mut shot = resized(&paper_shot(args.wind), args.frames, width, height);
    shot.groom = args.preset.into();
    let scene = shot.build_scene()?;
    let configurations = configurations(args, &shot)?;
    let mut renderer = PipelineRenderer::new(&RendererOptions::from_env()?, &scene)?;
    renderer.warm_up(&scene)?;
    println!(
        "rendering on {}; {} configurations × {} frames at {width}x{height} of {}",
        renderer.renderer().adapter_report(),
        configurations.len(),
        args.frames,
        args.preset.name()
    );
    // Every configuration makes frame k before any makes k + 1 (the reference first, so that
    // each frame has its yardstick), on one renderer: on a shared machine, configurations run
    // one after another can differ by several times in cost for load alone; interleaved, each
    // frame's costs are measured in the same stretch of time. Each run's frames are its own (bit
    // for bit what it makes alone, `tests/frame_loop.rs`).
    let mut runs = Vec::with_capacity(configurations.len());
    for configuration in configurations {
        let label = configuration.label.clone();
        runs.push(
            ConfigurationRun::start(configuration, &shot, &scene, &mut renderer)
                .with_context(|| format!("starting {label}"))?,
        );
    }
    let mut reference: Vec<ReferenceFrame> = Vec::with_capacity(args.frames);
    let bar = progress_bar(
        args.frames * runs.len(),
        "every configuration, frame by frame",
    );
    for frame in 0..shot.frames {
        for run in &mut runs {
            let label = run.label.clone();
            run.step(&mut renderer, &mut reference, (width, height))
                .with_context(|| format!("running {label} at frame {frame}"))?;
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let mut points: Vec<Point> = runs.into_iter().map(ConfigurationRun::point).collect();
    for point in &points {
        print_point(point);
    }
    mark_pareto(&mut points);
    print_fronts(&points);
    if let Some(path) = &args.json {
        let report = serde_json::json!({
            "preset": args.preset.name(),
            "frames": args.frames,
            "width": width,
            "height": height,
            "wind": args.wind,
            "reference": "Reference",
            "reference_settings": reference_settings().dynamics,
            "levels_integrator": args.integrator.name(),
            "levels_substeps": levels_dynamics(args).substeps,
            "levels_max_substeps": levels_dynamics(args).max_substeps(),
            "points": points,
        });
        write_json(path, &report)?;
    }
    if let Some(path) = &args.chart {
        let scatter: Vec<_> = points
            .iter()
            .filter(|p| p.failed.is_none() && p.label != "Reference")
            .map(Point::scatter)
            .collect();
        let chart = ParetoChart {
            panel_names: ACCURACY_PANELS,
            group_colours: &GROUP_COLOURS,
            title: format!(
                "Error against cost, {} ({}), {} frames at {width}x{height}; levels and LODs \
                 with {} {}: fixed levels (blue), LODs (red), strands with other integrators \
                 (green)",
                args.preset.name(),
                if args.wind { "wind" } else { "calm" },
                args.frames,
                args.integrator,
                levels_dynamics(args).substeps_label()
            ),
            points: &scatter,
        };
        let (png, svg) = write_png_and_svg(path, (1400, 620), &chart)?;
        println!("wrote {} and {}", png.display(), svg.display());
    }
    Ok(())
}

fn print_point(point: &Point) {
    match &point.failed {
        Some(reason) => println!("{:>26}: failed: {reason}", point.label),
        None => println!(
            "{:>26}: {:8.2} ms/frame  SSIM {:.4}  pixel error {:.2} (p95 {:.2})  length error \
             {:.1e}  penetration {:.2} mm (roots {:.2} mm)",
            point.label,
            1e3 * point.median_cost,
            1.0 - point.ssim_loss,
            point.mean_pixel_error,
            point.mean_p95_pixel_error,
            point.physical.segment_length,
            1e3 * point.physical.penetration,
            1e3 * point.physical.root_penetration
        ),
    }
}

/// Prints both fronts and the cheapest configuration that keeps the target SSIM, with its
/// speedup over Strands.
fn print_fronts(points: &[Point]) {
    for (name, on_front) in [
        (
            "SSIM loss",
            (|p: &Point| p.pareto_ssim) as fn(&Point) -> bool,
        ),
        ("mean pixel error", |p: &Point| p.pareto_pixels),
    ] {
        let mut front: Vec<&Point> = points.iter().filter(|p| on_front(p)).collect();
        front.sort_by(|a, b| a.median_cost.total_cmp(&b.median_cost));
        println!("\nPareto front, median cost against {name}:");
        for point in front {
            println!(
                "{:>26}: {:8.2} ms/frame  SSIM {:.4}  pixel error {:.2}",
                point.label,
                1e3 * point.median_cost,
                1.0 - point.ssim_loss,
                point.mean_pixel_error
            );
        }
    }
    let strands = points.iter().find(|p| p.label == "Strands");
    let cheapest = points
        .iter()
        .filter(|p| p.group == Group::Lods && p.pareto_ssim && 1.0 - p.ssim_loss >= TARGET_SSIM)
        .min_by(|a, b| a.median_cost.total_cmp(&b.median_cost));
    if let (Some(strands), Some(lods)) = (strands, cheapest) {
        println!(
            "\ncheapest LODs on the SSIM front with mean SSIM >= {TARGET_SSIM}: {} at {:.2} ms, \
             {:.1}x cheaper than Strands ({:.2} ms), SSIM {:.4}",
            lods.label,
            1e3 * lods.median_cost,
            strands.median_cost / lods.median_cost.max(1e-12),
            1e3 * strands.median_cost,
            1.0 - lods.ssim_loss
        );
    } else {
        println!("\nno LODs configuration on the SSIM front keeps a mean SSIM of {TARGET_SSIM}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: AccuracyArgs,
    }

    fn lod_configurations(flags: &[&str]) -> Result<Vec<(String, f32, f32)>> {
        let cli = Cli::try_parse_from(["accuracy", "--no-integrators"].iter().chain(flags))?;
        let shot = paper_shot(false);
        Ok(configurations(&cli.args, &shot)?
            .into_iter()
            .filter_map(|c| match (c.group, c.settings.lod) {
                (Group::Lods, LodMode::Auto(lod)) => {
                    Some((c.label, lod.pixel_tolerance, lod.blend_lead))
                }
                _ => None,
            })
            .collect())
    }

    #[test]
    fn each_blend_lead_runs_every_tolerance() {
        let default_lead = paper_shot(false).lod_settings().blend_lead;
        assert_eq!(
            lod_configurations(&["--tolerances", "1,2"]).unwrap(),
            vec![
                ("LODs 1px".to_string(), 1.0, default_lead),
                ("LODs 2px".to_string(), 2.0, default_lead),
            ]
        );
        let swept = lod_configurations(&["--tolerances", "1,2", "--blend-leads", "0,0.5"]).unwrap();
        let expected = [
            ("LODs lead 0 1px", 1.0, 0.0),
            ("LODs 1px", 1.0, 0.5),
            ("LODs lead 0 2px", 2.0, 0.0),
            ("LODs 2px", 2.0, 0.5),
        ];
        assert_eq!(
            default_lead, 0.5,
            "the labels below assume the default lead"
        );
        assert_eq!(swept.len(), expected.len());
        for ((label, tolerance, lead), (want_label, want_tolerance, want_lead)) in
            swept.iter().zip(expected)
        {
            assert_eq!(
                (label.as_str(), *tolerance, *lead),
                (want_label, want_tolerance, want_lead)
            );
        }
    }

    #[test]
    fn a_blend_lead_out_of_range_is_refused_by_name() {
        let error = lod_configurations(&["--blend-leads", "1.5"]).unwrap_err();
        assert!(format!("{error:#}").contains("lead"), "{error:#}");
    }
}
