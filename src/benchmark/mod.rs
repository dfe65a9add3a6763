//! The paper's benchmark (§8.2, Tables 1 and 2): the `paper-curly` groom (91 patches, 273
//! clusters, 455 strand groups, 37,765 strands) with the camera zooming out from the face, calm or
//! with wind, run in each mode (LODs, Strands, Clusters, Patches) over the same frames, timing
//! dynamics, collision and rendering. The scene is `scenes/paper-table1.toml` (calm) or
//! `scenes/paper-table2.toml` (wind), compiled in: `hairlod bench paper` and `hairlod bench
//! scenes/paper-table1.toml` run the same description.

use hair_core::Level;
use hair_core::lod::LodSettings;

mod budget;
mod costs;
pub mod coverage;
mod paper;

pub use budget::{BudgetedRun, run_budgeted};
pub use costs::{LevelCost, SimulationCosts};
pub use paper::{
    AgainstStrands, BudgetedAgainstStrands, PaperOptions, PaperRun, PaperRunError, PaperRuns,
    run_budgeted_against, run_paper_tables,
};

use crate::pipeline::{LodMode, PipelineRenderer, PipelineSettings, Result};
use crate::run::{ModeRun, RunOptions, View, run_shot};
use crate::scene_file::SceneFile;
use crate::shot::Shot;

/// The paper's figures [s per frame], rows dynamics, collision, rendering; columns LODs, Strands,
/// Clusters, Patches. Table 1: camera zooming out.
pub const PAPER_TABLE_1: [[f64; 4]; 3] = [
    [0.183, 1.071, 0.099, 0.030],
    [0.077, 0.200, 0.122, 0.040],
    [0.385, 1.687, 0.656, 0.158],
];

/// Table 2: the same with wind blowing.
pub const PAPER_TABLE_2: [[f64; 4]; 3] = [
    [0.356, 1.134, 0.105, 0.032],
    [0.107, 0.168, 0.101, 0.034],
    [0.785, 1.734, 0.665, 0.158],
];

/// The text of `scenes/paper-table1.toml`: the zoom-out in calm air.
pub const PAPER_TABLE_1_SCENE: &str = include_str!("../../scenes/paper-table1.toml");

/// The text of `scenes/paper-table2.toml`: the zoom-out with a gusting wind.
pub const PAPER_TABLE_2_SCENE: &str = include_str!("../../scenes/paper-table2.toml");

/// The paper's figures for table `table` (1 or 2).
pub fn paper_figures(table: u8) -> Option<[[f64; 4]; 3]> {
    match table {
        1 => Some(PAPER_TABLE_1),
        2 => Some(PAPER_TABLE_2),
        _ => None,
    }
}

/// The paper's benchmark shot: Table 2's (gusting wind) or Table 1's (calm); 60 frames at
/// 1280×720, the camera from 0.45 m to 12 m.
pub fn paper_shot(wind: bool) -> Shot {
    let text = if wind {
        PAPER_TABLE_2_SCENE
    } else {
        PAPER_TABLE_1_SCENE
    };
    SceneFile::parse(text)
        .and_then(|file| file.resolve())
        .expect("the paper's scene files are valid (tested)")
}

/// `shot` with `frames` frames at `width`×`height` [pixels], the LOD settings matched to the size.
pub fn resized(shot: &Shot, frames: usize, width: u32, height: u32) -> Shot {
    let mut shot = shot.clone();
    shot.frames = frames;
    shot.width = width;
    shot.height = height;
    if let LodMode::Auto(lod) = &mut shot.settings.lod {
        lod.image_width = width;
        lod.image_height = height;
    }
    shot
}

/// The four modes of the tables, in the paper's column order.
pub fn paper_modes(lod: LodSettings) -> [LodMode; 4] {
    [
        LodMode::Auto(lod),
        LodMode::Fixed(Level::StrandGroup),
        LodMode::Fixed(Level::Cluster),
        LodMode::Fixed(Level::Patch),
    ]
}

/// How long a *grown* groom (see [`RestPose::Grown`](crate::RestPose::Grown)) settles under
/// gravity before the first frame [s] (see [`Pipeline::settle`](crate::Pipeline::settle)). The
/// paper's scenes hang their groom at rest instead and settle for 0 s.
pub const SETTLE_TIME: f32 = 1.0;

/// Runs `settings` on `shot` over all its frames (through the frame loop, [`run_shot`]),
/// rendering each frame shaded with `renderer` when given; `on_frame` sees each frame (report,
/// the shaded image when rendered, the pipeline, for popping and error measures or progress); an
/// error from it stops the run.
pub fn run_mode(
    shot: &Shot,
    scene: &hair_core::Scene,
    settings: PipelineSettings,
    renderer: Option<&mut PipelineRenderer>,
    on_frame: impl FnMut(crate::run::FrameOutput<'_>) -> Result<()>,
) -> Result<ModeRun> {
    let options = RunOptions::whole(shot, settings);
    let views = [View::Shaded];
    let renderer = renderer.map(|r| (r, &views[..]));
    let run = run_shot(shot, scene, options, renderer, on_frame)?;
    Ok(run.run)
}
