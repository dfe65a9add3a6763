//! The groom and body files a scene names (`[groom] file`, `[body] file`): their paths resolved
//! against the scene file's folder and checked to exist, their units and axes, and the fit's
//! section count, as [`GroomFile`] and [`BodyFile`]. Reading them is
//! [`Shot::build_scene`](crate::Shot::build_scene)'s work; every error here names the field.

use hair_core::fit::SectionCount;

use hair_formats::UpAxis;

use super::checks::{count, positive, within};
use super::choices::BodyKind;
use super::{SceneFile, SceneFileError};
use crate::loaded::{BodyFile, FileAxes, GroomFile};

type Result<T> = std::result::Result<T, SceneFileError>;

/// The keys that shape a generated groom, refused beside `groom.file` (the file gives the strands).
const GENERATED_ONLY: [&str; 4] = [
    "strands_per_group",
    "hair_length",
    "style_factor_degrees",
    "style_size",
];

/// `table.scale`, `table.up_axis`, `table.mirror` as axes; errors name `{table}.{key}`.
fn axes(
    table: &str,
    scale: Option<f32>,
    up: Option<UpAxis>,
    mirror: Option<bool>,
) -> Result<FileAxes> {
    let scale_to_metres = positive(&format!("{table}.scale"), scale.unwrap_or(1.0))?;
    Ok(FileAxes {
        scale_to_metres,
        z_up: up == Some(UpAxis::Z),
        mirror_x: mirror.unwrap_or(false),
    })
}

impl SceneFile {
    /// The file `value` of `field` resolved against the scene file's folder, checked to be a
    /// file.
    fn existing_file(&self, field: &str, value: &str) -> Result<std::path::PathBuf> {
        let path = self.resolve_path(value);
        if path.is_file() {
            Ok(path)
        } else if path.is_dir() {
            Err(SceneFileError::new(format!(
                "{field} = {value:?}: {} is a folder, not a file",
                path.display()
            )))
        } else {
            Err(SceneFileError::new(format!(
                "{field} = {value:?}: no such file {}{}",
                path.display(),
                if self.base_dir.is_some() {
                    " (relative paths start at the scene file's folder)"
                } else {
                    ""
                }
            )))
        }
    }

    /// `[groom] file` and its settings, or `None` (a generated groom; the file-only keys are
    /// then errors).
    pub(super) fn groom_file(&self) -> Result<Option<GroomFile>> {
        let table = &self.groom;
        let Some(file) = &table.file else {
            let file_only = [
                ("scale", table.scale.is_some()),
                ("up_axis", table.up_axis.is_some()),
                ("mirror", table.mirror.is_some()),
                ("strands_per_section", table.strands_per_section.is_some()),
                ("section_size_slack", table.section_size_slack.is_some()),
                ("children_per_strand", table.children_per_strand.is_some()),
                ("child_spread", table.child_spread.is_some()),
                ("child_clump", table.child_clump.is_some()),
            ];
            if let Some((key, _)) = file_only.iter().find(|(_, given)| *given) {
                return Err(SceneFileError::new(format!(
                    "groom.{key}: only read with groom.file (a groom read from a file)"
                )));
            }
            return Ok(None);
        };
        let generated = [
            table.strands_per_group.is_some(),
            table.hair_length.is_some(),
            table.style_factor_degrees.is_some(),
            table.style_size.is_some(),
        ];
        if let Some(k) = generated.iter().position(|&given| given) {
            return Err(SceneFileError::new(format!(
                "groom.{}: not used with groom.file (the file gives the strands; groom.preset \
                 gives their material)",
                GENERATED_ONLY[k]
            )));
        }
        let names = file.paths();
        if names.is_empty() {
            return Err(SceneFileError::new(
                "groom.file = []: expected a file or a list of at least one",
            ));
        }
        let paths = names
            .iter()
            .map(|name| self.existing_file("groom.file", name))
            .collect::<Result<Vec<_>>>()?;
        let mut groom = GroomFile::new(paths);
        groom.axes = axes("groom", table.scale, table.up_axis, table.mirror)?;
        groom.sections = match (table.section_count, table.strands_per_section) {
            (Some(_), Some(_)) => {
                return Err(SceneFileError::new(
                    "groom.section_count and groom.strands_per_section: give one of them",
                ));
            }
            (Some(n), None) => SectionCount::Fixed(count("groom.section_count", n, 1, 10_000)?),
            (None, Some(n)) => {
                SectionCount::StrandsPerSection(count("groom.strands_per_section", n, 1, 100_000)?)
            }
            (None, None) => groom.sections,
        };
        if let Some(v) = table.smoothness {
            groom.max_segment_length = positive("groom.smoothness", v)?;
        }
        if let Some(seed) = table.seed {
            groom.seed = seed;
        }
        if let Some(v) = table.section_size_slack {
            groom.section_size_slack = within(
                "groom.section_size_slack",
                v,
                0.0,
                10.0,
                "a fraction in 0..=10",
            )?;
        }
        if let Some(n) = table.children_per_strand {
            groom.children.per_strand = count("groom.children_per_strand", n, 0, 1000)?;
            groom.auto_children = false;
        }
        if let Some(v) = table.child_spread {
            groom.children.spread = within("groom.child_spread", v, 0.0, 1.0, "metres in 0..=1")?;
            groom.auto_child_spread = false;
        }
        if let Some(v) = table.child_clump {
            groom.children.clump = within("groom.child_clump", v, 0.0, 1.0, "a fraction in 0..=1")?;
        }
        Ok(Some(groom))
    }

    /// `[body] file` and its settings, or `None` (the procedural head).
    pub(super) fn body_file(&self, groom_file: bool) -> Result<Option<BodyFile>> {
        let table = &self.body;
        let kind = table.kind.unwrap_or(if table.file.is_some() {
            BodyKind::Mesh
        } else {
            BodyKind::ProceduralHead
        });
        let Some(file) = &table.file else {
            if kind == BodyKind::Mesh {
                return Err(SceneFileError::new(
                    "body.kind = \"mesh\": needs body.file, the mesh to read",
                ));
            }
            if table.scale.is_some() || table.up_axis.is_some() || table.mirror.is_some() {
                return Err(SceneFileError::new(
                    "body.scale, body.up_axis and body.mirror: only read with body.file",
                ));
            }
            return Ok(None);
        };
        if kind != BodyKind::Mesh {
            return Err(SceneFileError::new(format!(
                "body.kind = \"{kind}\": body.file = {file:?} is a mesh; leave body.kind out or \
                 set it to \"mesh\""
            )));
        }
        if !groom_file {
            return Err(SceneFileError::new(format!(
                "body.file = {file:?}: needs groom.file (the preset grooms grow on the \
                 procedural head)"
            )));
        }
        let path = self.existing_file("body.file", file)?;
        let axes = axes("body", table.scale, table.up_axis, table.mirror)?;
        Ok(Some(BodyFile {
            path,
            axes,
            seconds: None,
        }))
    }
}
