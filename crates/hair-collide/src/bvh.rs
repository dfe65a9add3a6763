//! The hair hierarchy (§5.3): one swept-sphere volume per skeleton segment of many chains, in a
//! top-down (binned SAH) parry3d `Bvh` of their AABBs, refitted from new positions each step.
//!
//! Leaves are the `n − 1` segment volumes of every chain, numbered chain after chain (the
//! *segment id*). The tree's nodes are AABBs; the exact swept-sphere test runs at the leaves (see
//! [`crate::query`]). Leaf AABBs are padded by [`aabb_padding`] so that AABB culling can never
//! reject a pair that the exact f32 test would accept.

use glam::Vec3;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

use crate::chain_blocks::{ChainSlice, for_chain_blocks};
use crate::error::{CollideError, Result, require_finite_points, require_len};
use crate::fit::{cluster_segment, patch_segment, strand_group_segment};
use crate::volume::{Pss, SweptSphere};

/// Chains per task when the segment volumes are computed side by side.
const CHAINS_PER_TASK: usize = 32;

/// How the segments of one chain are bounded, after its hair representation (§5.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ChainVolume {
    /// A strand group's skeleton: an LSS per segment with radius `thickness` \[m\] (0 for a lone
    /// strand). Needs no control points.
    StrandGroup {
        /// Radius of every segment's LSS \[m\], finite and `>= 0`.
        thickness: f32,
    },
    /// A cluster: 4 control points per node (its cross-section); an LSS per segment enclosing the
    /// segment's 8 control points ([`crate::fit::cluster_segment`]).
    Cluster,
    /// A patch: 2 control points per node (`[left, right]`); an RSS per segment enclosing the 4
    /// that outline it ([`crate::fit::patch_segment`]).
    Patch,
}

impl ChainVolume {
    /// Control points per node that this representation reads (0, 4 or 2).
    pub fn control_points_per_node(&self) -> usize {
        match self {
            ChainVolume::StrandGroup { .. } => 0,
            ChainVolume::Cluster => 4,
            ChainVolume::Patch => 2,
        }
    }
}

/// Padding \[m\] added around a volume's AABB so AABB culling is conservative with respect to the
/// f32 exact test: `64 ε (1 + magnitude + radius)`, about 4 µm at 0.5 m.
pub fn aabb_padding(volume: &SweptSphere) -> f32 {
    64.0 * f32::EPSILON * (1.0 + volume.magnitude() + volume.radius())
}

/// A bounding-volume hierarchy over the segment volumes of many skeleton chains.
///
/// Chains are stored flat: chain `c` owns nodes `chain_offsets[c]..chain_offsets[c + 1]` of
/// `node_positions`, and its control points (if its [`ChainVolume`] has any) follow those of the
/// previous chains, `k` per node, node after node. Build once per set of chains
/// ([`HairBvh::build`]), then [`HairBvh::refit`] every step; build again when the chains change
/// (a section changes level), which [`HairBvh::has_layout`] tells.
pub struct HairBvh {
    chain_offsets: Vec<u32>,
    chain_volumes: Vec<ChainVolume>,
    control_offsets: Vec<usize>,
    segment_offsets: Vec<u32>,
    segment_top_nodes: Vec<u32>,
    segment_chains: Vec<u32>,
    volumes: Vec<SweptSphere>,
    bvh: Bvh,
    workspace: BvhWorkspace,
    /// Whether the tree bounds the current volumes (false after [`HairBvh::update_volumes`]).
    tree_current: bool,
}

impl std::fmt::Debug for HairBvh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HairBvh")
            .field("chain_count", &self.chain_volumes.len())
            .field("segment_count", &self.volumes.len())
            .finish_non_exhaustive()
    }
}

/// Validates `chain_offsets` against the node count; returns the chain count.
fn validate_offsets(chain_offsets: &[u32], node_count: usize) -> Result<usize> {
    let invalid = |reason: String| Err(CollideError::InvalidOffsets { reason });
    let Some((&first, _)) = chain_offsets.split_first() else {
        return invalid("empty (need chain count + 1 entries, starting at 0)".into());
    };
    if first != 0 {
        return invalid(format!("first entry is {first}, expected 0"));
    }
    if let Some(c) = chain_offsets.windows(2).position(|w| w[1] < w[0]) {
        return invalid(format!("entry {} is smaller than entry {c}", c + 1));
    }
    let last = *chain_offsets.last().unwrap_or(&0) as usize;
    if last != node_count {
        return invalid(format!(
            "last entry is {last}, but there are {node_count} node positions"
        ));
    }
    Ok(chain_offsets.len() - 1)
}

