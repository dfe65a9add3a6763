//! How far each coarse level of a section is from the strands it stands for [m], measured once
//! on the groom at rest: the geometric half of error-driven level selection (the selector scales
//! it by the pixels a metre covers at the section's depth, see
//! [`LodSelector`](super::LodSelector)).
//!
//! For a section and a coarse level (one patch, or three clusters), two one-sided distances over
//! the shapes as drawn:
//!
//! - **strands → level**: each strand sample's distance to the level's shape, the patch's ruled
//!   strip (zero thickness) or the cluster tubes taken as solids (a strand inside a tube is
//!   covered by it; the drawn tube's radius is [`DRAWN_TUBE_RADIUS`] of the control radius);
//! - **level → strands**: each vertex of the level's tessellated surface to the nearest strand
//!   sample (a tube that bulges where there is no hair, a strip that spans a gap).
//!
//! The deviation is the larger of their [`DEVIATION_PERCENTILE`] percentiles: a Hausdorff distance
//! that a few stray strands do not decide. Strand groups have no deviation (they are the
//! reference). The strands are taken as drawn: each ends at its length and its offset shrinks
//! towards the tip by its tip scale (applied at the control points). Strand samples lie
//! `1/SAMPLES_PER_SEGMENT` of a skeleton segment apart, so the level → strands side
//! over-estimates by at most half that spacing where it runs along a strand.

mod grid;
mod shapes;

use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::frame::Frame;
use crate::groom::Groom;
use crate::level::Level;
use crate::representation::geometry::{cluster_surface, patch_control_grid, strand_sampler};
use crate::representation::{cluster_radius_at, strand_control_points};
use crate::transform::RigidTransform;

pub use grid::PointGrid;
use shapes::{Pieces, Strip, Tube};

/// The percentile of the one-sided distances taken as a level's deviation.
pub const DEVIATION_PERCENTILE: f32 = 0.9;

/// Curve samples per skeleton segment, for strands and for the coarse shapes along the hair.
pub const SAMPLES_PER_SEGMENT: usize = 4;

/// Drawn radius of a cluster tube over its control radius: a periodic cubic B-spline through 4
/// points on a circle of radius `r` stays between `0.648 r` and `2r/3` of the axis (see
/// [`cluster_control_points`](crate::representation::cluster_control_points)); the mean.
pub const DRAWN_TUBE_RADIUS: f32 = 0.657;

/// Columns around a cluster tube when its surface is sampled.
const AROUND: usize = 8;

/// At most this many strands of a strand group are measured against the coarse shapes (every
/// k-th strand); all of them are searched from the shapes.
const MEASURED_STRANDS_PER_GROUP: usize = 16;

/// The deviations [m] of one section's coarse levels from its strands.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct LevelDeviation {
    /// The patch's deviation [m].
    pub patch: f32,
    /// The clusters' deviation [m].
    pub cluster: f32,
}

impl LevelDeviation {
    /// The deviation [m] of `level` (0 for strand groups).
    pub fn at(&self, level: Level) -> f32 {
        match level {
            Level::Patch => self.patch,
            Level::Cluster => self.cluster,
            Level::StrandGroup => 0.0,
        }
    }
}

/// The deviation of every section of `groom` at rest (head at the identity), in parallel over
/// sections (deterministic).
pub fn level_deviations(groom: &Groom) -> Result<Vec<LevelDeviation>> {
    let (positions, frames) = groom.skeletons.rest_pose(&RigidTransform::IDENTITY);
    level_deviations_at(groom, &positions, &frames)
}

/// The deviation of every section of `groom` with its skeletons at `positions` [m] with node
/// frames `frames` (one per node of every chain, all levels).
pub fn level_deviations_at(
    groom: &Groom,
    positions: &[Vec3],
    frames: &[Frame],
) -> Result<Vec<LevelDeviation>> {
    (0..groom.section_count())
        .into_par_iter()
        .map(|section| section_deviation(groom, section, positions, frames))
        .collect()
}

