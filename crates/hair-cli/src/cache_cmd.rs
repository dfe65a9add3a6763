//! `hairlod simulate SCENE --cache DIR` (a shot simulated into a per-frame cache, whole or in
//! chained chunks) and `hairlod render SCENE --from-cache DIR` (any range of its frames drawn
//! from the cache without simulating, bit-identical to the frames `hairlod render SCENE` makes
//! in one process). See docs/farm.md.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use hairlod::cache::{CachedRun, Chunk, SimulationCache, run_fingerprint, simulate};
use hairlod::crowd::{Crowd, CrowdModel, CrowdRenderer};
use hairlod::pipeline::{CharacterModel, Checkpoint, DrawStyle, PipelineRenderer};
use hairlod::render::RendererOptions;
use hairlod::run::{FrameLoop, ModeRun, Runnable, View, run_frames};
use hairlod::shot::Shot;

use crate::cli_args::{FramesArg, RunFlags};
use crate::destinations::writable_file;
use crate::frame_writer::FrameWriter;
use crate::report::{progress_bar, write_json};

/// Arguments of `hairlod simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Scene file (TOML, see scenes/example.toml; the built-in default scene without one). Give
    /// `hairlod render --from-cache` the same scene and flags: the cache is fingerprinted
    /// against them.
    #[arg(value_name = "SCENE.toml")]
    scene: Option<PathBuf>,
    /// The cache folder (created if missing): one record per frame, frame_00012.hlc, …, and the
    /// checkpoint at the end of the frames simulated, checkpoint_00015.json, …
    #[arg(long, value_name = "DIR")]
    cache: PathBuf,
    /// Simulate chunk K of N of the shot's frames (from 1; the chunks are as even as whole
    /// frames allow). Chunk K > 1 resumes from the checkpoint chunk K − 1 left in the cache.
    #[arg(long, value_name = "K/N")]
    chunk: Option<Chunk>,
    /// Frames: a count N (the shot is N frames long), or a range A..B or A.. of the scene's
    /// frames (A > 0 resumes from the cache's checkpoint at A).
    #[arg(long, value_name = "N|A..B", value_parser = FramesArg::parse)]
    frames: Option<FramesArg>,
    /// The flags that shape the run (the same as `hairlod render`'s).
    #[command(flatten)]
    run: RunFlags,
    /// Write every frame's report (levels, model size, stage times) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
}

/// Runs `hairlod simulate`.
pub fn run(args: &SimulateArgs) -> Result<()> {
    let file = args.run.scene_file(args.scene.as_deref(), args.frames)?;
    let mut shot = file
        .resolve()
        .context("the scene with the command-line flags")?;
    let frames = frames_of(&shot, args.chunk, args.frames)?;
    if let Some(path) = &args.json {
        writable_file(path, "JSON report")?;
    }
    let started = Instant::now();
    let report = if shot.is_crowd() {
        let model = CrowdModel::build(&shot).context("could not build the crowd's grooms")?;
        let characters: Vec<CharacterModel> = model.members.iter().map(|m| m.model()).collect();
        let cache = SimulationCache::create(&args.cache, run_fingerprint(&shot, &characters))?;
        let resume = resume_from(&cache, frames.start, args.chunk)?;
        let crowd = match resume {
            Some(checkpoint) => Crowd::resume(&model, shot.settings, checkpoint)?,
            None => Crowd::new(&model, shot.settings)?,
        };
        simulate_into(&shot, crowd, frames, &cache, started, |c| c.checkpoint())?
    } else {
        let scene = crate::scene_build::build_scene(&mut shot)?;
        let character = CharacterModel::new(Arc::new(scene.clone()), shot.environment.clone());
        let cache = SimulationCache::create(&args.cache, run_fingerprint(&shot, &[character]))?;
        let resume = resume_from(&cache, frames.start, args.chunk)?;
        let pipeline = shot.pipeline(&scene, shot.settings, resume)?;
        simulate_into(&shot, pipeline, frames, &cache, started, |p| p.checkpoint())?
    };
    if let Some(path) = &args.json {
        write_json(path, &serde_json::to_value(&report)?)?;
    }
    Ok(())
}

