//! OBJ export of a scene: the head and one level of the groom (strands as `l` polylines, clusters and
//! patches tessellated to triangles), written atomically.

use std::io::Write;
use std::path::Path;

use glam::Vec3;

use crate::obj::{ObjWriter, write_file_atomically};
use hair_core::error::{HairError, Result};
use hair_core::frame::Frame;
use hair_core::level::Level;
use hair_core::representation::geometry::{level_mesh, strand_polylines};
use hair_core::scene::Scene;
use hair_core::transform::RigidTransform;

/// What to export and how finely.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportOptions {
    /// The level drawn for every section.
    pub level: Level,
    /// Curve samples (strands) or surface rows (clusters, patches) per skeleton segment, ≥ 1.
    pub samples_per_segment: usize,
    /// Columns around a cluster tube, ≥ 3.
    pub cluster_sides: usize,
    /// Write the head mesh as its own object first.
    pub include_head: bool,
    /// The head's pose (the hair is exported at rest on the posed head).
    pub head_pose: RigidTransform,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            level: Level::StrandGroup,
            samples_per_segment: 4,
            cluster_sides: 8,
            include_head: true,
            head_pose: RigidTransform::IDENTITY,
        }
    }
}

/// What an export wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ExportSummary {
    /// Hair items exported (strands, clusters or patches).
    pub items: usize,
    /// `v` lines over the whole file.
    pub vertices: usize,
    /// `f` lines (triangles) over the whole file.
    pub triangles: usize,
    /// `l` lines (strand polylines).
    pub polylines: usize,
}

/// Writes the scene at rest (head posed by `options.head_pose`) to `path` as OBJ, atomically: a
/// stopped run leaves either the old file or none, never half of one.
pub fn export_obj(path: &Path, scene: &Scene, options: &ExportOptions) -> Result<ExportSummary> {
    let positions = scene.groom.skeletons.rest_positions(&options.head_pose);
    export_obj_with_positions(path, scene, &positions, options)
}

/// Like [`export_obj`], with the skeleton node positions given (one per node of every chain, as
/// simulated).
pub fn export_obj_with_positions(
    path: &Path,
    scene: &Scene,
    node_positions: &[Vec3],
    options: &ExportOptions,
) -> Result<ExportSummary> {
    let mut summary = ExportSummary::default();
    write_file_atomically(path, |file| {
        summary = write_obj(file, scene, node_positions, options)
            .map_err(|error| std::io::Error::other(error.to_string()))?;
        Ok(())
    })
    .map_err(|error| HairError::io("writing", path, &error))?;
    Ok(summary)
}

/// Writes the OBJ text to any writer; see [`export_obj`].
pub fn write_obj<W: Write>(
    writer: W,
    scene: &Scene,
    node_positions: &[Vec3],
    options: &ExportOptions,
) -> Result<ExportSummary> {
    let groom = &scene.groom;
    if node_positions.len() != groom.skeletons.node_count() {
        return Err(HairError::SizeMismatch {
            what: "node positions",
            actual: node_positions.len(),
            expected: groom.skeletons.node_count(),
        });
    }
    if let Some(node) = node_positions.iter().position(|p| !p.is_finite()) {
        return Err(HairError::invalid(
            "node position",
            format!("{:?} at node {node}", node_positions[node]),
            "finite coordinates [m]",
        ));
    }
    let mut frames = vec![Frame::default(); node_positions.len()];
    groom
        .skeletons
        .node_frames_into(&options.head_pose, node_positions, &mut frames);
    let io = |error: std::io::Error| HairError::Io {
        action: "writing",
        path: "OBJ stream".to_string(),
        message: error.to_string(),
    };
    let mut obj = ObjWriter::new(writer);
    let mut summary = ExportSummary::default();
    if options.include_head {
        let mut head = scene.head.mesh.clone();
        for p in &mut head.positions {
            *p = options.head_pose.transform_point(*p);
        }
        for n in &mut head.normals {
            *n = options.head_pose.transform_vector(*n);
        }
        obj.object("head").map_err(io)?;
        obj.mesh(&head).map_err(io)?;
        summary.vertices += head.vertex_count();
        summary.triangles += head.triangle_count();
    }
    obj.object(options.level.name()).map_err(io)?;
    match options.level {
        Level::StrandGroup => {
            let curves =
                strand_polylines(groom, node_positions, &frames, options.samples_per_segment)?;
            obj.polylines_flat(&curves.points, &curves.offsets)
                .map_err(io)?;
            summary.items = curves.curve_count();
            summary.polylines = curves.curve_count();
            summary.vertices += curves.points.len();
        }
        level => {
            let mesh = level_mesh(
                groom,
                node_positions,
                &frames,
                level,
                options.samples_per_segment,
                options.cluster_sides,
            )?;
            obj.mesh(&mesh).map_err(io)?;
            summary.items = groom.level_chains(level).len();
            summary.vertices += mesh.vertex_count();
            summary.triangles += mesh.triangle_count();
        }
    }
    obj.finish().map_err(io)?;
    Ok(summary)
}