/// One section's deviations.
fn section_deviation(
    groom: &Groom,
    section: usize,
    positions: &[Vec3],
    frames: &[Frame],
) -> Result<LevelDeviation> {
    let (all, measured) = strand_samples(groom, section, positions, frames)?;
    if all.is_empty() {
        return Ok(LevelDeviation::default());
    }
    let cell = (0.125 * groom.sections[section].width).max(1e-4);
    let grid = PointGrid::new(&all, cell);
    let to_strands = |vertices: &[Vec3]| -> Vec<f32> {
        vertices
            .iter()
            .filter_map(|&v| grid.nearest_distance(v))
            .collect()
    };

    // The patch: its strip's two edges sampled along the hair.
    let mut strip_rows = Vec::new();
    let mut strip_vertices = Vec::new();
    for chain in groom.section_chains(section, Level::Patch) {
        let grid_points = patch_control_grid(groom, positions, frames, chain);
        let left: Vec<Vec3> = grid_points.iter().step_by(2).copied().collect();
        let right: Vec<Vec3> = grid_points.iter().skip(1).step_by(2).copied().collect();
        let (left, right) = (sample_curve(&left)?, sample_curve(&right)?);
        // The strip's vertices, three across (edges and middle).
        for (&l, &r) in left.iter().zip(&right) {
            strip_vertices.extend([l, 0.5 * (l + r), r]);
        }
        strip_rows.push(Strip::new(left, right));
    }
    // A strand sample's nearest piece is most likely the one at the same place along the hair.
    let from_strands: Vec<f32> = measured
        .iter()
        .map(|&(p, hint)| {
            strip_rows
                .iter()
                .map(|strip| strip.distance(p, hint))
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    let patch = percentile(from_strands).max(percentile(to_strands(&strip_vertices)));

    // The clusters: tubes as solids around their axes.
    let mut tubes = Vec::new();
    let mut tube_vertices = Vec::new();
    for chain in groom.section_chains(section, Level::Cluster) {
        let nodes = groom.skeletons.nodes(chain);
        let count = nodes.len();
        let cluster = chain - groom.level_chains(Level::Cluster).start;
        let (root, tip) = (
            groom.cluster_root_radii[cluster],
            groom.cluster_tip_radii[cluster],
        );
        let axis = sample_curve(&positions[nodes])?;
        let radii: Vec<f32> = (0..axis.len())
            .map(|k| {
                let node = k as f32 / SAMPLES_PER_SEGMENT as f32;
                let (below, t) = (node.floor() as usize, node.fract());
                let r0 = cluster_radius_at(below, count, root, tip);
                let r1 = cluster_radius_at((below + 1).min(count - 1), count, root, tip);
                DRAWN_TUBE_RADIUS * (r0 + (r1 - r0) * t)
            })
            .collect();
        let rows = SAMPLES_PER_SEGMENT * (count - 1);
        let surface = cluster_surface(groom, positions, frames, chain)?.tessellate(AROUND, rows)?;
        tube_vertices.extend_from_slice(&surface.positions);
        tubes.push(Tube::new(axis, radii));
    }
    let from_strands: Vec<f32> = measured
        .iter()
        .map(|&(p, hint)| {
            tubes
                .iter()
                .map(|tube| tube.distance(p, hint))
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    let cluster = percentile(from_strands).max(percentile(to_strands(&tube_vertices)));
    Ok(LevelDeviation { patch, cluster })
}

/// A strand sample [m] and its index along its strand.
type IndexedSample = (Vec3, usize);

/// The section's strand samples as drawn: all of them, and those of every k-th strand (at most
/// [`MEASURED_STRANDS_PER_GROUP`] per group) with their index along the strand (where the nearest
/// piece of a coarse shape most likely is).
fn strand_samples(
    groom: &Groom,
    section: usize,
    positions: &[Vec3],
    frames: &[Frame],
) -> Result<(Vec<Vec3>, Vec<IndexedSample>)> {
    let first_group = groom.level_chains(Level::StrandGroup).start;
    let (mut all, mut measured) = (Vec::new(), Vec::new());
    let mut control = Vec::new();
    let mut curve = Vec::new();
    for chain in groom.section_chains(section, Level::StrandGroup) {
        let nodes = groom.skeletons.nodes(chain);
        let sampler = strand_sampler(nodes.len(), SAMPLES_PER_SEGMENT)?;
        control.resize(nodes.len(), Vec3::ZERO);
        curve.resize(sampler.sample_count(), Vec3::ZERO);
        let strands = groom.strands.strands(chain - first_group);
        let stride = strands.len().div_ceil(MEASURED_STRANDS_PER_GROUP).max(1);
        for (index, strand) in strands.enumerate() {
            // The strand as drawn: its offset shrinks towards the tip by its tip scale, and it
            // ends at its length (a fraction of the curve parameter).
            let offset = groom.strands.root_offsets[strand];
            let (tip, length) = (
                groom.strands.tip_scale(strand),
                groom.strands.length(strand),
            );
            strand_control_points(
                &positions[nodes.clone()],
                &frames[nodes.clone()],
                offset,
                &mut control,
            );
            let last = control.len().saturating_sub(1).max(1) as f32;
            for (k, (point, &node)) in control
                .iter_mut()
                .zip(&positions[nodes.clone()])
                .enumerate()
            {
                let scale = 1.0 + (tip - 1.0) * k as f32 / last;
                *point = node + (*point - node) * scale;
            }
            sampler.evaluate(&control, &mut curve, None)?;
            let drawn = curve
                .iter()
                .zip(sampler.parameters())
                .filter(|&(_, &u)| u <= length + 1e-6)
                .map(|(&p, _)| p);
            all.extend(drawn.clone());
            if index % stride == 0 {
                measured.extend(drawn.enumerate().map(|(k, p)| (p, k)));
            }
        }
    }
    Ok((all, measured))
}

/// The clamped uniform B-spline with control points `control` [m], sampled
/// [`SAMPLES_PER_SEGMENT`] times per control segment.
fn sample_curve(control: &[Vec3]) -> Result<Vec<Vec3>> {
    let sampler = strand_sampler(control.len(), SAMPLES_PER_SEGMENT)?;
    let mut curve = vec![Vec3::ZERO; sampler.sample_count()];
    sampler.evaluate(control, &mut curve, None)?;
    Ok(curve)
}

/// The [`DEVIATION_PERCENTILE`] percentile of `values` (0 when empty).
fn percentile(mut values: Vec<f32>) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f32::total_cmp);
    let rank = (DEVIATION_PERCENTILE * values.len() as f32).ceil() as usize;
    values[rank.clamp(1, values.len()) - 1]
}
