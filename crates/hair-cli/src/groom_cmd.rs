//! `hairlod groom`: build a preset groom on the procedural head, print its counts, export OBJ
//! (in its hanging rest shape unless told otherwise).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use hairlod::core::{GroomCounts, Level};
use hairlod::formats::UpAxis;
use hairlod::formats::export::{ExportOptions, export_obj};
use hairlod::{HangSettings, RestPose, hang_groom};

use crate::cli_args::choice;
use crate::scene_args::SceneArgs;
use serde::Serialize;

/// Arguments of `hairlod groom`.
#[derive(Debug, Args)]
pub struct GroomArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Print the counts as JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Level to export: strands, clusters or patches.
    #[arg(long, default_value = "strands")]
    level: String,
    /// Write the head and the chosen level as Wavefront OBJ to this file.
    #[arg(long, value_name = "FILE.obj")]
    export: Option<PathBuf>,
    /// Curve samples per skeleton segment in the export (strands as polylines, surfaces along the
    /// hair).
    #[arg(long, default_value_t = 4)]
    samples_per_segment: usize,
    /// The rest shape the export shows: hanging (fallen onto the head and at rest there, as runs
    /// start) or grown (the generated shape); loaded is for groom files.
    #[arg(long, default_value = "hanging", value_parser = choice::<RestPose>())]
    rest_pose: RestPose,
    /// A groom file to fit the paper's hierarchy to instead of a preset (.tfx, .hair, .data,
    /// .obj, .usda, .usdc, .usd, .abc): prints the fitted counts and each level's fit error, and how
    /// far the strands a scene would draw lie from the file at rest. To run a groom
    /// file, name it in a scene's `[groom] file` (docs/grooms.md).
    #[arg(long, value_name = "FILE")]
    file: Option<PathBuf>,
    /// With --file: metres per file unit (0.01 for centimetres).
    #[arg(long, value_name = "M", default_value_t = 1.0)]
    scale: f32,
    /// With --file: the file's up axis.
    #[arg(long, default_value = "y", value_parser = choice::<UpAxis>())]
    up: UpAxis,
    /// With --file: sections to fit [default: one per 50 strands].
    #[arg(long, value_name = "N")]
    fit_sections: Option<usize>,
}

#[derive(Serialize)]
struct GroomReport<'a> {
    preset: &'a str,
    style: &'a str,
    hair_length_m: f32,
    section_width_m: f32,
    #[serde(flatten)]
    counts: GroomCounts,
}

/// Runs `hairlod groom`.
pub fn run(args: &GroomArgs) -> Result<()> {
    if let Some(file) = &args.file {
        return fit_file(args, file);
    }
    if args.rest_pose == RestPose::Loaded {
        anyhow::bail!(
            "--rest-pose loaded: a preset groom has no loaded shape (use hanging or grown, or \
             give --file)"
        );
    }
    let level: Level = args.level.parse()?;
    let mut scene = args.scene.build()?;
    let counts = scene.groom.counts();
    let report = GroomReport {
        preset: args.scene.preset.name(),
        style: scene.groom.params.style.kind.name(),
        hair_length_m: scene.groom.params.hair_length,
        section_width_m: scene.groom.sections.first().map_or(0.0, |s| s.width),
        counts,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_table(&report);
    }
    if let Some(path) = &args.export {
        if args.rest_pose == RestPose::Hanging {
            let hang = hang_groom(&mut scene, &HangSettings::default())
                .context("could not hang the groom")?;
            eprintln!(
                "hung the groom in {:.1} s: its skeleton nodes moved {:.1} mm on average \
                 ({:.0} mm at most) from the grown shape",
                hang.wall_seconds,
                hang.mean_move * 1e3,
                hang.max_move * 1e3
            );
        }
        let options = ExportOptions {
            level,
            samples_per_segment: args.samples_per_segment,
            ..ExportOptions::default()
        };
        let summary = export_obj(path, &scene, &options)
            .with_context(|| format!("could not export {}", path.display()))?;
        eprintln!(
            "wrote {} ({} {}: {} vertices, {} triangles, {} polylines)",
            path.display(),
            summary.items,
            level,
            summary.vertices,
            summary.triangles,
            summary.polylines
        );
    }
    Ok(())
}