impl HairBvh {
    /// Builds the volumes and the hierarchy (top-down, binned SAH).
    ///
    /// - `chain_offsets`: chain count + 1 node offsets, from 0 to `node_positions.len()`.
    /// - `chain_volumes`: one per chain.
    /// - `node_positions`: skeleton node positions \[m\], chain-major.
    /// - `control_points`: cluster and patch control points \[m\] in chain order (empty when every
    ///   chain is a strand group).
    ///
    /// Errors on mismatched sizes, bad offsets, negative or non-finite thickness and non-finite
    /// positions.
    pub fn build(
        chain_offsets: &[u32],
        chain_volumes: &[ChainVolume],
        node_positions: &[Vec3],
        control_points: &[Vec3],
    ) -> Result<Self> {
        let chain_count = validate_offsets(chain_offsets, node_positions.len())?;
        require_len("chain_volumes", chain_volumes.len(), chain_count)?;
        for (index, volume) in chain_volumes.iter().enumerate() {
            if let ChainVolume::StrandGroup { thickness } = volume {
                if !thickness.is_finite() {
                    return Err(CollideError::NonFinite {
                        what: "thickness",
                        index,
                    });
                }
                if *thickness < 0.0 {
                    return Err(CollideError::InvalidParameter {
                        name: "thickness",
                        value: thickness.to_string(),
                        allowed: "a finite number >= 0 m",
                    });
                }
            }
        }
        let mut control_offsets = Vec::with_capacity(chain_count + 1);
        let mut segment_offsets = Vec::with_capacity(chain_count + 1);
        let mut segment_top_nodes = Vec::new();
        let mut segment_chains = Vec::new();
        control_offsets.push(0);
        segment_offsets.push(0);
        for (chain, volume) in chain_volumes.iter().enumerate() {
            let (begin, end) = (chain_offsets[chain], chain_offsets[chain + 1]);
            let node_count = (end - begin) as usize;
            control_offsets
                .push(control_offsets[chain] + node_count * volume.control_points_per_node());
            for top in begin..end.saturating_sub(1).max(begin) {
                segment_top_nodes.push(top);
                segment_chains.push(chain as u32);
            }
            segment_offsets.push(segment_top_nodes.len() as u32);
        }
        let mut hair = HairBvh {
            chain_offsets: chain_offsets.to_vec(),
            chain_volumes: chain_volumes.to_vec(),
            control_offsets,
            segment_offsets,
            segment_top_nodes,
            segment_chains,
            volumes: Vec::new(),
            bvh: Bvh::new(),
            workspace: BvhWorkspace::default(),
            tree_current: false,
        };
        hair.compute_volumes(node_positions, control_points)?;
        hair.rebuild();
        Ok(hair)
    }

    /// Recomputes every segment volume from new positions and refits the tree (no rebuild: the
    /// topology stays, only the AABBs change). Same arguments as [`HairBvh::build`]; errors on
    /// sizes that do not match the layout or non-finite positions, leaving `self` unchanged.
    pub fn refit(&mut self, node_positions: &[Vec3], control_points: &[Vec3]) -> Result<()> {
        self.compute_volumes(node_positions, control_points)?;
        for (leaf, volume) in self.volumes.iter().enumerate() {
            let aabb = volume.aabb(aabb_padding(volume));
            self.bvh.insert_or_update_partially(aabb, leaf as u32, 0.0);
        }
        self.bvh.refit(&mut self.workspace);
        self.tree_current = true;
        Ok(())
    }

    /// Recomputes every segment volume from new positions and leaves the tree alone: what a
    /// query through a body's distance field ([`crate::query_body_near`]) reads, for no tree
    /// work. Until the next [`refit`](Self::refit) the tree no longer bounds the volumes
    /// ([`tree_is_current`](Self::tree_is_current) is false), and [`crate::query_body`] then
    /// answers without it. Same arguments and errors as [`refit`](Self::refit).
    pub fn update_volumes(
        &mut self,
        node_positions: &[Vec3],
        control_points: &[Vec3],
    ) -> Result<()> {
        self.compute_volumes(node_positions, control_points)?;
        self.tree_current = false;
        Ok(())
    }

    /// Whether the tree bounds the current volumes (after a build or a refit, not after
    /// [`update_volumes`](Self::update_volumes)).
    pub fn tree_is_current(&self) -> bool {
        self.tree_current
    }

