//! `hairlod render`: run a scene (a `SCENE.toml` file, see `scenes/example.toml`, or the defaults
//! with flags) through the frame pipeline (levels of detail, dynamics with collision) and write
//! its frames as PNG image sequences: shaded, colour-coded by level, or both side by side, with
//! the head mesh drawn at its simulated pose.
//!
//! Long shots split into frame ranges: `--frames A..B --checkpoint DIR` writes the state at the
//! end of the range to `DIR/checkpoint_B.json`, and `--frames B.. --resume DIR/checkpoint_B.json`
//! goes on from it, bit for bit as if the run had never stopped. `--from-cache DIR` draws the
//! frames from a simulation cache written by `hairlod simulate` instead of simulating
//! ([`crate::cache_cmd`]), any range or `--chunk K/N` of them.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Args;
use hairlod::pipeline::{Checkpoint, DrawStyle, FrameReport, PipelineRenderer, StageTimes};
use hairlod::render::{DeviceOptions, LineShading, RendererOptions, output};
use hairlod::run::{RunOptions, View, run_shot};
use hairlod::scene_file::SceneFile;
use hairlod::shot::Shot;
use hairlod::usd_export::HairUsd;
use indicatif::{ProgressBar, ProgressStyle};

use hairlod::core::GroomPreset;
use hairlod::render::{ClusterGeometry, LineCoverage, ShadingModel};

use crate::cli_args::{BackendArg, FramesArg, RunFlags, choice};
use crate::destinations::{writable_file, writable_folder};
use crate::frame_writer::FrameWriter;

/// Arguments of `hairlod render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (TOML, version 2; every field is documented in scenes/example.toml). Flags
    /// given on the command line override it.
    #[arg(value_name = "SCENE.toml")]
    scene: Option<PathBuf>,
    /// Output folder (created if missing): frame_00000.png, … (several views: one sub-folder
    /// each, shaded/, levels/, side_by_side/).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Frames: a count N (the shot is N frames long), or a range A..B or A.. of the scene's
    /// frames (with --resume: from the checkpoint's frame).
    #[arg(long, value_name = "N|A..B", value_parser = FramesArg::parse)]
    frames: Option<FramesArg>,
    /// The flags that shape the run (the same as `hairlod simulate`'s).
    #[command(flatten)]
    run: RunFlags,
    /// Colour-code by level (strands yellow, clusters red, patches blue) instead of shading.
    #[arg(long)]
    color_code: bool,
    /// Write shaded | colour-coded pairs side by side (twice as wide).
    #[arg(long)]
    side_by_side: bool,
    /// Also write contact_sheet.png with every frame scaled down.
    #[arg(long)]
    contact_sheet: bool,
    /// Also write every strand of every frame as a cyHair file, hair/frame_00000.hair, … (the
    /// simulated strands, for Blender, Houdini or any cyHair reader) [scene: output.hair].
    #[arg(long)]
    hair: bool,
    /// Also write every strand of the run as hair.usda: one USD BasisCurves prim with a time
    /// sample per frame (time code = frame; usdview, Houdini, Blender's USD importer), and a
    /// deforming body beside it as a Mesh at its own samples, on the body file's time line
    /// (frame 0 at its first sample) [scene: output.usd]. Kept in memory until the end (12 bytes
    /// per point and frame).
    #[arg(long)]
    usd: bool,
    /// Write only the guide strands to hair.usda (implies --usd): a groom file's own strands,
    /// without the children grown around them, for a DCC tool to grow its own [scene:
    /// output.usd_strands = "guides"].
    #[arg(long)]
    usd_guides: bool,
    /// Shade 1-pixel strand lines per fragment instead of at their curve points (about 1.8× the
    /// strand render time on a CPU rasterizer; see docs/render.md).
    #[arg(long)]
    per_fragment_lines: bool,
    /// The hair's reflectance model (see docs/render.md, "Shading") [scene: output.shading;
    /// default kajiya-kay].
    #[arg(long, value_parser = choice::<ShadingModel>())]
    shading: Option<ShadingModel>,
    /// How much of a pixel a strand drawn as a 1-pixel line covers: the whole pixel, or its
    /// fibre's projected width's share (sub-pixel coverage, see docs/render.md) [scene:
    /// output.line_coverage; default pixel].
    #[arg(long, value_parser = choice::<LineCoverage>())]
    line_coverage: Option<LineCoverage>,
    /// How cluster tubes are drawn: their view-facing silhouette shaded as the tube (a fraction
    /// of the triangles), or tessellated around (see docs/render.md) [scene: output.clusters;
    /// default impostor].
    #[arg(long, value_parser = choice::<ClusterGeometry>())]
    clusters: Option<ClusterGeometry>,
    /// Graphics backend [default: $HAIRLOD_BACKEND, else auto].
    #[arg(long, value_enum)]
    backend: Option<BackendArg>,
    /// Write the state at the end of the frames to DIR/checkpoint_<frame>.json.
    #[arg(long, value_name = "DIR")]
    checkpoint: Option<PathBuf>,
    /// Start from a checkpoint written by --checkpoint (same scene and flags).
    #[arg(long, value_name = "FILE")]
    resume: Option<PathBuf>,
    /// Write every frame's report (levels, model size, stage times) as JSON to FILE [scene:
    /// output.json, in the output folder].
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Draw the frames from the simulation cache in DIR (written by `hairlod simulate` with the
    /// same scene and flags) instead of simulating them.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["checkpoint", "resume"])]
    from_cache: Option<PathBuf>,
    /// With --from-cache: draw chunk K of N of the shot's frames (from 1; as even as whole
    /// frames allow).
    #[arg(long, value_name = "K/N", requires = "from_cache")]
    chunk: Option<hairlod::cache::Chunk>,
}

