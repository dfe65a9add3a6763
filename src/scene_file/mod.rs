//! Scene files, version 2: a TOML file that describes everything a run needs (groom, body, head
//! motion, wind, camera path, levels of detail, dynamics, frames and outputs). Every field is
//! optional with a sensible default, except what an entry needs once it is given (a keyframe's
//! `time`, a camera keyframe's `position`, a `[[character]]`'s `position`); unknown keys are
//! errors, and every bad value gets an error that names the field path and the allowed range.
//! [`SceneFile::resolve`] turns a file into a [`Shot`](crate::shot::Shot).
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

mod bounds;
mod checks;
mod choices;
mod files;
#[cfg(test)]
mod fuzz;
mod resolve;

pub use bounds::{MAX_CAMERA_DISTANCE, MAX_HEAD_COORDINATE, MIN_CAMERA_DISTANCE};
pub use checks::parse_size;
pub use choices::{BodyKind, CameraPathKind, LodModeKind, MotionKind};
pub use resolve::DEFAULT_FILE_MATERIAL;

use std::path::{Path, PathBuf};

use hair_collide::BroadPhase;
use hair_core::GroomPreset;
use hair_core::dynamics::IntegratorKind;
use hair_core::lod::{BudgetMethod, ErrorModel, OcclusionTest};
use hair_formats::UpAxis;
use hair_render::{ClusterGeometry, LineCoverage, ShadingModel};
use serde::Deserialize;

use crate::pipeline::DrawnAs;
use crate::rest_pose::RestPose;

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
    /// The folder relative file paths (`groom.file`, `body.file`) resolve against: the scene
    /// file's folder when read with [`SceneFile::read`] (`None`: the working directory).
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
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
    /// Where the head's centre stands [m], required; each coordinate in
    /// `-MAX_HEAD_COORDINATE..=MAX_HEAD_COORDINATE` ([`MAX_HEAD_COORDINATE`], 1 km).
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
    pub preset: Option<GroomPreset>,
    /// A groom file (`.tfx`, `.hair`, `.data`, `.obj` polylines, `.usda`, `.usdc`, `.usd`,
    /// `.abc`; the extension picks
    /// the reader), relative to the scene file's folder, or a list of them (the parts of one
    /// hairstyle, read with the same units and axes): their curves, fitted with the paper's
    /// hierarchy, replace the preset's groom; `preset` then gives only the material (the style's
    /// stiffness). The keys that shape a generated groom (`strands_per_group`, `hair_length`,
    /// `style_factor_degrees`, `style_size`) are errors beside it.
    pub file: Option<FileList>,
    /// With `file`: metres per file unit, > 0 (default 1; 0.01 for centimetres).
    pub scale: Option<f32>,
    /// With `file`: the file's up axis, `y` (default) or `z` (turned to +Y up).
    pub up_axis: Option<UpAxis>,
    /// With `file`: negate x (a file from a left-handed tool), default false.
    pub mirror: Option<bool>,
    /// With `file`: about this many strands per fitted section, 1..=100000 (default 50; give
    /// this or `section_count`).
    pub strands_per_section: Option<usize>,
    /// With `file`: how much larger than the mean a fitted section may grow, as a fraction,
    /// 0..=10 (default 0.25; 0 with `strands_per_section = 5` gives every strand group one file
    /// strand).
    pub section_size_slack: Option<f32>,
    /// With `file`: child strands grown around each file strand, 0..=1000. Default: none on a
    /// dense groom; on a sparse one (fewer than 2 strands per cm² of scalp, a set of guides)
    /// enough to reach 20 per cm², at most 40,000 strands in all (`hairlod::loaded::auto_children`).
    /// 0 turns them off.
    pub children_per_strand: Option<usize>,
    /// With `file`: radius [m] of the disc around its guide a child's root is drawn in, ≥ 0
    /// (default 0.002; for the children grown by default on a sparse groom, the disc each guide
    /// stands for, `√(1/(π·density))`).
    pub child_spread: Option<f32>,
    /// With `file`: a child's offset at the tip as a fraction of that at the root, 0..=1
    /// (default 0.5; smaller gathers children to their guide's skeleton).
    pub child_clump: Option<f32>,
    /// Number of sections (each 1 patch = 3 clusters = 5 strand groups), 1..=10000 (a single
    /// section is as wide as each of two, 14 cm: [`GroomParams::section_width`]); with
    /// `file`, the sections the fit makes: at most one per 5 file strands (more is an error that
    /// names that maximum), fewer where some would hold fewer than 5 strands (merged; `hairlod
    /// groom --file` reports how many).
    ///
    /// [`GroomParams::section_width`]: hair_core::GroomParams::section_width
    pub section_count: Option<usize>,
    /// Strands per strand group, 1..=10000.
    pub strands_per_group: Option<usize>,
    /// Hair length [m], > 0.
    pub hair_length: Option<f32>,
    /// Wave or curl factor θ0 [degrees], 0..=90.
    pub style_factor_degrees: Option<f32>,
    /// Wave amplitude or curl radius [m], > 0.
    pub style_size: Option<f32>,
    /// Longest skeleton segment [m], > 0 (smaller: more nodes, smoother hair); with `file`, the
    /// fit's (default 0.025).
    pub smoothness: Option<f32>,
    /// Random seed of strand placement and shades (with `file`: of the fit's clustering and the
    /// shades).
    pub seed: Option<u64>,
    /// The shape the groom starts in: `hanging` (the default without `file`: fallen onto the
    /// body and made an equilibrium there, see [`hang_groom`](crate::rest_pose::hang_groom)),
    /// `grown` (the generated or loaded shape with its springs at rest, which falls at first) or
    /// `loaded` (the default with `file`: the file's shape kept and made an equilibrium).
    pub rest_pose: Option<RestPose>,
}

