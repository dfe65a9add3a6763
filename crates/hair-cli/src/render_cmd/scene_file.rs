//! The `SCENE.toml` file of `hairlod render`: a preset groom with overrides, the camera, the
//! motion and the frames. Every field is optional; command-line flags override the file.
//!
//! ```toml
//! preset = "paper-curly"          # paper-curly, straight, wavy or curly
//!
//! [groom]                         # overrides of the preset's parameters
//! section_count = 40
//! strands_per_group = 30
//! hair_length = 0.3               # [m]
//! seed = 7
//!
//! [camera]
//! path = "orbit"                  # orbit, zoom-out or fixed
//! distance = 0.9                  # [m] from the head's centre (zoom-out: the start)
//! end_distance = 3.0              # [m], zoom-out only
//! azimuth_degrees = 20            # 0 looks at the face
//! elevation_degrees = 10
//! fov_degrees = 35
//!
//! [render]
//! frames = 24
//! fps = 24                        # frame rate of the simulated motion [Hz]
//! size = "960x540"
//! level = "strands"               # strands, clusters, patches (auto: not yet)
//! color_code = false
//! side_by_side = false
//! motion = "shake"                # still (rest pose), shake or nod (simulated)
//! ```

use std::path::Path;

use anyhow::{Context, Result, bail};
use serde::Deserialize;

/// The whole file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Preset groom name.
    pub preset: Option<String>,
    /// Overrides of the preset's groom parameters.
    #[serde(default)]
    pub groom: GroomOverrides,
    /// Camera path and lens.
    #[serde(default)]
    pub camera: CameraSection,
    /// Frames, size, level and motion.
    #[serde(default)]
    pub render: RenderSection,
}

/// Overrides of [`hairlod::core::GroomParams`].
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroomOverrides {
    /// Number of sections.
    pub section_count: Option<usize>,
    /// Strands per strand group.
    pub strands_per_group: Option<usize>,
    /// Hair length [m].
    pub hair_length: Option<f32>,
    /// Random seed of strand placement and shades.
    pub seed: Option<u64>,
}

/// The `[camera]` table.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSection {
    /// `orbit`, `zoom-out` or `fixed`.
    pub path: Option<String>,
    /// Distance from the target [m].
    pub distance: Option<f32>,
    /// Final distance of `zoom-out` [m].
    pub end_distance: Option<f32>,
    /// Start azimuth [degrees] (0: looking at the face).
    pub azimuth_degrees: Option<f32>,
    /// Elevation above the horizontal [degrees].
    pub elevation_degrees: Option<f32>,
    /// Vertical field of view [degrees].
    pub fov_degrees: Option<f32>,
}

/// The `[render]` table.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderSection {
    /// Number of frames.
    pub frames: Option<u32>,
    /// Frame rate of the motion [Hz].
    pub fps: Option<f32>,
    /// Image size, `WIDTHxHEIGHT`.
    pub size: Option<String>,
    /// `strands`, `clusters`, `patches` or `auto`.
    pub level: Option<String>,
    /// Colour-code by level instead of shading.
    pub color_code: Option<bool>,
    /// Write shaded | colour-coded pairs.
    pub side_by_side: Option<bool>,
    /// `still`, `shake` or `nod`.
    pub motion: Option<String>,
}

impl SceneFile {
    /// Reads and parses `path`; errors name the file and, for syntax or unknown keys, the place.
    pub fn read(path: &Path) -> Result<SceneFile> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read scene file {}", path.display()))?;
        SceneFile::parse(&text).with_context(|| format!("bad scene file {}", path.display()))
    }

    /// Parses TOML text and checks the values that serde cannot.
    pub fn parse(text: &str) -> Result<SceneFile> {
        let file: SceneFile = toml::from_str(text)?;
        let camera = &file.camera;
        for (name, value) in [
            ("camera.distance", camera.distance),
            ("camera.end_distance", camera.end_distance),
            ("camera.fov_degrees", camera.fov_degrees),
            ("render.fps", file.render.fps),
            ("groom.hair_length", file.groom.hair_length),
        ] {
            if let Some(value) = value
                && !(value.is_finite() && value > 0.0)
            {
                bail!("{name} = {value}: expected a finite number > 0");
            }
        }
        for (name, value) in [
            ("camera.azimuth_degrees", camera.azimuth_degrees),
            ("camera.elevation_degrees", camera.elevation_degrees),
        ] {
            if let Some(value) = value
                && !value.is_finite()
            {
                bail!("{name} = {value}: expected a finite number");
            }
        }
        if let Some(fov) = camera.fov_degrees
            && fov >= 179.0
        {
            bail!("camera.fov_degrees = {fov}: expected less than 179");
        }
        Ok(file)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn documented_example_parses() {
        let text: String = include_str!("scene_file.rs")
            .lines()
            .skip_while(|line| !line.starts_with("//! ```toml"))
            .skip(1)
            .take_while(|line| !line.starts_with("//! ```"))
            .map(|line| line.trim_start_matches("//!").trim_start())
            .collect::<Vec<_>>()
            .join("\n");
        let file = SceneFile::parse(&text).unwrap();
        assert_eq!(file.preset.as_deref(), Some("paper-curly"));
        assert_eq!(file.groom.section_count, Some(40));
        assert_eq!(file.camera.path.as_deref(), Some("orbit"));
        assert_eq!(file.render.size.as_deref(), Some("960x540"));
    }

    #[test]
    fn bad_files_get_clear_errors() {
        let unknown = SceneFile::parse("[render]\nframez = 3").unwrap_err();
        assert!(format!("{unknown:#}").contains("framez"), "{unknown:#}");
        let negative = SceneFile::parse("[camera]\ndistance = -1.0").unwrap_err();
        assert!(
            negative.to_string().contains("camera.distance"),
            "{negative}"
        );
        let wrong_type = SceneFile::parse("[render]\nframes = \"many\"").unwrap_err();
        assert!(
            format!("{wrong_type:#}").contains("frames"),
            "{wrong_type:#}"
        );
        assert!(SceneFile::parse("").is_ok());
    }
}