impl RenderArgs {
    /// The shot's draw style (shading and line coverage from the scene and the flags), with
    /// lines shaded per fragment when asked.
    fn style(&self, shot: &hairlod::shot::Shot) -> DrawStyle {
        let mut style = shot.outputs.style();
        if self.per_fragment_lines {
            style.line_shading = LineShading::PerFragment;
        }
        style
    }

    /// The scene file with the flags applied over it.
    fn scene_file(&self) -> Result<SceneFile> {
        let mut file = self.run.scene_file(self.scene.as_deref(), self.frames)?;
        if self.color_code {
            file.output.color_coded = Some(true);
            file.output.shaded.get_or_insert(false);
        }
        if self.side_by_side {
            file.output.side_by_side = Some(true);
            file.output.shaded.get_or_insert(false);
        }
        if self.contact_sheet {
            file.output.contact_sheet = Some(true);
        }
        if self.hair {
            file.output.hair = Some(true);
        }
        if self.usd {
            file.output.usd = Some(true);
        }
        if self.usd_guides {
            file.output.usd_strands = Some(hairlod::usd_export::UsdStrands::Guides);
        }
        if let Some(shading) = self.shading {
            file.output.shading = Some(shading);
        }
        if let Some(coverage) = self.line_coverage {
            file.output.line_coverage = Some(coverage);
        }
        if let Some(clusters) = self.clusters {
            file.output.clusters = Some(clusters);
        }
        // Flags are checked like the file's own values.
        file.resolve()
            .context("the scene with the command-line flags")?;
        Ok(file)
    }
}

/// Points per skeleton segment along each exported strand (`--hair`): the B-spline at its
/// skeleton's resolution, enough to follow a curl's turn.
const HAIR_SAMPLES_PER_SEGMENT: usize = 2;

/// The error of writing an export file: `writing PATH: why`, the path named once (the writers'
/// own errors name it already, [`hairlod::HairError::io`]).
fn writing(path: &Path, error: std::io::Error) -> hairlod::HairError {
    hairlod::HairError::io("writing", path, &error)
}