/// One file path or a list of them, as a scene file gives `groom.file`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum FileList {
    /// One file.
    One(String),
    /// Several files, read one after the other.
    Many(Vec<String>),
}

impl FileList {
    /// The paths as given.
    pub fn paths(&self) -> Vec<&str> {
        match self {
            FileList::One(path) => vec![path.as_str()],
            FileList::Many(paths) => paths.iter().map(String::as_str).collect(),
        }
    }
}

/// `[body]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyTable {
    /// `procedural-head` (the default without `file`) or `mesh` (the default with `file`).
    pub kind: Option<BodyKind>,
    /// A body mesh file (`.tfxmesh`, `.obj`, or a USD `Mesh` in `.usda`, `.usdc` or `.usd`), relative to the scene file's folder, drawn and
    /// collided with in place of the procedural head. Needs `groom.file` (the presets grow on
    /// the procedural head).
    pub file: Option<String>,
    /// With `file`: metres per file unit, > 0 (default 1).
    pub scale: Option<f32>,
    /// With `file`: the file's up axis, `y` (default) or `z`.
    pub up_axis: Option<UpAxis>,
    /// With `file`: negate x, default false.
    pub mirror: Option<bool>,
    /// The procedural head's own deformation: `none` (default) or `talk` (the jaw opens and
    /// closes, the head squashes and stretches; the roots ride it, collision and drawing follow
    /// it; combined with `[motion]`, which moves the deforming head rigidly). A body file's own
    /// animation (time samples) plays without this.
    pub animation: Option<crate::body_animation::BodyAnimationKind>,
}

/// `[motion]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionTable {
    /// `still` (default), `shake` (about the vertical axis), `nod` (about the ear-to-ear axis) or
    /// `keyframes`.
    pub kind: Option<MotionKind>,
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
    /// Translation [m], default none; each coordinate in -1000..=1000 ([`MAX_HEAD_COORDINATE`]).
    #[serde(default)]
    pub translation: [f32; 3],
}

