//! Typed command-line values shared by the verbs: presets, levels, camera paths, head motions,
//! backends, image sizes and frame ranges.

use std::ops::Range;

use anyhow::{Result, bail};
use clap::ValueEnum;
use hairlod::render::BackendChoice;
use hairlod::scene_file::parse_size;

/// A preset groom.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Preset {
    /// The paper's benchmark groom: 91 sections, 37,765 curly strands.
    PaperCurly,
    /// Straight hair.
    Straight,
    /// Wavy hair.
    Wavy,
    /// Ringlet curls.
    Curly,
}

impl Preset {
    /// The preset's name in hair-core and scene files.
    pub fn name(self) -> &'static str {
        match self {
            Preset::PaperCurly => "paper-curly",
            Preset::Straight => "straight",
            Preset::Wavy => "wavy",
            Preset::Curly => "curly",
        }
    }
}

/// The hair's reflectance model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ShadingArg {
    /// Kajiya-Kay: a diffuse term and one specular lobe.
    KajiyaKay,
    /// Marschner's R, TT and TRT lobes (the paper's measured shift and width).
    Marschner,
}

/// How much of a pixel a strand line covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CoverageArg {
    /// The whole pixel.
    Pixel,
    /// Its fibre's width's share of the pixel's samples.
    Width,
}

/// How cluster tubes are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ClustersArg {
    /// The tube's view-facing silhouette, shaded as the tube.
    Impostor,
    /// The tube tessellated around.
    Tube,
}

impl ClustersArg {
    /// The scene file's `output.clusters` value.
    pub fn name(self) -> &'static str {
        match self {
            ClustersArg::Impostor => "impostor",
            ClustersArg::Tube => "tube",
        }
    }
}

impl ShadingArg {
    /// The scene file's `output.shading` value.
    pub fn name(self) -> &'static str {
        match self {
            ShadingArg::KajiyaKay => "kajiya-kay",
            ShadingArg::Marschner => "marschner",
        }
    }
}

impl CoverageArg {
    /// The scene file's `output.line_coverage` value.
    pub fn name(self) -> &'static str {
        match self {
            CoverageArg::Pixel => "pixel",
            CoverageArg::Width => "width",
        }
    }
}

/// Level of detail: chosen per section every frame, or one fixed level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LevelArg {
    /// Chosen per section from visibility, screen size and motion (§7).
    Auto,
    /// Every section as five strand groups.
    Strands,
    /// Every section as three clusters.
    Clusters,
    /// Every section as one patch.
    Patches,
}

impl LevelArg {
    /// The scene file's `lod.mode` value.
    pub fn name(self) -> &'static str {
        match self {
            LevelArg::Auto => "auto",
            LevelArg::Strands => "strands",
            LevelArg::Clusters => "clusters",
            LevelArg::Patches => "patches",
        }
    }
}

/// Camera path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CameraArg {
    /// Once around the head.
    Orbit,
    /// From the start distance to 4× (or `camera.end_distance`), geometrically.
    ZoomOut,
    /// Still.
    Fixed,
}

impl CameraArg {
    /// The scene file's `camera.path` value.
    pub fn name(self) -> &'static str {
        match self {
            CameraArg::Orbit => "orbit",
            CameraArg::ZoomOut => "zoom-out",
            CameraArg::Fixed => "fixed",
        }
    }
}

/// Head motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MotionArg {
    /// The head holds still.
    Still,
    /// The head shakes (about the vertical axis).
    Shake,
    /// The head nods.
    Nod,
}

impl MotionArg {
    /// The scene file's `motion.kind` value.
    pub fn name(self) -> &'static str {
        match self {
            MotionArg::Still => "still",
            MotionArg::Shake => "shake",
            MotionArg::Nod => "nod",
        }
    }
}

/// Graphics backend.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BackendArg {
    /// Any adapter (a GPU first, then Mesa's CPU drivers).
    Auto,
    /// Vulkan (lavapipe on a CPU).
    Vulkan,
    /// OpenGL through EGL (llvmpipe on a CPU).
    Gl,
}

impl From<BackendArg> for BackendChoice {
    fn from(backend: BackendArg) -> Self {
        match backend {
            BackendArg::Auto => BackendChoice::Auto,
            BackendArg::Vulkan => BackendChoice::Vulkan,
            BackendArg::Gl => BackendChoice::Gl,
        }
    }
}

/// An image size `WIDTHxHEIGHT` [pixels] (clap value parser).
pub fn size(text: &str) -> Result<(u32, u32)> {
    Ok(parse_size("size", text)?)
}

/// Which frames: a count `N` (the shot is N frames long) or a range `A..B` / `A..` of the
/// shot's frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FramesArg {
    /// The shot has this many frames; all of them.
    Count(usize),
    /// Frames `start..end` of the shot (`end` `None`: to the shot's end).
    Range(usize, Option<usize>),
}

