//! Whole-groom geometry from skeleton state: strand polylines as drawn (precomputed basis), and the
//! NURBS surfaces and triangle meshes of clusters and patches.

use glam::Vec3;
use rayon::prelude::*;

use super::drawn::{
    ChainPoint, chain_point_at, drawn_strand_point, strand_last_point, strand_point_parameter,
};
use super::{
    CLUSTER_POINTS_PER_NODE, PATCH_POINTS_PER_NODE, cluster_control_points, patch_control_points,
};
use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::groom::Groom;
use crate::level::Level;
use crate::mesh::TriangleMesh;
use crate::nurbs::{CurveSampler, DEFAULT_DEGREE, KnotVector, NurbsSurface};

/// Many curves stored flat: curve `c` owns `points[offsets[c]..offsets[c + 1]]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Polylines {
    /// Curve points [m].
    pub points: Vec<Vec3>,
    /// `curve_count + 1` entries starting at 0.
    pub offsets: Vec<u32>,
}

impl Polylines {
    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }
}

/// The degree used for a chain of `node_count` nodes: cubic, or lower when there are too few nodes.
pub fn degree_for(node_count: usize) -> usize {
    DEFAULT_DEGREE.min(node_count.saturating_sub(1)).max(1)
}

/// A sampler of the clamped uniform B-spline over `node_count` control points, with
/// `samples_per_segment` samples per skeleton segment (`samples_per_segment · (n − 1) + 1` in all,
/// both ends included).
pub fn strand_sampler(node_count: usize, samples_per_segment: usize) -> Result<CurveSampler> {
    if samples_per_segment == 0 {
        return Err(HairError::invalid(
            "samples per segment",
            0,
            "at least 1 sample per skeleton segment",
        ));
    }
    let knots = KnotVector::clamped_uniform(node_count, degree_for(node_count))?;
    CurveSampler::new(&knots, samples_per_segment * (node_count - 1) + 1)
}

/// Every strand of `groom` as drawn (see [`super::drawn`]: its own length, tapered root offset
/// and residual profile) on the strand-group skeletons' node positions and frames (one per node,
/// all chains), each skeleton curve tessellated into `samples_per_segment` steps per segment: a
/// strand's polyline is the tessellation points up to its length and its exact end. Parallel over
/// strand groups, deterministic.
///
/// Errors: `samples_per_segment` 0; node arrays shorter than the groom's nodes; a strand-group
/// skeleton with fewer than two nodes; residual profiles that fail
/// [`StrandSet::check_profiles`](crate::StrandSet::check_profiles).
pub fn strand_polylines(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    samples_per_segment: usize,
) -> Result<Polylines> {
    check_node_arrays(groom, node_positions, node_frames)?;
    groom.strands.check_profiles()?;
    let group_chains = groom.level_chains(Level::StrandGroup);
    let strands = &groom.strands;
    let per_group = group_chains
        .clone()
        .into_par_iter()
        .map(|chain| -> Result<(Vec<Vec3>, Vec<u32>)> {
            let nodes = groom.skeletons.nodes(chain);
            let sampler = strand_sampler(nodes.len(), samples_per_segment)?;
            let samples = chain_samples(
                &sampler,
                &node_positions[nodes.clone()],
                &node_frames[nodes],
            )?;
            let segments = samples.len() - 1;
            let group = chain - group_chains.start;
            let mut points = Vec::new();
            let mut counts = Vec::with_capacity(strands.strands(group).len());
            for strand in strands.strands(group) {
                let length = strands.length(strand);
                let last = strand_last_point(length, segments);
                for point in 0..=last {
                    let u = strand_point_parameter(point, segments, length);
                    points.push(drawn_strand_point(
                        &chain_point_at(&samples, u),
                        u,
                        length,
                        strands.root_offsets[strand],
                        strands.tip_scale(strand),
                        strands.profile(strand),
                    ));
                }
                counts.push(last as u32 + 1);
            }
            Ok((points, counts))
        })
        .collect::<Result<Vec<_>>>()?;
    let mut lines = Polylines {
        points: Vec::with_capacity(per_group.iter().map(|(p, _)| p.len()).sum()),
        offsets: Vec::with_capacity(strands.strand_count() + 1),
    };
    lines.offsets.push(0);
    for (points, counts) in per_group {
        lines.points.extend_from_slice(&points);
        for count in counts {
            let end = lines.offsets[lines.offsets.len() - 1] + count;
            lines.offsets.push(end);
        }
    }
    Ok(lines)
}

/// Checks that node positions and frames cover every node of `groom` (a size mismatch naming
/// the array that falls short).
pub(crate) fn check_node_arrays(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
) -> Result<()> {
    let node_count = groom.skeletons.node_count();
    for (what, actual) in [
        ("node positions", node_positions.len()),
        ("node frames", node_frames.len()),
    ] {
        if actual < node_count {
            return Err(HairError::SizeMismatch {
                what,
                actual,
                expected: node_count,
            });
        }
    }
    Ok(())
}

