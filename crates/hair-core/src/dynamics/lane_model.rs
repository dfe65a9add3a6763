//! The constants of the lane steps (position-based and XPBD), laid out once per model in lane
//! form, so that a step loads them as vectors instead of gathering them chain by chain and
//! dividing by every mass.
//!
//! Chains are stepped in batches of [`LANES`] consecutive chains (`LANES·k .. LANES·(k + 1)`, the
//! parallel split). A batch is cut into **runs** of consecutive chains with the same node count;
//! each run is one call of the lane kernel, its lanes past the run's last chain repeating it. A
//! groom whose chains all have the same node count has one run per batch; a chain between two of
//! other lengths is a run of one (a chain alone is a lane of one).

use glam::{Mat3, Vec3};

use crate::dynamics::error::DynamicsError;
use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::model::DynamicsModel;
use crate::dynamics::params::IntegratorKind;

/// The longest chain (in nodes) the lane steps take: their scratch lives on the stack, up to
/// about 80 KiB for a run of 64-node chains.
pub const MAX_CHAIN_NODES: usize = 64;

/// The constants of one node of every lane of a run.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LaneNode {
    /// Rest direction in the parent frame (normal, binormal, tangent coordinates).
    pub rest_local: LaneVec3,
    /// Node mass [kg].
    pub mass: Lanes,
    /// `1/m` [1/kg].
    pub inverse_mass: Lanes,
    /// Rest length of the segment ending at this node [m] (0 at the root).
    pub rest_length: Lanes,
    /// Spring stiffness of the bend ending at this node [N·m/rad] (0 at the root).
    pub stiffness: Lanes,
}

/// The roots of a run in head space: positions [m] and frames.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LaneRoots {
    pub position: LaneVec3,
    pub normal: LaneVec3,
    pub binormal: LaneVec3,
    pub tangent: LaneVec3,
}

/// Where a run's constants are.
#[derive(Debug, Clone, Copy)]
struct RunEntry {
    first_chain: usize,
    end_chain: usize,
    /// First entry in [`LaneModel::nodes`].
    first_node: usize,
    /// Nodes per chain.
    nodes: usize,
}

/// One run of a batch: chains `first_chain..end_chain`, all of `nodes.len()` nodes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LaneRun<'a> {
    pub first_chain: usize,
    pub end_chain: usize,
    pub nodes: &'a [LaneNode],
    pub roots: &'a LaneRoots,
}

/// The lane-form constants of every run of every batch.
#[derive(Debug, Clone, Default)]
pub(crate) struct LaneModel {
    /// Per batch, the range of its runs in `runs`.
    batches: Vec<std::ops::Range<usize>>,
    runs: Vec<RunEntry>,
    /// Per run.
    roots: Vec<LaneRoots>,
    nodes: Vec<LaneNode>,
}

impl LaneModel {
    /// Lays out the constants of `model` for `integrator`; fails on a chain longer than
    /// [`MAX_CHAIN_NODES`].
    pub(crate) fn new(
        model: &DynamicsModel,
        integrator: IntegratorKind,
    ) -> Result<Self, DynamicsError> {
        let rest = &model.rest;
        let chain_count = rest.chain_count();
        if let Some(chain) = (0..chain_count).find(|&c| rest.chain_node_count(c) > MAX_CHAIN_NODES)
        {
            return Err(DynamicsError::ChainTooLong {
                chain,
                nodes: rest.chain_node_count(chain),
                limit: MAX_CHAIN_NODES,
                integrator,
            });
        }
        let mut lane_model = LaneModel::default();
        for batch in 0..chain_count.div_ceil(LANES) {
            let batch_start = batch * LANES;
            let batch_end = (batch_start + LANES).min(chain_count);
            let first_run = lane_model.runs.len();
            let mut first_chain = batch_start;
            while first_chain < batch_end {
                let n = rest.chain_node_count(first_chain);
                let end_chain = (first_chain..batch_end)
                    .find(|&c| rest.chain_node_count(c) != n)
                    .unwrap_or(batch_end);
                lane_model.push_run(model, first_chain, end_chain, n);
                first_chain = end_chain;
            }
            lane_model.batches.push(first_run..lane_model.runs.len());
        }
        Ok(lane_model)
    }

    /// Lays out the run `first_chain..end_chain` of `n`-node chains.
    fn push_run(&mut self, model: &DynamicsModel, first_chain: usize, end_chain: usize, n: usize) {
        let rest = &model.rest;
        let first_node = self.nodes.len();
        self.nodes.resize(first_node + n, LaneNode::default());
        let mut roots = LaneRoots::default();
        for lane in 0..LANES {
            let chain = (first_chain + lane).min(end_chain - 1);
            let frame = rest.root_frames[chain];
            roots.position.set(lane, rest.root_positions[chain]);
            roots.normal.set(lane, frame.normal);
            roots.binormal.set(lane, frame.binormal);
            roots.tangent.set(lane, frame.tangent);
            let global = rest.offsets[chain] as usize;
            for (i, node) in self.nodes[first_node..first_node + n]
                .iter_mut()
                .enumerate()
            {
                let mass = model.node_masses[global + i];
                node.rest_local
                    .set(lane, model.rest_local_directions[global + i]);
                node.mass.0[lane] = mass;
                node.inverse_mass.0[lane] = 1.0 / mass;
                node.rest_length.0[lane] = rest.segment_rest_lengths[global + i];
                node.stiffness.0[lane] = model.joint_stiffness[global + i];
            }
        }
        self.runs.push(RunEntry {
            first_chain,
            end_chain,
            first_node,
            nodes: n,
        });
        self.roots.push(roots);
    }

    /// The runs of the batch starting at chain `first_chain` (a multiple of [`LANES`]).
    pub(crate) fn runs(&self, first_chain: usize) -> impl Iterator<Item = LaneRun<'_>> {
        let range = self
            .batches
            .get(first_chain / LANES)
            .cloned()
            .unwrap_or(0..0);
        range.map(move |index| {
            let run = self.runs[index];
            LaneRun {
                first_chain: run.first_chain,
                end_chain: run.end_chain,
                nodes: &self.nodes[run.first_node..run.first_node + run.nodes],
                roots: &self.roots[index],
            }
        })
    }
}

/// `rotation · v` of every lane.
#[inline(always)]
pub(crate) fn rotate_lanes(rotation: &Mat3, v: &LaneVec3) -> LaneVec3 {
    let column = |c: Vec3| LaneVec3 {
        x: Lanes::splat(c.x),
        y: Lanes::splat(c.y),
        z: Lanes::splat(c.z),
    };
    column(rotation.x_axis).scale(v.x)
        + column(rotation.y_axis).scale(v.y)
        + column(rotation.z_axis).scale(v.z)
}