/// Checks every place the run will write before anything is built or simulated: the output
/// folder (and its per-view and hair folders), the JSON report, the USD file and the checkpoint
/// folder. A destination that cannot be written fails the run in its first second, naming the
/// path and the reason, instead of after the last frame.
fn check_destinations(args: &RenderArgs, shot: &Shot, json: Option<&Path>) -> Result<()> {
    writable_folder(&args.out, "output folder")?;
    if !shot.is_crowd() {
        let views = View::of_outputs(&shot.outputs);
        if views.len() > 1 {
            for view in &views {
                writable_folder(&args.out.join(view.name()), "output folder")?;
            }
        }
        if shot.outputs.hair {
            writable_folder(&args.out.join("hair"), "hair folder")?;
        }
        if shot.outputs.usd {
            writable_file(&args.out.join("hair.usda"), "USD file")?;
        }
    }
    if let Some(path) = json {
        writable_file(path, "JSON report")?;
    }
    if let Some(dir) = &args.checkpoint {
        writable_folder(dir, "checkpoint folder")?;
    }
    Ok(())
}

/// What the banner calls the groom: the file (or files) it was read from, or its preset
/// (`preset`, the scene's `groom.preset`; `paper-curly` when none is given).
fn groom_name(shot: &hairlod::Shot, preset: Option<GroomPreset>) -> String {
    match &shot.groom_file {
        Some(groom) => {
            let paths: Vec<String> = groom
                .paths
                .iter()
                .map(|path| path.display().to_string())
                .collect();
            format!("the groom file {}", paths.join(" + "))
        }
        None => format!("`{}`", preset.unwrap_or_default()),
    }
}

