//! What the benchmark and accuracy commands share: the paper's shot as they take it on the
//! command line, progress bars, the paper's table layout, JSON reports and labels. Every command
//! imports this module; it imports none of them.

use anyhow::Result;
use clap::Args;
use hairlod::benchmark::{SimulationCosts, paper_shot, resized};
use hairlod::collide::BroadPhase;
use hairlod::pipeline::DrawnAs;
use hairlod::run::ModeRun;
use hairlod::shot::Shot;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

/// The paper's zoom-out as `bench paper` and `bench costs` take it.
#[derive(Debug, Args)]
pub struct PaperShotArgs {
    /// Blow a gusting wind (Table 2) instead of calm air (Table 1).
    #[arg(long)]
    pub wind: bool,
    /// Frames per mode (at least 2).
    #[arg(long, default_value_t = 60)]
    pub frames: usize,
    /// Image size WIDTHxHEIGHT [pixels].
    #[arg(long, default_value = "1280x720", value_parser = crate::cli_args::size)]
    pub size: (u32, u32),
    /// How collision finds the hair near the head: `field-contacts` (the library's default:
    /// contacts from the head's distance field), `hierarchies` (the paper's §5.3: exact triangle
    /// tests) or `distance-field` (the same exact tests, culled by the field).
    #[arg(long, default_value_t = BroadPhase::default())]
    pub broad_phase: BroadPhase,
    /// How the levels are drawn: `level` (each as itself, the paper's Tables) or `strands`
    /// (every level's sections as strands, on strand-group skeletons rebuilt from the level
    /// simulated).
    #[arg(long, default_value_t = DrawnAs::default())]
    pub drawn_as: DrawnAs,
}

impl PaperShotArgs {
    /// The paper's shot (calm or windy) over `frames` frames at `size`; an error names a frame
    /// count below 2.
    pub fn shot(&self) -> Result<Shot> {
        anyhow::ensure!(
            self.frames >= 2,
            "--frames must be at least 2 (got {})",
            self.frames
        );
        let (width, height) = self.size;
        let mut shot = resized(&paper_shot(self.wind), self.frames, width, height);
        shot.settings.broad_phase = self.broad_phase;
        shot.settings.drawn_as = self.drawn_as;
        Ok(shot)
    }
}

#[derive(Serialize, Clone, Copy)]
/// The LODs' speedups over Strands, stage by stage and in total [×].
pub struct Speedups {
    pub dynamics: f64,
    pub collision: f64,
    pub rendering: f64,
    pub total: f64,
}

