//! The `hairlod` command-line tool: grooms, OBJ export (and, as they land, simulation, rendering and
//! benchmarks).

mod groom_cmd;
mod scene_args;
mod stability_cmd;

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
    /// Sweep the three skeleton integrators over time step, stiffness, wind and head shake and
    /// report where each is stable.
    Stability(stability_cmd::StabilityArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Groom(args) => groom_cmd::run(&args),
        Command::Stability(args) => stability_cmd::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
