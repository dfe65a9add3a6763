//! The constants of the lane-parallel position-based step, laid out once per model in lane form
//! (one batch of [`LANES`] chains per block, one [`LaneNode`] per node), so that a step loads them
//! as vectors instead of gathering them chain by chain and dividing by every mass.

use glam::{Mat3, Vec3};

use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::dynamics::model::DynamicsModel;

/// The longest chain (in nodes) the lane-parallel step takes.
pub(crate) const MAX_LANE_NODES: usize = 64;

/// The constants of one node of every lane of a batch.
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

/// The roots of a batch in head space: positions [m] and frames.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LaneRoots {
    pub position: LaneVec3,
    pub normal: LaneVec3,
    pub binormal: LaneVec3,
    pub tangent: LaneVec3,
}

/// Where a batch's constants are.
#[derive(Debug, Clone, Copy)]
struct LaneBatch {
    /// First entry in [`LaneModel::nodes`].
    first_node: usize,
    /// Nodes per chain.
    nodes: usize,
}

/// The lane-form constants of every batch `LANES·k .. LANES·(k + 1)` whose chains have the same
/// node count (2 to [`MAX_LANE_NODES`]); lanes past a model's last chain repeat it.
#[derive(Debug, Clone, Default)]
pub(crate) struct LaneModel {
    /// Per batch, `None` where the lanes cannot step it.
    batches: Vec<Option<LaneBatch>>,
    /// Per batch.
    roots: Vec<LaneRoots>,
    nodes: Vec<LaneNode>,
}

impl LaneModel {
    /// Lays out the constants of `model`.
    pub(crate) fn new(model: &DynamicsModel) -> Self {
        let rest = &model.rest;
        let chain_count = rest.chain_count();
        let batch_count = chain_count.div_ceil(LANES);
        let mut lane_model = LaneModel {
            batches: Vec::with_capacity(batch_count),
            roots: Vec::with_capacity(batch_count),
            nodes: Vec::new(),
        };
        for batch in 0..batch_count {
            let first_chain = batch * LANES;
            let end_chain = (first_chain + LANES).min(chain_count);
            let n = rest.chain_node_count(first_chain);
            let mut roots = LaneRoots::default();
            let lane_able = (2..=MAX_LANE_NODES).contains(&n)
                && (first_chain..end_chain).all(|c| rest.chain_node_count(c) == n);
            if !lane_able {
                lane_model.batches.push(None);
                lane_model.roots.push(roots);
                continue;
            }
            let first_node = lane_model.nodes.len();
            lane_model.nodes.resize(first_node + n, LaneNode::default());
            for lane in 0..LANES {
                let chain = (first_chain + lane).min(end_chain - 1);
                let frame = rest.root_frames[chain];
                roots.position.set(lane, rest.root_positions[chain]);
                roots.normal.set(lane, frame.normal);
                roots.binormal.set(lane, frame.binormal);
                roots.tangent.set(lane, frame.tangent);
                let global = rest.offsets[chain] as usize;
                for (i, node) in lane_model.nodes[first_node..first_node + n]
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
            lane_model.batches.push(Some(LaneBatch {
                first_node,
                nodes: n,
            }));
            lane_model.roots.push(roots);
        }
        lane_model
    }

    /// The nodes and roots of the batch starting at chain `first_chain`, if the lanes can step it.
    pub(crate) fn batch(&self, first_chain: usize) -> Option<(&[LaneNode], &LaneRoots)> {
        let index = first_chain / LANES;
        let batch = (*self.batches.get(index)?)?;
        Some((
            &self.nodes[batch.first_node..batch.first_node + batch.nodes],
            &self.roots[index],
        ))
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