/// `[wind]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindTable {
    /// Mean speed [m/s], ≥ 0 (default 0: calm).
    pub speed: Option<f32>,
    /// Direction the wind blows towards (normalised; any finite vector but zero), default
    /// `[0.6, 0, -0.8]`.
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
    pub path: Option<CameraPathKind>,
    /// The point looked at [m], default the head's centre `[0, 0, 0]`; each coordinate in
    /// `-10000..=10000` ([`MAX_CAMERA_DISTANCE`]).
    pub target: Option<[f32; 3]>,
    /// Distance from the target [m], in `0.001..=10000` ([`MIN_CAMERA_DISTANCE`],
    /// [`MAX_CAMERA_DISTANCE`]; default 0.8; zoom-out: at the first frame).
    pub distance: Option<f32>,
    /// Distance at the last frame of a zoom-out [m], in `0.001..=10000` (default 4 × distance,
    /// at most 10000).
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
    /// Camera position [m], required; each coordinate in `-10000..=10000`, and
    /// `0.001..=10000` m from the target ([`MAX_CAMERA_DISTANCE`]).
    pub position: [f32; 3],
    /// The point looked at [m], default `[0, 0, 0]`; each coordinate in `-10000..=10000`.
    #[serde(default)]
    pub target: [f32; 3],
}

/// `[lod]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LodTable {
    /// `auto` (default), `strands`, `clusters` or `patches`.
    pub mode: Option<LodModeKind>,
    /// Screen-space error tolerance [pixels], > 0 (default 2; larger means coarser levels).
    pub pixel_tolerance: Option<f32>,
    /// How a coarse level's error is estimated: `deviation` (default: each section's measured
    /// deviation from its strands, scaled by its depth) or `chord` (the paper's rule, §7.4).
    pub error_model: Option<ErrorModel>,
    /// Frame budget [ms], > 0: the levels are chosen so that a frame costs at most this.
    pub budget_ms: Option<f64>,
    /// How the budget is met: `greedy` (default: the levels that minimise the total estimated
    /// error within it) or `tolerance` (the pixel tolerance steered to meet it).
    pub budget_method: Option<BudgetMethod>,
    /// Blend time of a level transition [s], ≥ 0 (default 0.25).
    pub blend_time: Option<f32>,
    /// How far ahead the level choice looks, as a fraction of the blend time, 0..=1 (default
    /// 0.5; 0: the current frame only).
    pub blend_lead: Option<f32>,
    /// The motion criterion and the part/face rule apply only to sections whose chord spans at
    /// least this many pixels [pixels], ≥ 0 (default 20; 0: always, the paper's rule).
    pub rules_min_pixels: Option<f32>,
    /// How a section is found hidden behind the head: `section` (default: all of it, samples of
    /// its skeletons widened by half its width) or `ends` (the paper's test: the root and tip of
    /// its centre skeleton, §7.1).
    pub occlusion_test: Option<OcclusionTest>,
    /// Strand thinning: strands drawn per pixel of a strand group's screen width, ≥ 0 (default
    /// 0: every strand). 4 covers a group's pixels as all its strands do.
    pub strands_per_pixel: Option<f32>,
    /// With thinning, widen each drawn strand to stand for those left out, so that a thinned
    /// group covers what all its strands cover (default false).
    pub raise_thinned_widths: Option<bool>,
    /// How the levels are drawn: `"level"` (default: each as itself, the paper) or
    /// `"strands"` (every level's sections drawn as strands on strand-group skeletons rebuilt
    /// from the level simulated).
    pub drawn_as: Option<DrawnAs>,
}

