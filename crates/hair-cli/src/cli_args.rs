//! Typed command-line values shared by the verbs: the fixed-choice options' value parser
//! ([`choice`]), backends, image sizes and frame ranges.

use std::ops::Range;

use anyhow::{Result, bail};
use clap::ValueEnum;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use hairlod::core::GroomPreset;
use hairlod::core::named::Named;
use hairlod::render::BackendChoice;
use hairlod::scene_file::{CameraPathKind, LodModeKind, MotionKind, parse_size};

/// A clap value parser of a fixed-choice option (one declared with `hair_core::named_enum!`):
/// `--help` lists its names, the same as a scene file's, and an unknown one is refused with
/// them.
pub fn choice<T: Named + Clone>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::names().iter().copied()).try_map(|name| T::from_name(&name))
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
    pub preset: Option<GroomPreset>,
    /// `frames.count`.
    pub frames: Option<usize>,
    /// `lod.mode`.
    pub level: Option<LodModeKind>,
    /// `lod.pixel_tolerance` [pixels].
    pub pixel_tolerance: Option<f32>,
    /// `frames.size`, `WIDTHxHEIGHT`.
    pub size: Option<&'a String>,
    /// `camera.path`.
    pub camera: Option<CameraPathKind>,
    /// `motion.kind`.
    pub motion: Option<MotionKind>,
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
            file.groom.preset = Some(preset);
        }
        if let Some(count) = self.frames {
            file.frames.count = Some(count);
        }
        if let Some(level) = self.level {
            file.lod.mode = Some(level);
        }
        if let Some(tolerance) = self.pixel_tolerance {
            file.lod.pixel_tolerance = Some(tolerance);
        }
        if let Some(size) = self.size {
            file.frames.size = Some(size.clone());
        }
        if let Some(camera) = self.camera {
            file.camera.path = Some(camera);
        }
        if let Some(motion) = self.motion {
            file.motion.kind = Some(motion);
        }
    }
}

/// The flags that shape a run, which a simulation cache is fingerprinted against: `render` and
/// `simulate` take these same ones (one definition), so a cache simulated with some flags is
/// rendered with the same.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct RunFlags {
    /// Preset groom [scene: groom.preset; default paper-curly].
    #[arg(long, value_parser = choice::<GroomPreset>())]
    pub preset: Option<GroomPreset>,
    /// Level of detail [scene: lod.mode; default auto].
    #[arg(long, value_parser = choice::<LodModeKind>())]
    pub level: Option<LodModeKind>,
    /// Screen-space error tolerance of automatic levels [pixels] [scene: lod.pixel_tolerance].
    #[arg(long, value_name = "PX")]
    pub pixel_tolerance: Option<f32>,
    /// How the levels are drawn: `level` (each as itself) or `strands` (every level's sections
    /// as strands, on strand-group skeletons rebuilt from the level simulated) [scene:
    /// lod.drawn_as; default level].
    #[arg(long, value_parser = choice::<hairlod::pipeline::DrawnAs>())]
    pub drawn_as: Option<hairlod::pipeline::DrawnAs>,
    /// Image size WIDTHxHEIGHT [pixels] (the levels follow it) [scene: frames.size; default
    /// 1280x720].
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Camera path [scene: camera.path; default orbit].
    #[arg(long, value_parser = choice::<CameraPathKind>())]
    pub camera: Option<CameraPathKind>,
    /// Head motion [scene: motion.kind; default still].
    #[arg(long, value_parser = choice::<MotionKind>())]
    pub motion: Option<MotionKind>,
}

impl RunFlags {
    /// The scene file at `path` (the built-in default scene without one) with these flags and
    /// `frames` (a count sets the shot's length) applied.
    pub fn scene_file(
        &self,
        path: Option<&std::path::Path>,
        frames: Option<FramesArg>,
    ) -> anyhow::Result<hairlod::scene_file::SceneFile> {
        let mut file = ShotOverrides {
            preset: self.preset,
            frames: match frames {
                Some(FramesArg::Count(count)) => Some(count),
                _ => None,
            },
            level: self.level,
            pixel_tolerance: self.pixel_tolerance,
            size: self.size.as_ref(),
            camera: self.camera,
            motion: self.motion,
        }
        .scene_file(path)?;
        if let Some(drawn_as) = self.drawn_as {
            file.lod.drawn_as = Some(drawn_as);
        }
        Ok(file)
    }
}
