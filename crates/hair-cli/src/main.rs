//! The `hairlod` command-line tool: every verb that makes frames runs a scene through the one frame
//! loop (`hairlod::run`): `render` (image sequences, checkpoints, frames from a cache),
//! `simulate` (a per-frame cache), `farm` (OpenJD job templates), `bench` (a scene in every mode,
//! the paper's tables), `demo` (the main job), `accuracy` (speed against accuracy); and `groom`
//! (counts, OBJ export) and `stability` (where each integrator holds); `view` opens a window on
//! the same frame loop.

mod accuracy_cmd;
mod bench_cmd;
mod bench_costs;
mod bench_coverage;
mod bench_shading;
mod cache_cmd;
mod charts;
mod cli_args;
mod crowd_cmd;
mod demo_cmd;
mod destinations;
mod farm_cmd;
mod frame_writer;
mod groom_cmd;
mod pareto;
mod render_cmd;
mod report;
mod scene_args;
mod scene_build;
mod stability_cmd;
mod view_cmd;
mod viewer;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// hairlod: hair simulation with automatic levels of detail.
#[derive(Debug, Parser)]
#[command(name = "hairlod", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Build a groom from a preset, print its counts, optionally export one level as OBJ.
    Groom(groom_cmd::GroomArgs),
    /// Sweep the four skeleton integrators over time step, stiffness, wind and head shake, report
    /// where each is stable, and how many substeps each needs at 60 Hz and at what cost.
    Stability(stability_cmd::StabilityArgs),
    /// Run a scene (SCENE.toml or flags) with levels of detail, dynamics and collision, and
    /// write its frames as PNG sequences: shaded, colour-coded by level, or side by side.
    Render(render_cmd::RenderArgs),
    /// Simulate a scene into a per-frame cache (whole, or chunk K/N resuming from the chunk
    /// before), for `render --from-cache` to draw on any machine. See docs/farm.md.
    Simulate(cache_cmd::SimulateArgs),
    /// Write an Open Job Description job template that simulates a scene in chained chunks and
    /// renders its frames in parallel chunks from the cache (`openjd run`, Deadline Cloud). See
    /// docs/farm.md.
    Farm(farm_cmd::FarmArgs),
    /// Benchmarks: `bench SCENE` runs a scene in LODs and each fixed level in the paper's table
    /// layout, `bench paper` the paper's Tables 1 and 2, `bench shading` the strand-line
    /// shading's cost against its error.
    Bench(bench_cmd::BenchArgs),
    /// The main job: the benchmark scene with wind and LODs rendered to ./out (shaded and
    /// colour-coded), then the Table 2 comparison.
    Demo(demo_cmd::DemoArgs),
    /// Speed against accuracy: fixed levels and LODs against the strand-level reference.
    Accuracy(accuracy_cmd::AccuracyArgs),
    /// Open a window on a scene running through the pipeline: orbit, pan and zoom with the
    /// mouse; pause, step, force a level, colour-code, tune the tolerance, budget, wind and head
    /// motion with keys; a HUD with stage times and counts. `--frames N --screenshot F` and
    /// `--script FILE` run it headless (under Xvfb). See docs/viewer.md.
    View(view_cmd::ViewArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Groom(args) => groom_cmd::run(&args),
        Command::Stability(args) => stability_cmd::run(&args),
        Command::Render(args) => render_cmd::run(&args),
        Command::Simulate(args) => cache_cmd::run(&args),
        Command::Farm(args) => farm_cmd::run(&args),
        Command::Bench(args) => bench_cmd::run(&args),
        Command::Demo(args) => demo_cmd::run(&args),
        Command::Accuracy(args) => accuracy_cmd::run(&args),
        Command::View(args) => view_cmd::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