/// Runs `hairlod render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    let setup_start = Instant::now();
    let file = args.scene_file()?;
    let mut shot = file.resolve()?;
    let json = args
        .json
        .clone()
        .or_else(|| file.json_output().map(|name| args.out.join(name)));
    let mut device = DeviceOptions::from_env()?;
    if let Some(backend) = args.backend {
        device.backend = backend.into();
    }
    if let Some(cache) = &args.from_cache {
        if let Some(path) = &json {
            writable_file(path, "JSON report")?;
        }
        return crate::cache_cmd::render(crate::cache_cmd::CacheRender {
            shot: &shot,
            cache,
            out: &args.out,
            chunk: args.chunk,
            frames: args.frames,
            json,
            options: RendererOptions { device },
            style: args.style(&shot),
        });
    }
    let resume = match &args.resume {
        Some(path) => Some(Checkpoint::read(path)?),
        None => None,
    };
    let start = resume.as_ref().map_or(0, |c| c.state.frame);
    let frames = match args.frames {
        Some(frames) => frames.range(shot.frames)?,
        None => start..shot.frames,
    };
    check_destinations(args, &shot, json.as_deref())?;
    if shot.is_crowd() {
        let style = args.style(&shot);
        let frames = crate::crowd_cmd::CrowdFrames {
            frames,
            resume,
            checkpoint: args.checkpoint.clone(),
        };
        return crate::crowd_cmd::render(
            &shot,
            &args.out,
            json,
            &RendererOptions { device },
            style,
            frames,
        );
    }
    let scene = crate::scene_build::build_scene(&mut shot)?;
    let views = View::of_outputs(&shot.outputs);
    let mut writer = FrameWriter::new(
        &args.out,
        &views,
        frames.clone(),
        shot.frames,
        shot.outputs.contact_sheet,
    )?;
    let hair_folder = args.out.join("hair");

    let options = RunOptions {
        frames: frames.clone(),
        resume,
        ..RunOptions::whole(&shot, shot.settings)
    };
    let mut renderer = PipelineRenderer::new(&RendererOptions { device }, &scene)?;
    renderer.set_style(args.style(&shot));
    let counts = scene.groom.counts();
    eprintln!("adapter: {}", renderer.renderer().adapter_report());
    eprintln!(
        "rendering frames {}..{} of {} of {} ({} sections, {} strands) at {}x{}, {}, {}",
        frames.start,
        frames.end,
        shot.frames,
        groom_name(&shot, file.groom.preset),
        counts.sections,
        counts.strands,
        shot.width,
        shot.height,
        shot.settings.lod.column_name(),
        views
            .iter()
            .map(|v| v.name())
            .collect::<Vec<_>>()
            .join(" + "),
    );
    let setup = setup_start.elapsed();

    let progress = ProgressBar::new(frames.len() as u64);
    progress.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} frames, {elapsed} elapsed, eta {eta} {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut write_time = Duration::ZERO;
    let mut usd = shot.outputs.usd.then(|| {
        HairUsd::of_strands(
            &scene,
            &shot.environment.head,
            shot.fps,
            shot.outputs.usd_strands,
        )
    });
    let result = run_shot(
        &shot,
        &scene,
        options,
        Some((&mut renderer, &views)),
        |frame| {
            let started = Instant::now();
            let index = frame.report.frame as u64;
            writer.write(frame.report.frame, frame.images)?;
            if shot.outputs.hair || shot.outputs.usd {
                let curves = frame.pipeline.strand_curves(HAIR_SAMPLES_PER_SEGMENT)?;
                if shot.outputs.hair {
                    let path = output::frame_path(&hair_folder, index, shot.frames as u64)
                        .with_extension("hair");
                    hairlod::formats::write_hair(&path, &curves)
                        .map_err(|error| writing(&path, error))?;
                }
                if let Some(usd) = &mut usd {
                    usd.push_frame(frame.report.frame, &curves)
                        .map_err(|error| writing(&args.out.join("hair.usda"), error))?;
                }
            }
            write_time += started.elapsed();
            let [p, c, s] = frame.report.sections_at;
            progress.set_message(format!("{s} strand groups, {c} clusters, {p} patches"));
            progress.inc(1);
            Ok(())
        },
    )
    .with_context(|| format!("the run stopped in frames {}..{}", frames.start, frames.end))?;
    progress.finish_and_clear();
    writer.finish()?;
    if let Some(usd) = &mut usd {
        let path = args.out.join("hair.usda");
        usd.write(&path).map_err(|error| writing(&path, error))?;
        eprintln!(
            "wrote {} ({} of {} strands, {} frames at {} time codes per second{})",
            path.display(),
            usd.strands_written(),
            counts.strands,
            usd.frame_count(),
            usd.time_codes_per_second(),
            if usd.body_deforms() {
                ", with the deforming body"
            } else {
                ", with the head"
            }
        );
    }
    if let Some(dir) = &args.checkpoint {
        let path = dir.join(format!("checkpoint_{:05}.json", frames.end));
        result.pipeline.checkpoint()?.write(&path)?;
        eprintln!(
            "wrote {} (resume with --resume {} --frames {}..)",
            path.display(),
            path.display(),
            frames.end
        );
    }
    if let Some(path) = &json {
        crate::report::write_json(path, &serde_json::to_value(&result.run)?)?;
    }
    print_summary(&args.out, &result.run.frames, setup, write_time);
    Ok(())
}

/// Prints where the frames went and the time per stage.
fn print_summary(out: &Path, frames: &[FrameReport], setup: Duration, write: Duration) {
    let mut total = StageTimes::default();
    for frame in frames {
        total.add(&frame.times);
    }
    let count = frames.len().max(1) as f64;
    let levels = frames
        .iter()
        .flat_map(|f| {
            f.sections_at
                .iter()
                .enumerate()
                .filter(|(_, n)| **n > 0)
                .map(|(k, _)| k)
        })
        .collect::<std::collections::BTreeSet<_>>()
        .len();
    eprintln!(
        "wrote {} frame(s) to {} (setup {:.2} s: groom, device, upload, settling); {levels} \
         level(s) in use",
        frames.len(),
        out.display(),
        setup.as_secs_f64()
    );
    eprintln!("  stage        total [s]   per frame [ms]");
    for (name, seconds) in [
        ("lod", total.lod),
        ("dynamics", total.dynamics),
        ("collision", total.collision),
        ("render", total.rendering),
        ("write png", write.as_secs_f64()),
    ] {
        eprintln!(
            "  {name:<10} {seconds:>10.3} {:>15.1}",
            1e3 * seconds / count
        );
    }
}
