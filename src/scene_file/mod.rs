//! Scene files, version 2: a TOML file that describes everything a run needs (groom, body, head
//! motion, wind, camera path, levels of detail, dynamics, frames and outputs). Every field is
//! optional with a sensible default; unknown keys are errors, and every bad value gets an error
//! that names the field path and the allowed range. [`SceneFile::resolve`] turns a file into a
//! [`Shot`](crate::shot::Shot).
//!
//! `scenes/example.toml` in the repository documents every field; `scenes/paper-table1.toml` and
//! `scenes/paper-table2.toml` are the paper's benchmark (`hairlod bench paper` runs them).
//!
//! ```
//! use hairlod::scene_file::SceneFile;
//!
//! let file = SceneFile::parse("[groom]\npreset = \"curly\"\n[frames]\ncount = 4\n")?;
//! let shot = file.resolve()?;
//! assert_eq!(shot.frames, 4);
//! let error = SceneFile::parse("[wind]\nspeed = -1.0\n").unwrap_err();
//! assert!(error.to_string().contains("wind.speed"));
//! # Ok::<(), hairlod::scene_file::SceneFileError>(())
//! ```

mod resolve;

pub use resolve::parse_size;

use std::path::{Path, PathBuf};

use serde::Deserialize;

/// A scene file that cannot be read or used: the file, and what is wrong (naming the field path
/// and the allowed range for a bad value).
#[derive(Debug, thiserror::Error)]
#[error("{}{message}", path.as_ref().map(|p| format!("scene file {}: ", p.display())).unwrap_or_default())]
pub struct SceneFileError {
    /// The file, when the text came from one.
    pub path: Option<PathBuf>,
    /// What is wrong.
    pub message: String,
}

impl SceneFileError {
    /// An error about the text (no file yet).
    pub(crate) fn new(message: impl Into<String>) -> Self {
        SceneFileError {
            path: None,
            message: message.into(),
        }
    }
}

/// The version of the scene-file layout this hairlod reads.
pub const SCENE_FILE_VERSION: u32 = 2;

/// A whole scene file: each table optional.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The layout version: 2 (the default).
    pub version: Option<u32>,
    /// `[groom]`: a preset and overrides of its parameters.
    #[serde(default)]
    pub groom: GroomTable,
    /// `[body]`: the body the hair grows on and collides with.
    #[serde(default)]
    pub body: BodyTable,
    /// `[motion]`: how the head moves.
    #[serde(default)]
    pub motion: MotionTable,
    /// `[wind]`: the wind.
    #[serde(default)]
    pub wind: WindTable,
    /// `[camera]`: the camera path and lens.
    #[serde(default)]
    pub camera: CameraTable,
    /// `[lod]`: automatic or fixed levels, tolerance, frame budget.
    #[serde(default)]
    pub lod: LodTable,
    /// `[dynamics]`: integrator, substeps, collision, settling.
    #[serde(default)]
    pub dynamics: DynamicsTable,
    /// `[frames]`: how many, how fast, how large.
    #[serde(default)]
    pub frames: FramesTable,
    /// `[output]`: which images to write.
    #[serde(default)]
    pub output: OutputTable,
    /// `[bench]`: what `hairlod bench` compares with.
    #[serde(default)]
    pub bench: BenchTable,
    /// `[[character]]`: the characters of a crowd, each with its own groom, place, motion and
    /// wind (none: one character, the scene's groom on a head at the origin).
    #[serde(default)]
    pub character: Vec<CharacterTable>,
}

/// `[[character]]`: one character of a crowd.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CharacterTable {
    /// A name for reports (default `character K`).
    pub name: Option<String>,
    /// Where the head's centre stands [m].
    pub position: [f32; 3],
    /// The head turned about the vertical [degrees], -360..=360 (default 0: facing +Z).
    pub yaw_degrees: Option<f32>,
    /// The character's groom, as `[groom]` (default the scene's `[groom]`).
    pub groom: Option<GroomTable>,
    /// The character's head motion, as `[motion]` (default the scene's `[motion]`), relative to
    /// where it stands.
    pub motion: Option<MotionTable>,
    /// The wind around the character, as `[wind]` (default the scene's `[wind]`).
    pub wind: Option<WindTable>,
}