/// A skeleton's curve and frame curves at the sampler's parameters, from its nodes' positions
/// and frames (the renderer's chain-curve pass computes the same).
pub fn chain_samples(
    sampler: &CurveSampler,
    node_positions: &[Vec3],
    node_frames: &[Frame],
) -> Result<Vec<ChainPoint>> {
    let count = sampler.sample_count();
    let mut position = vec![Vec3::ZERO; count];
    let mut derivative = vec![Vec3::ZERO; count];
    let mut normal = vec![Vec3::ZERO; count];
    let mut binormal = vec![Vec3::ZERO; count];
    sampler.evaluate(node_positions, &mut position, Some(&mut derivative))?;
    let normals: Vec<Vec3> = node_frames.iter().map(|f| f.normal).collect();
    let binormals: Vec<Vec3> = node_frames.iter().map(|f| f.binormal).collect();
    sampler.evaluate(&normals, &mut normal, None)?;
    sampler.evaluate(&binormals, &mut binormal, None)?;
    Ok((0..count)
        .map(|k| ChainPoint {
            position: position[k],
            normal: normal[k],
            binormal: binormal[k],
            derivative: derivative[k],
        })
        .collect())
}

/// The `4n` control points of cluster chain `chain` (node-major, 4 around each node).
pub fn cluster_control_grid(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    chain: usize,
) -> Vec<Vec3> {
    let nodes = groom.skeletons.nodes(chain);
    let cluster = chain - groom.level_chains(Level::Cluster).start;
    let mut points = vec![Vec3::ZERO; CLUSTER_POINTS_PER_NODE * nodes.len()];
    cluster_control_points(
        &node_positions[nodes.clone()],
        &node_frames[nodes],
        groom.cluster_root_radii[cluster],
        groom.cluster_tip_radii[cluster],
        &mut points,
    );
    points
}

/// The `2n` control points of patch chain `chain` (node-major, 2 across each node).
pub fn patch_control_grid(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    chain: usize,
) -> Vec<Vec3> {
    let nodes = groom.skeletons.nodes(chain);
    let patch = chain - groom.level_chains(Level::Patch).start;
    let mut points = vec![Vec3::ZERO; PATCH_POINTS_PER_NODE * nodes.len()];
    patch_control_points(
        &node_positions[nodes.clone()],
        &node_frames[nodes],
        groom.patch_widths[patch],
        &mut points,
    );
    points
}

/// The closed tube of cluster chain `chain`: periodic cubic around (4 control points), clamped
/// along the hair.
pub fn cluster_surface(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    chain: usize,
) -> Result<NurbsSurface> {
    let node_count = groom.skeletons.chain_node_count(chain);
    let around = KnotVector::periodic_uniform(CLUSTER_POINTS_PER_NODE, DEFAULT_DEGREE)?;
    let along = KnotVector::clamped_uniform(node_count, degree_for(node_count))?;
    NurbsSurface::new(
        around,
        along,
        cluster_control_grid(groom, node_positions, node_frames, chain),
    )
}

/// The strip of patch chain `chain`: linear across (2 control points), clamped along the hair.
pub fn patch_surface(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    chain: usize,
) -> Result<NurbsSurface> {
    let node_count = groom.skeletons.chain_node_count(chain);
    let across = KnotVector::clamped_uniform(PATCH_POINTS_PER_NODE, 1)?;
    let along = KnotVector::clamped_uniform(node_count, degree_for(node_count))?;
    NurbsSurface::new(
        across,
        along,
        patch_control_grid(groom, node_positions, node_frames, chain),
    )
}

/// All clusters or all patches of `groom` tessellated into one mesh: `samples_per_segment` rows
/// per skeleton segment along the hair, `around` columns around a cluster (1 across a patch).
/// Strand groups have no surface: asking for them is an error.
pub fn level_mesh(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    level: Level,
    samples_per_segment: usize,
    around: usize,
) -> Result<TriangleMesh> {
    if samples_per_segment == 0 || around < 3 {
        return Err(HairError::invalid(
            "tessellation",
            format!("{samples_per_segment} rows per segment, {around} around"),
            "at least 1 row per segment and 3 around",
        ));
    }
    let surfaces = groom
        .level_chains(level)
        .into_par_iter()
        .map(|chain| {
            let rows = samples_per_segment * (groom.skeletons.chain_node_count(chain) - 1);
            match level {
                Level::Cluster => cluster_surface(groom, node_positions, node_frames, chain)?
                    .tessellate(around, rows),
                Level::Patch => {
                    patch_surface(groom, node_positions, node_frames, chain)?.tessellate(1, rows)
                }
                Level::StrandGroup => Err(HairError::invalid(
                    "level",
                    level,
                    "clusters or patches (strands are curves, not surfaces)",
                )),
            }
        })
        .collect::<Result<Vec<TriangleMesh>>>()?;
    let mut merged = TriangleMesh::default();
    for mesh in surfaces {
        let base = merged.positions.len() as u32;
        merged.positions.extend_from_slice(&mesh.positions);
        merged.normals.extend_from_slice(&mesh.normals);
        merged
            .triangles
            .extend(mesh.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    Ok(merged)
}