    /// Rebuilds the tree top-down from the current volumes (restores tree quality after large
    /// motions; never needed for correctness).
    pub fn rebuild(&mut self) {
        let leaves = self
            .volumes
            .iter()
            .map(|volume| volume.aabb(aabb_padding(volume)))
            .enumerate();
        self.bvh = Bvh::from_iter(BvhBuildStrategy::Binned, leaves);
        self.tree_current = true;
    }

    fn compute_volumes(&mut self, node_positions: &[Vec3], control_points: &[Vec3]) -> Result<()> {
        let node_count = *self.chain_offsets.last().unwrap_or(&0) as usize;
        require_len("node_positions", node_positions.len(), node_count)?;
        require_len(
            "control_points",
            control_points.len(),
            *self.control_offsets.last().unwrap_or(&0),
        )?;
        require_finite_points("node_positions", node_positions)?;
        require_finite_points("control_points", control_points)?;

        let segment_count = *self.segment_offsets.last().unwrap_or(&0) as usize;
        let placeholder = SweptSphere::Point(Pss {
            center: Vec3::ZERO,
            radius: 0.0,
        });
        self.volumes.resize(segment_count, placeholder);
        let (chain_offsets, control_offsets) = (&self.chain_offsets, &self.control_offsets);
        let chain_volumes = &self.chain_volumes;
        let segment_offsets = &self.segment_offsets;
        let volumes = ChainSlice {
            items: &mut self.volumes[..],
            first: |c: usize| segment_offsets[c] as usize,
        };
        for_chain_blocks(
            0..chain_volumes.len(),
            CHAINS_PER_TASK,
            volumes,
            &|block, volumes| {
                let first = segment_offsets[block.start] as usize;
                for chain in block {
                    let nodes = &node_positions
                        [chain_offsets[chain] as usize..chain_offsets[chain + 1] as usize];
                    let controls =
                        &control_points[control_offsets[chain]..control_offsets[chain + 1]];
                    let out = &mut volumes.items[segment_offsets[chain] as usize - first..];
                    for (i, (pair, out)) in nodes.windows(2).zip(out).enumerate() {
                        *out = match chain_volumes[chain] {
                            ChainVolume::StrandGroup { thickness } => {
                                strand_group_segment(pair[0], pair[1], thickness).into()
                            }
                            ChainVolume::Cluster => {
                                let mut points = [Vec3::ZERO; 8];
                                points.copy_from_slice(&controls[4 * i..4 * i + 8]);
                                cluster_segment(pair[0], pair[1], &points).into()
                            }
                            ChainVolume::Patch => {
                                let mut points = [Vec3::ZERO; 4];
                                points.copy_from_slice(&controls[2 * i..2 * i + 4]);
                                patch_segment(&points).into()
                            }
                        };
                    }
                }
            },
        );
        Ok(())
    }

    /// Whether this hierarchy was built for exactly these chains (same offsets and volume kinds,
    /// thickness included); when not, call [`HairBvh::build`] again.
    pub fn has_layout(&self, chain_offsets: &[u32], chain_volumes: &[ChainVolume]) -> bool {
        self.chain_offsets == chain_offsets && self.chain_volumes == chain_volumes
    }

    /// Number of chains.
    pub fn chain_count(&self) -> usize {
        self.chain_volumes.len()
    }

    /// Number of segments (leaves): the sum over chains of `max(nodes − 1, 0)`.
    pub fn segment_count(&self) -> usize {
        self.volumes.len()
    }

    /// The segment volumes, indexed by segment id.
    pub fn volumes(&self) -> &[SweptSphere] {
        &self.volumes
    }

    /// Per segment id, the index of its top node `p_i` (its bottom node is `p_{i+1}`).
    pub fn segment_top_nodes(&self) -> &[u32] {
        &self.segment_top_nodes
    }

    /// Per segment id, the chain it belongs to.
    pub fn segment_chains(&self) -> &[u32] {
        &self.segment_chains
    }

    /// Chain count + 1 segment offsets: chain `c` owns segment ids
    /// `segment_offsets[c]..segment_offsets[c + 1]`.
    pub fn segment_offsets(&self) -> &[u32] {
        &self.segment_offsets
    }

    /// The chain node offsets this hierarchy was built for.
    pub fn chain_offsets(&self) -> &[u32] {
        &self.chain_offsets
    }

    /// The per-chain volume kinds this hierarchy was built for.
    pub fn chain_volumes(&self) -> &[ChainVolume] {
        &self.chain_volumes
    }

    /// The underlying parry3d tree (leaf data = segment id).
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }
}