impl FramesArg {
    /// Parses `N`, `A..B` or `A..` (clap value parser).
    pub fn parse(text: &str) -> Result<FramesArg> {
        let bad = || {
            anyhow::anyhow!(
                "frames {text:?}: expected a count N ≥ 1, or a range A..B (A < B) or A.. of the \
                 shot's frames"
            )
        };
        match text.split_once("..") {
            None => {
                let count: usize = text.trim().parse().map_err(|_| bad())?;
                if count == 0 {
                    bail!(bad());
                }
                Ok(FramesArg::Count(count))
            }
            Some((a, b)) => {
                let start: usize = a.trim().parse().map_err(|_| bad())?;
                let end = if b.trim().is_empty() {
                    None
                } else {
                    Some(b.trim().parse::<usize>().map_err(|_| bad())?)
                };
                if end.is_some_and(|end| end <= start) {
                    bail!(bad());
                }
                Ok(FramesArg::Range(start, end))
            }
        }
    }

    /// The range within a shot of `shot_frames` frames.
    pub fn range(self, shot_frames: usize) -> Result<Range<usize>> {
        let range = match self {
            FramesArg::Count(count) => 0..count,
            FramesArg::Range(start, end) => start..end.unwrap_or(shot_frames),
        };
        if range.end > shot_frames || range.start >= range.end {
            bail!(
                "frames {}..{}: the shot has frames 0..{shot_frames} (set [frames] count in the \
                 scene file, or give --frames N)",
                range.start,
                range.end
            );
        }
        Ok(range)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_parse_as_counts_and_ranges_or_explain() {
        assert_eq!(FramesArg::parse("12").unwrap(), FramesArg::Count(12));
        assert_eq!(
            FramesArg::parse("3..7").unwrap(),
            FramesArg::Range(3, Some(7))
        );
        assert_eq!(FramesArg::parse("3..").unwrap(), FramesArg::Range(3, None));
        for bad in ["0", "7..3", "a..b", "-1", ""] {
            assert!(FramesArg::parse(bad).is_err(), "{bad}");
        }
        assert_eq!(FramesArg::Range(3, None).range(10).unwrap(), 3..10);
        assert!(FramesArg::Range(3, Some(11)).range(10).is_err());
    }

    #[test]
    fn sizes_parse_or_name_the_range() {
        assert_eq!(size("640x360").unwrap(), (640, 360));
        assert!(size("0x10").unwrap_err().to_string().contains("16..=8192"));
    }
}

/// The scene-file fields that `render` and `view` let the command line override: levels,
/// pixel tolerance, image size, camera path and head motion (`None`: the file's).
#[derive(Debug, Clone, Copy, Default)]
pub struct ShotOverrides<'a> {
    /// `groom.preset`.
    pub preset: Option<Preset>,
    /// `frames.count`.
    pub frames: Option<usize>,
    /// `lod.mode`.
    pub level: Option<LevelArg>,
    /// `lod.pixel_tolerance` [pixels].
    pub pixel_tolerance: Option<f32>,
    /// `frames.size`, `WIDTHxHEIGHT`.
    pub size: Option<&'a String>,
    /// `camera.path`.
    pub camera: Option<CameraArg>,
    /// `motion.kind`.
    pub motion: Option<MotionArg>,
}

impl ShotOverrides<'_> {
    /// The scene file at `path` (the built-in default scene without one) with the overrides
    /// applied.
    pub fn scene_file(
        &self,
        path: Option<&std::path::Path>,
    ) -> anyhow::Result<hairlod::scene_file::SceneFile> {
        let mut file = match path {
            Some(path) => hairlod::scene_file::SceneFile::read(path)?,
            None => hairlod::scene_file::SceneFile::default(),
        };
        self.apply(&mut file);
        Ok(file)
    }

    /// Writes the given overrides into `file`.
    pub fn apply(&self, file: &mut hairlod::scene_file::SceneFile) {
        if let Some(preset) = self.preset {
            file.groom.preset = Some(preset.name().to_string());
        }
        if let Some(count) = self.frames {
            file.frames.count = Some(count);
        }
        if let Some(level) = self.level {
            file.lod.mode = Some(level.name().to_string());
        }
        if let Some(tolerance) = self.pixel_tolerance {
            file.lod.pixel_tolerance = Some(tolerance);
        }
        if let Some(size) = self.size {
            file.frames.size = Some(size.clone());
        }
        if let Some(camera) = self.camera {
            file.camera.path = Some(camera.name().to_string());
        }
        if let Some(motion) = self.motion {
            file.motion.kind = Some(motion.name().to_string());
        }
    }
}