/// A progress bar over `frames` frames labelled `label`.
pub fn progress_bar(frames: usize, label: &str) -> ProgressBar {
    let bar = ProgressBar::new(frames as u64).with_style(
        ProgressStyle::with_template("{prefix:>26} [{bar:30}] {pos}/{len} frames {elapsed} {msg}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    bar.set_prefix(label.to_string());
    bar
}

/// Prints the modes' stage times in the paper's layout (LODs first, then Strands); returns the
/// LODs' speedups over Strands.
pub fn print_table(
    title: &str,
    modes: &[ModeRun],
    paper: Option<&[[f64; 4]; 3]>,
    shot: &Shot,
) -> Speedups {
    println!();
    println!(
        "{title} ({} frames, {}x{}; seconds per frame, mean{})",
        shot.frames,
        shot.width,
        shot.height,
        if paper.is_some() {
            "; the paper's in brackets"
        } else {
            ""
        }
    );
    print!("{:<12}", "Breakdown");
    for run in modes {
        print!("{:>20}", run.mode);
    }
    println!("{:>14}", "LODs speedup");
    type Row = (&'static str, fn(&ModeRun) -> f64);
    let rows: [Row; 3] = [
        ("Dyn Sim", |r| r.mean.dynamics),
        ("Col Detect", |r| r.mean.collision),
        ("Rendering", |r| r.mean.rendering),
    ];
    let mut speedup = [0.0; 4];
    for (row, (name, value)) in rows.iter().enumerate() {
        print!("{name:<12}");
        for (column, run) in modes.iter().enumerate() {
            match paper {
                Some(paper) => print!("{:>11.4} ({:.3})", value(run), paper[row][column]),
                None => print!("{:>20.4}", value(run)),
            }
        }
        speedup[row] = value(&modes[1]) / value(&modes[0]).max(1e-12);
        println!("{:>13.2}×", speedup[row]);
    }
    print!("{:<12}", "Total");
    for (column, run) in modes.iter().enumerate() {
        let total = run.mean.dynamics + run.mean.collision + run.mean.rendering;
        match paper {
            Some(paper) => {
                let paper_total: f64 = paper.iter().map(|row| row[column]).sum();
                print!("{total:>11.4} ({paper_total:.3})");
            }
            None => print!("{total:>20.4}"),
        }
    }
    let total = |run: &ModeRun| run.mean.dynamics + run.mean.collision + run.mean.rendering;
    speedup[3] = total(&modes[1]) / total(&modes[0]).max(1e-12);
    println!("{:>13.2}×", speedup[3]);
    if let Some(paper) = paper {
        let paper_speedup =
            paper.iter().map(|r| r[1]).sum::<f64>() / paper.iter().map(|r| r[0]).sum::<f64>();
        print!("(the paper's LODs speedup in total: {paper_speedup:.2}×; ");
    } else {
        print!("(");
    }
    println!(
        "LOD level selection took {:.4} s per frame)",
        modes[0].mean.lod
    );
    Speedups {
        dynamics: speedup[0],
        collision: speedup[1],
        rendering: speedup[2],
        total: speedup[3],
    }
}

/// Writes `value` as pretty JSON to `path` through the one atomic writer (a temporary file with
/// the process id, synced, renamed into place, removed on error).
pub fn write_json(path: &std::path::Path, value: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    crate::charts::write_atomically(path, text.as_bytes())?;
    println!("wrote {}", path.display());
    Ok(())
}

/// How a LOD configuration's label names its strand thinning: ` thinned K/px` (`, widened`
/// when the drawn strands stand wider for those left out), or nothing when every strand is
/// drawn (`strands_per_pixel` 0).
pub(crate) fn thinning_label(lod: &hairlod::core::lod::LodSettings) -> String {
    match (lod.strands_per_pixel > 0.0, lod.raise_thinned_widths) {
        (false, _) => String::new(),
        (true, false) => format!(" thinned {}/px", lod.strands_per_pixel),
        (true, true) => format!(" thinned {}/px, widened", lod.strands_per_pixel),
    }
}

/// Prints each mode's simulation cost per level (means per frame): nodes, dynamics and
/// collision [ms], nanoseconds per node, and the modes' dynamics plus collision against the
/// first all-strands mode's.
pub fn print_simulation_costs(costs: &[SimulationCosts]) {
    println!(
        "simulation cost per level, mean per frame (nodes | dynamics ms | collision ms | ns per node):"
    );
    let cell = |c: &hairlod::benchmark::LevelCost| {
        if c.nodes > 0.0 {
            format!(
                "{:>7.0} | {:>6.2} | {:>6.2} | {:>6.0}",
                c.nodes, c.dynamics_ms, c.collision_ms, c.ns_per_node
            )
        } else {
            format!("{:>7} | {:>6} | {:>6} | {:>6}", "-", "-", "-", "-")
        }
    };
    println!(
        "  {:<12} {:<33} {:<33} {:<33} all",
        "mode", "patches", "clusters", "strand groups"
    );
    let strands = costs
        .iter()
        .find(|c| c.mode == "Strands")
        .map(|c| c.all.total_ms());
    for c in costs {
        let against = match strands {
            Some(s) if c.all.total_ms() > 0.0 => {
                format!("  (Strands / this: {:.2}×)", s / c.all.total_ms())
            }
            _ => String::new(),
        };
        println!(
            "  {:<12} {}   {}   {}   {}{against}",
            c.mode,
            cell(&c.levels[0]),
            cell(&c.levels[1]),
            cell(&c.levels[2]),
            cell(&c.all)
        );
    }
}
