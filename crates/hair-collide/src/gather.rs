//! The active chains' geometry, gathered contiguously from the simulation state and brought into
//! head space (the bodies' own frame): node positions, node frames and the cluster/patch control
//! points the segment volumes enclose.
//!
//! Memory is sized once per layout; [`ActiveHair::gather`] only writes into it.

use std::ops::Range;

use glam::Vec3;
use hair_core::representation::{cluster_control_points, patch_control_points};
use hair_core::skeleton::node_frames;
use hair_core::{Frame, RigidTransform, SkeletonRest};

use crate::bvh::ChainVolume;
use crate::chain_blocks::{ChainSlice, for_chain_blocks};
use crate::error::{CollideError, Result, require_len};
use crate::layout::{ChainShape, CollisionChain};

/// The active chains' layout and gathered geometry.
#[derive(Debug, Default)]
pub(crate) struct ActiveHair {
    /// The layout it was sized for.
    pub chains: Vec<CollisionChain>,
    /// Gathered node offsets (chain count + 1).
    pub chain_offsets: Vec<u32>,
    /// Volume kind per active chain.
    pub chain_volumes: Vec<ChainVolume>,
    /// Per gathered node, its index in the simulation state.
    pub model_nodes: Vec<u32>,
    /// Per gathered node, its mass \[kg\] (filled by the solver from the dynamics model).
    pub masses: Vec<f32>,
    /// Per gathered node, whether it is the first node (root) of its chain.
    pub is_root: Vec<bool>,
    /// Gathered node positions \[m\].
    pub positions: Vec<Vec3>,
    /// Gathered node frames (computed for clusters and patches only, whose control points
    /// follow them; a strand group's entries are left as they are).
    pub frames: Vec<Frame>,
    /// Control points \[m\] of clusters (4 per node) and patches (2 per node), chain order.
    pub control_points: Vec<Vec3>,
    /// Per chain, where its control points start (chain count + 1).
    pub control_offsets: Vec<u32>,
}

impl ActiveHair {
    /// Sizes everything for `chains` of `rest`; errors on an unknown chain, a chain listed twice
    /// or bad shape sizes.
    pub fn set_layout(&mut self, rest: &SkeletonRest, chains: &[CollisionChain]) -> Result<()> {
        let mut seen = vec![false; rest.chain_count()];
        for (index, chain) in chains.iter().enumerate() {
            let id = chain.chain as usize;
            if id >= rest.chain_count() {
                return Err(CollideError::InvalidParameter {
                    name: "collision chain",
                    value: format!("{id} (entry {index})"),
                    allowed: "a chain index of the simulated skeletons",
                });
            }
            if std::mem::replace(&mut seen[id], true) {
                return Err(CollideError::InvalidParameter {
                    name: "collision chain",
                    value: format!("{id} listed twice (entry {index})"),
                    allowed: "each chain at most once",
                });
            }
            chain.shape.validate(index)?;
        }
        self.chains.clear();
        self.chains.extend_from_slice(chains);
        self.chain_offsets.clear();
        self.chain_offsets.push(0);
        self.chain_volumes.clear();
        self.model_nodes.clear();
        self.is_root.clear();
        self.control_offsets.clear();
        self.control_offsets.push(0);
        let mut control_count = 0;
        for chain in chains {
            let nodes = rest.nodes(chain.chain as usize);
            control_count += nodes.len() * chain.shape.volume().control_points_per_node();
            self.control_offsets.push(control_count as u32);
            let first = nodes.start;
            self.is_root.extend(nodes.clone().map(|n| n == first));
            self.model_nodes.extend(nodes.map(|n| n as u32));
            self.chain_offsets.push(self.model_nodes.len() as u32);
            self.chain_volumes.push(chain.shape.volume());
        }
        let node_count = self.model_nodes.len();
        self.positions.resize(node_count, Vec3::ZERO);
        self.frames.resize(node_count, Frame::default());
        self.control_points.resize(control_count, Vec3::ZERO);
        Ok(())
    }

    /// Gathers positions from `node_positions` (the whole state, one per model node, world) into
    /// head space for the head at `head`, and computes node frames and control points there.
    pub fn gather(
        &mut self,
        rest: &SkeletonRest,
        node_positions: &[Vec3],
        head: &RigidTransform,
    ) -> Result<()> {
        require_len("node_positions", node_positions.len(), rest.node_count())?;
        let to_head = head.inverse();
        for (gathered, &model) in self.positions.iter_mut().zip(&self.model_nodes) {
            *gathered = to_head.transform_point(node_positions[model as usize]);
        }
        let shapes = Shapes {
            rest,
            chains: &self.chains,
            chain_offsets: &self.chain_offsets,
            control_offsets: &self.control_offsets,
            positions: &self.positions,
        };
        let (node_offsets, control_offsets) = (&self.chain_offsets, &self.control_offsets);
        let parts = (
            ChainSlice {
                items: &mut self.frames[..],
                first: |c: usize| node_offsets[c] as usize,
            },
            ChainSlice {
                items: &mut self.control_points[..],
                first: |c: usize| control_offsets[c] as usize,
            },
        );
        for_chain_blocks(0..self.chains.len(), CHAINS_PER_TASK, parts, &|block,
                                                                         (
            frames,
            controls,
        )| {
            shapes.frames_and_controls(block, frames.items, controls.items)
        });
        Ok(())
    }
}

/// Chains per task of the frames and control points.
const CHAINS_PER_TASK: usize = 32;

/// What the cluster and patch control points are computed from.
struct Shapes<'a> {
    rest: &'a SkeletonRest,
    chains: &'a [CollisionChain],
    chain_offsets: &'a [u32],
    control_offsets: &'a [u32],
    /// Gathered positions (head space).
    positions: &'a [Vec3],
}

impl Shapes<'_> {
    /// Node frames and control points of the clusters and patches among `chains`: `frames` and
    /// `controls` start at those chains' first node and first control point.
    fn frames_and_controls(
        &self,
        chains: Range<usize>,
        frames: &mut [Frame],
        controls: &mut [Vec3],
    ) {
        let node_start = self.chain_offsets[chains.start] as usize;
        let control_start = self.control_offsets[chains.start] as usize;
        for index in chains {
            let chain = &self.chains[index];
            let span = self.control_offsets[index] as usize - control_start
                ..self.control_offsets[index + 1] as usize - control_start;
            if span.is_empty() {
                // A strand group's volumes are its segments' own capsules: no frames needed.
                continue;
            }
            let nodes = self.chain_offsets[index] as usize..self.chain_offsets[index + 1] as usize;
            let positions = &self.positions[nodes.clone()];
            let frames = &mut frames[nodes.start - node_start..nodes.end - node_start];
            let root = self
                .rest
                .world_root_frame(chain.chain as usize, &RigidTransform::IDENTITY);
            node_frames(&root, positions, frames);
            let out = &mut controls[span];
            match chain.shape {
                ChainShape::StrandGroup { .. } => {}
                ChainShape::Cluster {
                    root_radius,
                    tip_radius,
                } => cluster_control_points(positions, frames, root_radius, tip_radius, out),
                ChainShape::Patch { width } => patch_control_points(positions, frames, width, out),
            }
        }
    }
}