fn print_table(report: &GroomReport) {
    let c = &report.counts;
    println!(
        "groom `{}`: {} hair, {:.3} m long, sections {:.1} mm wide, {} nodes per skeleton",
        report.preset,
        report.style,
        report.hair_length_m,
        report.section_width_m * 1000.0,
        c.nodes_per_skeleton
    );
    println!("  sections        {:>8}", c.sections);
    println!(
        "  patches         {:>8}   ({} skeleton nodes)",
        c.patches, c.patch_nodes
    );
    println!(
        "  clusters        {:>8}   ({} skeleton nodes)",
        c.clusters, c.cluster_nodes
    );
    println!(
        "  strand groups   {:>8}   ({} skeleton nodes)",
        c.strand_groups, c.strand_group_nodes
    );
    println!("  strands         {:>8}", c.strands);
    println!("  skeleton nodes  {:>8}   (all levels)", c.skeleton_nodes);
}

/// `hairlod groom --file F`: reads the curves, fits the hierarchy, prints counts and errors.
fn fit_file(args: &GroomArgs, file: &std::path::Path) -> Result<()> {
    use hairlod::core::fit::{FitSettings, SectionCount, fit_hierarchy};
    use hairlod::formats::{ImportAxes, ImportOptions, read_curves_file};
    let options = ImportOptions {
        axes: ImportAxes {
            scale_to_metres: args.scale,
            up: args.up,
            ..ImportAxes::default()
        },
        ..ImportOptions::default()
    };
    let started = std::time::Instant::now();
    let curves = read_curves_file(file, &options)?;
    let read_seconds = started.elapsed().as_secs_f64();
    let mut settings = FitSettings::default();
    if let Some(sections) = args.fit_sections {
        settings.sections = SectionCount::Fixed(sections);
    }
    let started = std::time::Instant::now();
    let fit = fit_hierarchy(&curves, &settings)
        .with_context(|| format!("could not fit {}", file.display()))?;
    let fit_seconds = started.elapsed().as_secs_f64();
    if !curves.skipped.is_empty() {
        eprintln!(
            "skipped {} degenerate curves of {} (the first: curve {}, {})",
            curves.skipped.len(),
            file.display(),
            curves.skipped[0].index,
            curves.skipped[0].reason
        );
    }
    // The fit report is printed either way; a groom a scene could not build is an error after it.
    let built = drawn_rest_errors(args, file);
    let rest_pose = built.as_ref().ok();
    if args.json {
        let json = serde_json::json!({
            "file": file.display().to_string(),
            "read_seconds": read_seconds,
            "fit_seconds": fit_seconds,
            "skipped_curves": curves.skipped.len(),
            "fit": fit.report,
            "rest_pose": rest_pose,
            "rest_pose_error": built.as_ref().err().map(|error| format!("{error:#}")),
        });
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        println!(
            "{}: read in {read_seconds:.3} s, fitted in {fit_seconds:.3} s",
            file.display()
        );
        println!("{}", fit.report);
        if let Some(errors) = rest_pose {
            println!(
                "as a scene loads it (one node count for the groom, residual profiles bound), \
                 rest pose against the file:"
            );
            println!("  strands as drawn      {}", errors.drawn_strands);
            for (level, model) in [
                (Level::Patch, "patch model"),
                (Level::Cluster, "cluster model"),
                (Level::StrandGroup, "strand-group model"),
            ] {
                println!("  {model:18}    {}", errors.levels[level]);
            }
        }
    }
    built.map(|_| ()).with_context(|| {
        format!(
            "{} was fitted (above), but a scene's `[groom] file` could not use it at --scale {} \
             (a scene's groom.scale; --fit-sections is its groom.section_count)",
            file.display(),
            args.scale
        )
    })
}

/// The rest errors of the groom a scene's `[groom] file` builds from `file` (the scene's fit
/// settings with these axes and sections, the default preset's material, residual profiles
/// bound, before it is hung): how far the strands as drawn, and each level's model, lie from
/// the file's curves.
fn drawn_rest_errors(
    args: &GroomArgs,
    file: &std::path::Path,
) -> Result<hairlod::loaded::LevelRestErrors> {
    use hairlod::core::fit::SectionCount;
    use hairlod::loaded::{FileAxes, GroomFile, load_scene, rest_errors};
    let mut groom_file = GroomFile::new(vec![file.to_path_buf()]);
    groom_file.axes = FileAxes {
        scale_to_metres: args.scale,
        z_up: args.up == UpAxis::Z,
        mirror_x: false,
    };
    if let Some(sections) = args.fit_sections {
        groom_file.sections = SectionCount::Fixed(sections);
    }
    let loaded = load_scene(&groom_file, None, &hairlod::GroomParams::paper_curly())?;
    Ok(rest_errors(
        &loaded.scene.groom,
        &loaded.fit,
        &loaded.curves,
    )?)
}