/// `[dynamics]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsTable {
    /// `xpbd` (default), `linear-implicit`, `semi-implicit-euler` or `position-based`.
    pub integrator: Option<IntegratorKind>,
    /// Substeps per frame, 1..=10000 (default: the integrator's recommended substeps per 1/60 s,
    /// scaled to the frame time).
    pub substeps: Option<u32>,
    /// Most substeps per frame where the hair moves fast, 1..=10000: a frame starts at
    /// `substeps` and doubles them while a node would move more than 0.2 of its segment in one
    /// (XPBD's default: 32 per 1/60 s, scaled to the frame time; the other integrators' and any
    /// value not above `substeps`: a fixed count).
    pub max_substeps: Option<u32>,
    /// Hair–head collision on (default true).
    pub collision: Option<bool>,
    /// How collision finds the hair near the head: `field-contacts` (the default: contacts from
    /// the head's distance field), `hierarchies` (the paper's §5.3: exact triangle tests) or
    /// `distance-field` (the same exact tests, culled by the field).
    pub collision_broad_phase: Option<BroadPhase>,
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
    /// Which strands `hair.usda` holds: `"all"` (the default) or `"guides"` (a groom file's own
    /// strands, without the children grown around them); naming it writes the file.
    pub usd_strands: Option<crate::usd_export::UsdStrands>,
    /// Write the run's JSON report (per-frame stage times and levels) to this file, relative to
    /// the output folder.
    pub json: Option<String>,
    /// The hair's reflectance model: `"kajiya-kay"` (the default) or `"marschner"`.
    pub shading: Option<ShadingModel>,
    /// How much of a pixel a strand line covers: `"pixel"` (the default) or `"width"` (its
    /// fibre's width's share).
    pub line_coverage: Option<LineCoverage>,
    /// How cluster tubes are drawn: `"impostor"` (the default: the tube's view-facing silhouette,
    /// shaded as the tube) or `"tube"` (tessellated around).
    pub clusters: Option<ClusterGeometry>,
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
    /// Relative file paths in it resolve against its folder.
    pub fn read(path: &Path) -> Result<SceneFile, SceneFileError> {
        let text = std::fs::read_to_string(path).map_err(|error| SceneFileError {
            path: Some(path.to_path_buf()),
            message: format!("cannot read it: {error}"),
        })?;
        let folder = path.parent().unwrap_or(Path::new(""));
        SceneFile::parse_in(&text, Some(folder)).map_err(|error| SceneFileError {
            path: Some(path.to_path_buf()),
            message: error.message,
        })
    }

    /// Parses TOML text; syntax errors, unknown keys and wrong types name the place, and values
    /// are checked ([`SceneFile::resolve`] does the checking). Relative file paths resolve
    /// against the working directory.
    pub fn parse(text: &str) -> Result<SceneFile, SceneFileError> {
        SceneFile::parse_in(text, None)
    }

    /// [`SceneFile::parse`] with relative file paths resolved against `base_dir` (`None`: the
    /// working directory).
    pub fn parse_in(text: &str, base_dir: Option<&Path>) -> Result<SceneFile, SceneFileError> {
        let mut file = deserialize(text)?;
        file.base_dir = base_dir.map(Path::to_path_buf);
        file.resolve()?;
        Ok(file)
    }

    /// `path` (a scene-file field's value) resolved against [`SceneFile::base_dir`].
    pub fn resolve_path(&self, path: &str) -> PathBuf {
        match &self.base_dir {
            Some(base) if Path::new(path).is_relative() => base.join(path),
            _ => PathBuf::from(path),
        }
    }

    /// The JSON report's file name, if asked for.
    pub fn json_output(&self) -> Option<&str> {
        self.output.json.as_deref()
    }
}

/// `text` deserialized as a scene file; an error names the field path (`lod.mode`), what is
/// wrong with its value (a name that is none of the allowed ones lists them), and the line.
fn deserialize(text: &str) -> Result<SceneFile, SceneFileError> {
    let document = toml::de::Deserializer::parse(text)
        .map_err(|error| SceneFileError::new(error.to_string()))?;
    serde_path_to_error::deserialize(document).map_err(|error| {
        let path = error.path().to_string();
        let inner = error.into_inner();
        let line = inner
            .span()
            .map(|span| format!(" (line {})", text[..span.start].matches('\n').count() + 1))
            .unwrap_or_default();
        let message = inner.message();
        // A bad value reads `field = "value": expected …`, as every other check's error does.
        let joint = if message.starts_with('"') {
            " = "
        } else {
            ": "
        };
        SceneFileError::new(if path == "." {
            format!("{message}{line}")
        } else {
            format!("{path}{joint}{message}{line}")
        })
    })
}