/// `[groom]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroomTable {
    /// Preset: `paper-curly` (default), `straight`, `wavy` or `curly`.
    pub preset: Option<String>,
    /// Reserved for grooms read from files (the real-groom issue); an error for now.
    pub file: Option<String>,
    /// Number of sections (each 1 patch = 3 clusters = 5 strand groups), 1..=10000.
    pub section_count: Option<usize>,
    /// Strands per strand group, 1..=10000.
    pub strands_per_group: Option<usize>,
    /// Hair length [m], > 0.
    pub hair_length: Option<f32>,
    /// Wave or curl factor θ0 [degrees], 0..=90.
    pub style_factor_degrees: Option<f32>,
    /// Wave amplitude or curl radius [m], > 0.
    pub style_size: Option<f32>,
    /// Longest skeleton segment [m], > 0 (smaller: more nodes, smoother hair).
    pub smoothness: Option<f32>,
    /// Random seed of strand placement and shades.
    pub seed: Option<u64>,
    /// The shape the groom starts in: `hanging` (default: fallen onto the body and made an
    /// equilibrium there, see [`hang_groom`](crate::rest_pose::hang_groom)) or `grown` (the
    /// generated shape, which falls at first).
    pub rest_pose: Option<String>,
}

/// `[body]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyTable {
    /// `procedural-head` (the default and, for now, the only body).
    pub kind: Option<String>,
    /// Reserved for body meshes read from files (the real-groom issue); an error for now.
    pub file: Option<String>,
}

/// `[motion]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionTable {
    /// `still` (default), `shake` (about the vertical axis), `nod` (about the ear-to-ear axis) or
    /// `keyframes`.
    pub kind: Option<String>,
    /// Shake or nod amplitude [degrees], 0..=90 (default 14).
    pub amplitude_degrees: Option<f32>,
    /// Shake or nod peak angular speed [rad/s], > 0 (default 1.2).
    pub peak_speed: Option<f32>,
    /// `keyframes`: the head's pose at times (ascending).
    #[serde(default)]
    pub keyframes: Vec<HeadKeyframeEntry>,
}

/// One head keyframe.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeadKeyframeEntry {
    /// Time [s], ≥ 0.
    pub time: f64,
    /// Rotation [degrees] about X, Y, Z (applied in that order), default none.
    #[serde(default)]
    pub rotation_degrees: [f32; 3],
    /// Translation [m], default none.
    #[serde(default)]
    pub translation: [f32; 3],
}

/// `[wind]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindTable {
    /// Mean speed [m/s], ≥ 0 (default 0: calm).
    pub speed: Option<f32>,
    /// Direction the wind blows towards (normalised), default `[0.6, 0, -0.8]`.
    pub direction: Option<[f32; 3]>,
    /// Gust speed [m/s], ≥ 0 (default 0: steady).
    pub gusts: Option<f32>,
    /// Gust time scale [s], > 0 (default 1).
    pub gust_period: Option<f32>,
    /// Gust length scale [m], > 0 (default 0.5).
    pub gust_length: Option<f32>,
    /// Seed of the gusts (default 7).
    pub seed: Option<u64>,
}

/// `[camera]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraTable {
    /// `orbit` (default), `zoom-out`, `fixed` or `keyframes`.
    pub path: Option<String>,
    /// The point looked at [m], default the head's centre `[0, 0, 0]`.
    pub target: Option<[f32; 3]>,
    /// Distance from the target [m], > 0 (default 0.8; zoom-out: at the first frame).
    pub distance: Option<f32>,
    /// Distance at the last frame of a zoom-out [m], > 0 (default 4 × distance).
    pub end_distance: Option<f32>,
    /// Azimuth [degrees] (0: in front of the face), default 150.
    pub azimuth_degrees: Option<f32>,
    /// Elevation above the horizontal [degrees], -89..=89, default 8.
    pub elevation_degrees: Option<f32>,
    /// Vertical field of view [degrees], 1..=170, default 35.
    pub fov_degrees: Option<f32>,
    /// `keyframes`: positions and targets at times (ascending).
    #[serde(default)]
    pub keyframes: Vec<CameraKeyframeEntry>,
}