/// The frames a command works on: chunk K/N of the shot, a range or count, or the whole shot (a
/// count with a chunk is the shot's length, already in the scene).
fn frames_of(shot: &Shot, chunk: Option<Chunk>, frames: Option<FramesArg>) -> Result<Range<usize>> {
    match (chunk, frames) {
        (Some(chunk), Some(FramesArg::Range(..))) => {
            bail!("--chunk {chunk} and a frame range both choose the frames: give one")
        }
        (Some(chunk), _) => chunk
            .frames(shot.frames)
            .map_err(|why| anyhow::anyhow!("--chunk {chunk}: {why}")),
        (None, Some(frames)) => frames.range(shot.frames),
        (None, None) => Ok(0..shot.frames),
    }
}

/// The checkpoint a simulation starting at `start` resumes from: none at frame 0, else the one
/// the frames before left in the cache (an error names it and the chunk to run first).
fn resume_from(
    cache: &SimulationCache,
    start: usize,
    chunk: Option<Chunk>,
) -> Result<Option<Checkpoint>> {
    if start == 0 {
        return Ok(None);
    }
    let path = cache.checkpoint_path(start);
    if !path.is_file() {
        let before = match chunk {
            Some(chunk) => format!("chunk {}/{}", chunk.index - 1, chunk.count),
            None => format!("the frames before {start}"),
        };
        bail!(
            "the simulation resumes at frame {start} from {}, which is missing: simulate {before} \
             first (simulation chunks chain, each from the checkpoint of the one before)",
            path.display()
        );
    }
    Ok(Some(Checkpoint::read(&path)?))
}

/// Simulates `frames` of `shot` on `target` into `cache`, with a progress bar, then writes the
/// checkpoint at the frames' end (taken by `checkpoint`) and prints a summary.
fn simulate_into<R: Runnable + hairlod::pipeline::DrawnSource>(
    shot: &Shot,
    target: R,
    frames: Range<usize>,
    cache: &SimulationCache,
    started: Instant,
    checkpoint: impl Fn(&R) -> hairlod::pipeline::Result<Checkpoint>,
) -> Result<ModeRun> {
    let setup = started.elapsed().as_secs_f64();
    eprintln!(
        "simulating frames {}..{} of {} into {} (run {})",
        frames.start,
        frames.end,
        shot.frames,
        cache.dir().display(),
        cache.fingerprint()
    );
    let bar = progress_bar(frames.len(), shot.settings.lod.column_name());
    let mut bytes = 0u64;
    let frame_loop = FrameLoop::new(shot, target, frames.clone(), None)?;
    let result = simulate(frame_loop, cache, |frame| {
        bytes += frame.bytes;
        let [p, c, s] = frame.record.report.sections_at;
        bar.set_message(format!("{s} strand groups, {c} clusters, {p} patches"));
        bar.inc(1);
        Ok(())
    })
    .with_context(|| {
        format!(
            "the simulation stopped in frames {}..{}",
            frames.start, frames.end
        )
    })?;
    bar.finish_and_clear();
    let path = cache.checkpoint_path(frames.end);
    checkpoint(&result.pipeline)?.write(&path)?;
    let count = frames.len().max(1) as f64;
    let mean = &result.run.mean;
    eprintln!(
        "wrote {} record(s) to {} ({:.1} kB per frame) and {} (setup {setup:.2} s); per frame: \
         lod {:.1} ms, dynamics {:.1} ms, collision {:.1} ms",
        frames.len(),
        cache.dir().display(),
        bytes as f64 / count / 1e3,
        path.display(),
        1e3 * mean.lod,
        1e3 * mean.dynamics,
        1e3 * mean.collision
    );
    Ok(result.run)
}

