//! Whole-groom geometry from skeleton state: strand polylines (fast, precomputed basis), and the
//! NURBS surfaces and triangle meshes of clusters and patches.

use glam::Vec3;
use rayon::prelude::*;

use super::{
    CLUSTER_POINTS_PER_NODE, PATCH_POINTS_PER_NODE, cluster_control_points, patch_control_points,
    strand_control_points,
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

/// Evaluates every strand of `groom` into `points` (strand-major, `sampler.sample_count()` points
/// per strand) from the strand-group skeletons' node positions and frames (one per node, all
/// chains). Parallel over strand groups, deterministic, no allocation per strand.
///
/// Every strand-group skeleton must have the sampler's control-point count.
pub fn evaluate_strands(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    sampler: &CurveSampler,
    points: &mut [Vec3],
) -> Result<()> {
    let samples = sampler.sample_count();
    let expected = groom.strands.strand_count() * samples;
    if points.len() != expected {
        return Err(HairError::SizeMismatch {
            what: "strand sample buffer",
            actual: points.len(),
            expected,
        });
    }
    let group_chains = groom.level_chains(Level::StrandGroup);
    for chain in group_chains.clone() {
        let nodes = groom.skeletons.chain_node_count(chain);
        if nodes != sampler.control_point_count() {
            return Err(HairError::SizeMismatch {
                what: "strand-group skeleton nodes",
                actual: nodes,
                expected: sampler.control_point_count(),
            });
        }
    }
    // Split the output by group so each group writes its own strands.
    let mut per_group = Vec::with_capacity(group_chains.len());
    let mut rest = points;
    for group in 0..group_chains.len() {
        let count = groom.strands.strands(group).len() * samples;
        let (mine, tail) = rest.split_at_mut(count);
        per_group.push((group, mine));
        rest = tail;
    }
    per_group.into_par_iter().for_each_init(
        || vec![Vec3::ZERO; sampler.control_point_count()],
        |control_points, (group, out)| {
            let chain = group_chains.start + group;
            let nodes = groom.skeletons.nodes(chain);
            let positions = &node_positions[nodes.clone()];
            let frames = &node_frames[nodes];
            for (strand, strand_out) in groom
                .strands
                .strands(group)
                .zip(out.chunks_exact_mut(samples))
            {
                let offset = groom.strands.root_offsets[strand];
                strand_control_points(positions, frames, offset, control_points);
                // Sizes were checked above, so evaluation cannot fail.
                let _ = sampler.evaluate(control_points, strand_out, None);
            }
        },
    );
    Ok(())
}

/// Every strand of `groom` as a polyline with `samples_per_segment` samples per skeleton segment.
pub fn strand_polylines(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
    samples_per_segment: usize,
) -> Result<Polylines> {
    let Some(first) = groom.level_chains(Level::StrandGroup).next() else {
        return Ok(Polylines {
            points: Vec::new(),
            offsets: vec![0],
        });
    };
    let sampler = strand_sampler(groom.skeletons.chain_node_count(first), samples_per_segment)?;
    let samples = sampler.sample_count();
    let mut points = vec![Vec3::ZERO; groom.strands.strand_count() * samples];
    evaluate_strands(groom, node_positions, node_frames, &sampler, &mut points)?;
    let offsets = (0..=groom.strands.strand_count())
        .map(|strand| (strand * samples) as u32)
        .collect();
    Ok(Polylines { points, offsets })
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