/// One camera keyframe.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKeyframeEntry {
    /// Time [s], ≥ 0.
    pub time: f64,
    /// Camera position [m].
    pub position: [f32; 3],
    /// The point looked at [m], default `[0, 0, 0]`.
    #[serde(default)]
    pub target: [f32; 3],
}

/// `[lod]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LodTable {
    /// `auto` (default), `strands`, `clusters` or `patches`.
    pub mode: Option<String>,
    /// Screen-space error tolerance [pixels], > 0 (default 2; larger means coarser levels).
    pub pixel_tolerance: Option<f32>,
    /// How a coarse level's error is estimated: `deviation` (default: each section's measured
    /// deviation from its strands, scaled by its depth) or `chord` (the paper's rule, §7.4).
    pub error_model: Option<String>,
    /// Frame budget [ms], > 0: the levels are chosen so that a frame costs at most this.
    pub budget_ms: Option<f64>,
    /// How the budget is met: `greedy` (default: the levels that minimise the total estimated
    /// error within it) or `tolerance` (the pixel tolerance steered to meet it).
    pub budget_method: Option<String>,
    /// Blend time of a level transition [s], ≥ 0 (default 0.25).
    pub blend_time: Option<f32>,
}

/// `[dynamics]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsTable {
    /// `linear-implicit` (default), `semi-implicit-euler`, `position-based` or `xpbd`.
    pub integrator: Option<String>,
    /// Substeps per frame, 1..=10000 (default: the integrator's recommended substeps per 1/60 s,
    /// scaled to the frame time).
    pub substeps: Option<u32>,
    /// Hair–head collision on (default true).
    pub collision: Option<bool>,
    /// Settling at full detail under gravity before frame 0 [s], 0..=60 (default 0 for a
    /// hanging groom, which is at rest already, and 1 for a grown one).
    pub settle_seconds: Option<f32>,
}

/// `[frames]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FramesTable {
    /// Frames of the shot, 1..=1000000 (default 12).
    pub count: Option<usize>,
    /// Frame rate [Hz], 1..=10000 (default 60); one pipeline step per frame.
    pub fps: Option<f32>,
    /// Image size `WIDTHxHEIGHT` [pixels], each 16..=8192 (default `1280x720`).
    pub size: Option<String>,
}

/// `[output]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputTable {
    /// Shaded frames (default true, unless another view is asked for).
    pub shaded: Option<bool>,
    /// Frames colour-coded by level (strands yellow, clusters red, patches blue).
    pub color_coded: Option<bool>,
    /// Shaded | colour-coded pairs side by side.
    pub side_by_side: Option<bool>,
    /// A contact sheet of every frame, scaled down.
    pub contact_sheet: Option<bool>,
    /// Every strand of every frame as a cyHair `.hair` file, `hair/frame_00000.hair`, …
    pub hair: Option<bool>,
    /// Every strand of the run as one USD BasisCurves prim with a time sample per frame,
    /// `hair.usda`.
    pub usd: Option<bool>,
    /// Write the run's JSON report (per-frame stage times and levels) to this file, relative to
    /// the output folder.
    pub json: Option<String>,
}

/// `[bench]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BenchTable {
    /// The paper's table (1 or 2) whose figures `hairlod bench` prints in brackets.
    pub paper_table: Option<u8>,
}

impl SceneFile {
    /// Reads and parses the file at `path`; errors name the file.
    pub fn read(path: &Path) -> Result<SceneFile, SceneFileError> {
        let text = std::fs::read_to_string(path).map_err(|error| SceneFileError {
            path: Some(path.to_path_buf()),
            message: format!("cannot read it: {error}"),
        })?;
        SceneFile::parse(&text).map_err(|error| SceneFileError {
            path: Some(path.to_path_buf()),
            message: error.message,
        })
    }

    /// Parses TOML text; syntax errors, unknown keys and wrong types name the place, and values
    /// are checked ([`SceneFile::resolve`] does the checking).
    pub fn parse(text: &str) -> Result<SceneFile, SceneFileError> {
        let file: SceneFile =
            toml::from_str(text).map_err(|error| SceneFileError::new(error.to_string()))?;
        file.resolve()?;
        Ok(file)
    }

    /// The JSON report's file name, if asked for.
    pub fn json_output(&self) -> Option<&str> {
        self.output.json.as_deref()
    }
}