/// What `hairlod render --from-cache` is handed by the render command.
pub struct CacheRender<'a> {
    /// The shot, with the render command's flags applied.
    pub shot: &'a Shot,
    /// The cache folder.
    pub cache: &'a Path,
    /// The output folder.
    pub out: &'a Path,
    /// Chunk K/N of the shot, or a range of its frames.
    pub chunk: Option<Chunk>,
    /// The frames, when no chunk is given.
    pub frames: Option<FramesArg>,
    /// The JSON report's path.
    pub json: Option<PathBuf>,
    /// Adapter and backend.
    pub options: RendererOptions,
    /// Shading and line coverage.
    pub style: DrawStyle,
}

/// Renders frames of a shot from its simulation cache (nothing is simulated): the scene is
/// built for its geometry, the cache opened under the shot's fingerprint, and each frame's
/// record drawn through the frame loop.
pub fn render(job: CacheRender<'_>) -> Result<()> {
    let shot = job.shot;
    if shot.outputs.hair || shot.outputs.usd {
        eprintln!(
            "note: --from-cache renders images only; the strands' cyHair and USD files \
             (output.hair, output.usd) are not in the cache and are not written"
        );
    }
    let frames = frames_of(shot, job.chunk, job.frames)?;
    let views = View::of_outputs(&shot.outputs);
    let mut writer = FrameWriter::new(
        job.out,
        &views,
        frames.clone(),
        shot.frames,
        shot.outputs.contact_sheet,
    )?;
    let started = Instant::now();
    let (run, read_seconds) = if shot.is_crowd() {
        let model = CrowdModel::build(shot).context("could not build the crowd's grooms")?;
        let characters: Vec<CharacterModel> = model.members.iter().map(|m| m.model()).collect();
        let cache = SimulationCache::open(job.cache, run_fingerprint(shot, &characters))?;
        let mut renderer = CrowdRenderer::new(&job.options, &model)?;
        renderer.set_style(job.style);
        let run = CachedRun::new(cache, &characters, shot.settings, frames.start)?;
        play(shot, &mut renderer, run, frames, &views, &mut writer)?
    } else {
        let mut framed = shot.clone();
        let scene = crate::scene_build::build_scene(&mut framed)?;
        let shot = &framed;
        let characters = [CharacterModel::new(
            Arc::new(scene.clone()),
            shot.environment.clone(),
        )];
        let cache = SimulationCache::open(job.cache, run_fingerprint(shot, &characters))?;
        let mut renderer = PipelineRenderer::new(&job.options, &scene)?;
        renderer.set_style(job.style);
        let run = CachedRun::new(cache, &characters, shot.settings, frames.start)?;
        play(shot, &mut renderer, run, frames, &views, &mut writer)?
    };
    writer.finish()?;
    if let Some(path) = &job.json {
        write_json(path, &serde_json::to_value(&run)?)?;
    }
    let count = run.frames.len().max(1) as f64;
    eprintln!(
        "wrote {} frame(s) to {} from the cache {} (setup {:.2} s); per frame: read {:.2} ms, \
         render {:.1} ms",
        run.frames.len(),
        job.out.display(),
        job.cache.display(),
        started.elapsed().as_secs_f64() - run.frames.iter().map(|f| f.times.rendering).sum::<f64>(),
        1e3 * read_seconds / count,
        1e3 * run.mean.rendering
    );
    Ok(())
}

/// The frame loop over `frames` of the cache's `run`, drawn by `renderer` in `views` and
/// written.
fn play<R: hairlod::run::FrameRenderer>(
    shot: &Shot,
    renderer: &mut R,
    run: CachedRun<R>,
    frames: Range<usize>,
    views: &[View],
    writer: &mut FrameWriter,
) -> Result<(ModeRun, f64)> {
    eprintln!(
        "rendering frames {}..{} of {} from the cache {}",
        frames.start,
        frames.end,
        shot.frames,
        run.cache_dir().display()
    );
    let bar = progress_bar(frames.len(), shot.settings.lod.column_name());
    let mut read = 0.0;
    let result = run_frames(shot, run, frames, None, Some((renderer, views)), |frame| {
        writer.write(frame.report.frame, frame.images)?;
        read = frame.pipeline.read_seconds();
        bar.inc(1);
        Ok(())
    })?;
    bar.finish_and_clear();
    Ok((result.run, read))
}
