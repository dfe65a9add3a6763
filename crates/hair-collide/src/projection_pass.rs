//! The positional guarantee over the active chains, after each step
//! ([`CollisionSolver::after_step`](crate::CollisionSolver::after_step)): every node that ends
//! inside a body is projected out and its chain's following nodes are dragged behind it at their
//! segment lengths.
//!
//! Two passes. The first, side by side over blocks of chains, only reads the positions: a node is
//! *clear* when its clearance cache, the body's distance field (certified bounds) or a
//! closest-point search shows it outside every body, and each chain learns whether all its nodes
//! are. Those chains are done. The second pass walks the other chains, node by node along each,
//! as the projection always did; a chain's walk reads and writes only its own nodes, so where
//! the chains' nodes lie in the state in chain order (as the pipeline lays them out) the chains
//! walk side by side too, each reporting apart. Clear nodes are left exactly as they were, and
//! every clearance is a fact about a region of head space, so the result is the one-pass walk's,
//! bit for bit, whatever the thread count.

use std::ops::Range;

use glam::Vec3;
use hair_core::RigidTransform;

use crate::body::CollisionBody;
use crate::chain_blocks::{ChainSlice, for_chain_blocks};
use crate::clearance::{CLEARANCE_ROUNDING, Clearance};
use crate::projection::{Probe, Projection, probe, project_out, restore_length};
use crate::response::rigid_point_velocity;
use crate::solver_settings::ProjectionReport;

/// Chains per task of the first pass.
const CHAINS_PER_TASK: usize = 64;

/// What one step's projection reads.
pub(crate) struct ProjectionPass<'a> {
    /// The bodies, posed for the end of the step (world).
    pub bodies: &'a [CollisionBody],
    /// World to head space at the end of the step.
    pub to_head: RigidTransform,
    /// The head at the start and the end of the step (for the surface's velocity).
    pub head_before: RigidTransform,
    pub head: RigidTransform,
    /// The step \[s\].
    pub time_step: f32,
    /// The depth \[m\] a projected node ends outside.
    pub skin: f32,
    /// Whether the bodies' distance fields may certify clear nodes.
    pub use_field: bool,
    /// Whether roots are attached (then never projected).
    pub attached: bool,
    /// Gathered node offsets per chain (chain count + 1).
    pub chain_offsets: &'a [u32],
    /// Per gathered node, its index in the state.
    pub model_nodes: &'a [u32],
    /// Per gathered node, whether it is its chain's root.
    pub is_root: &'a [bool],
    /// Rest length \[m\] of the segment ending at each model node.
    pub lengths: &'a [f32],
}

/// The part of the state and the clearances that a walk along chains reads and writes: the
/// nodes from model node `first_model` on, the clearances from gathered node `first_node` on.
struct Walk<'a> {
    positions: &'a mut [Vec3],
    velocities: &'a mut [Vec3],
    caches: &'a mut [Clearance],
    first_model: usize,
    first_node: usize,
}

impl ProjectionPass<'_> {
    /// Whether `position` (world) is certified outside `body` by its clearance cache, the
    /// body's distance field or a closest-point search; the cache learns what was found.
    fn clear_of(&self, body: &CollisionBody, position: Vec3, cache: &mut Clearance) -> bool {
        let local = self.to_head.transform_point(position);
        if local.distance(cache.local_position) + CLEARANCE_ROUNDING < cache.clearance {
            return true;
        }
        let certified = if self.use_field {
            body.field_clearance(local, CLEARANCE_ROUNDING)
        } else {
            None
        };
        let (clearance, triangle) = match certified {
            Some(clearance) => (clearance, cache.triangle),
            None => match probe(body, position, cache.triangle) {
                Probe::Outside {
                    clearance,
                    triangle,
                } => (clearance, triangle),
                Probe::Inside(surface) => {
                    cache.triangle = surface.triangle;
                    cache.inside = Some((position, surface));
                    return false;
                }
            },
        };
        *cache = Clearance {
            local_position: local,
            clearance,
            triangle,
            inside: None,
        };
        true
    }

    /// Whether every node of the chains `chains` that may be projected is clear of every body,
    /// into `all_clear` (one per chain); `caches` are those chains' clearances (node-major).
    fn certify(
        &self,
        positions: &[Vec3],
        chains: Range<usize>,
        caches: &mut [Clearance],
        all_clear: &mut [bool],
    ) {
        let body_count = self.bodies.len();
        let first = self.chain_offsets[chains.start] as usize;
        for (chain, clear) in chains.zip(all_clear.iter_mut()) {
            let nodes = self.chain_offsets[chain] as usize..self.chain_offsets[chain + 1] as usize;
            *clear = nodes.into_iter().all(|node| {
                if self.attached && self.is_root[node] {
                    return true;
                }
                let position = positions[self.model_nodes[node] as usize];
                let node_caches = &mut caches[(node - first) * body_count..][..body_count];
                self.bodies
                    .iter()
                    .zip(node_caches)
                    .all(|(body, cache)| self.clear_of(body, position, cache))
            });
        }
    }

    /// Projects the chains out of the bodies: `all_clear` and `reports` are scratch (one per
    /// chain), `caches` the clearances (node-major, all chains).
    pub fn run(
        &self,
        positions: &mut [Vec3],
        velocities: &mut [Vec3],
        caches: &mut [Clearance],
        all_clear: &mut Vec<bool>,
        reports: &mut Vec<ProjectionReport>,
    ) -> ProjectionReport {
        let chain_count = self.chain_offsets.len().saturating_sub(1);
        all_clear.clear();
        all_clear.resize(chain_count, false);
        let body_count = self.bodies.len();
        let offsets = self.chain_offsets;
        let parts = (
            ChainSlice {
                items: &mut caches[..],
                first: |c: usize| offsets[c] as usize * body_count,
            },
            ChainSlice {
                items: &mut all_clear[..],
                first: |c: usize| c,
            },
        );
        let read: &[Vec3] = positions;
        for_chain_blocks(0..chain_count, CHAINS_PER_TASK, parts, &|block,
                                                                   (
            caches,
            clear,
        )| {
            self.certify(read, block, caches.items, clear.items)
        });
        reports.clear();
        reports.resize(chain_count, ProjectionReport::default());
        match model_starts(self.chain_offsets, self.model_nodes, positions.len()) {
            // Each chain's walk reads and writes its own nodes only, so the chains left walk side
            // by side, each reporting apart, where their nodes lie in the state in chain order.
            Some(starts) => {
                let from = starts(0);
                let parts = (
                    (
                        ChainSlice {
                            items: &mut positions[from..],
                            first: starts,
                        },
                        ChainSlice {
                            items: &mut velocities[from..],
                            first: starts,
                        },
                    ),
                    (
                        ChainSlice {
                            items: &mut caches[..],
                            first: |c: usize| offsets[c] as usize * body_count,
                        },
                        ChainSlice {
                            items: &mut reports[..],
                            first: |c: usize| c,
                        },
                    ),
                );
                let all_clear: &[bool] = all_clear;
                for_chain_blocks(0..chain_count, CHAINS_PER_TASK, parts, &|block,
                                                                           (
                    (positions, velocities),
                    (caches, reports),
                )| {
                    let mut walk = Walk {
                        positions: positions.items,
                        velocities: velocities.items,
                        caches: caches.items,
                        first_model: starts(block.start),
                        first_node: offsets[block.start] as usize,
                    };
                    for chain in block.clone().filter(|&chain| !all_clear[chain]) {
                        self.project_chain(
                            chain,
                            &mut walk,
                            &mut reports.items[chain - block.start],
                        );
                    }
                });
            }
            None => {
                let mut walk = Walk {
                    positions,
                    velocities,
                    caches,
                    first_model: 0,
                    first_node: 0,
                };
                for chain in (0..chain_count).filter(|&chain| !all_clear[chain]) {
                    self.project_chain(chain, &mut walk, &mut reports[chain]);
                }
            }
        }
        let mut report = ProjectionReport::default();
        for own in reports.iter() {
            report.projected_nodes += own.projected_nodes;
            report.max_depth = report.max_depth.max(own.max_depth);
            report.max_stretch = report.max_stretch.max(own.max_stretch);
        }
        report
    }

    /// The walk along one chain: projects each node inside a body out, drags the nodes behind a
    /// projected one at their segment lengths, and gives a projected segment back its length.
    fn project_chain(&self, chain: usize, walk: &mut Walk<'_>, report: &mut ProjectionReport) {
        let body_count = self.bodies.len();
        let nodes = self.chain_offsets[chain] as usize..self.chain_offsets[chain + 1] as usize;
        let mut dragged = false;
        for node in nodes.clone() {
            let m = self.model_nodes[node] as usize - walk.first_model;
            let positions = &mut *walk.positions;
            if dragged && node > nodes.start {
                // Follow the leader behind a projected node: keep the segment's length.
                let parent = positions[m - 1];
                if let Some(direction) = (positions[m] - parent).try_normalize() {
                    positions[m] = parent + direction * self.lengths[m + walk.first_model];
                }
            }
            if self.attached && self.is_root[node] {
                continue;
            }
            for (b, body) in self.bodies.iter().enumerate() {
                // The pose's motion, and a deforming body's own.
                let surface_velocity = |p, near| {
                    rigid_point_velocity(&self.head_before, &self.head, p, self.time_step)
                        + body.deformation_velocity_near(p, near)
                };
                let cache = &mut walk.caches[(node - walk.first_node) * body_count + b];
                // Found inside at this very position by the first pass (or by `clear_of` just
                // now): the projection starts from that search's answer. A search from its own
                // triangle at the same point would give the same one.
                let found = |cache: &mut Clearance, at: Vec3| {
                    cache
                        .inside
                        .take()
                        .and_then(|(searched, surface)| (searched == at).then_some(surface))
                };
                let inside = match found(cache, positions[m]) {
                    Some(surface) => Some(surface),
                    None if self.clear_of(body, positions[m], cache) => continue,
                    None => found(cache, positions[m]),
                };
                match project_out(
                    body,
                    &mut positions[m],
                    &mut walk.velocities[m],
                    self.skin,
                    inside,
                    cache.triangle,
                    surface_velocity,
                ) {
                    Projection::Outside {
                        clearance,
                        triangle,
                    } => {
                        *cache = Clearance {
                            local_position: self.to_head.transform_point(positions[m]),
                            clearance,
                            triangle,
                            inside: None,
                        }
                    }
                    Projection::Moved { depth, triangle } => {
                        *cache = Clearance {
                            triangle,
                            ..Clearance::default()
                        };
                        dragged = true;
                        report.projected_nodes += 1;
                        report.max_depth = report.max_depth.max(depth);
                        if node > nodes.start {
                            let length = self.lengths[m + walk.first_model];
                            restore_length(
                                body,
                                &mut positions[m - 1..=m],
                                &mut walk.velocities[m],
                                length,
                                self.skin,
                                triangle,
                                surface_velocity,
                            );
                            let reached = positions[m].distance(positions[m - 1]);
                            if length > 0.0 {
                                let stretch = (reached - length).abs() / length;
                                report.max_stretch = report.max_stretch.max(stretch);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Where each chain's nodes start in the state (chain `chain count` gives the end), for chains
/// of gathered nodes `chain_offsets` whose state indices are `model_nodes`: where every chain
/// has nodes and each chain's lie after the last one's, within `state_nodes`; `None` otherwise
/// (the walk then goes chain by chain on one thread).
fn model_starts<'a>(
    chain_offsets: &'a [u32],
    model_nodes: &'a [u32],
    state_nodes: usize,
) -> Option<impl Fn(usize) -> usize + Copy + Send + 'a> {
    let chain_count = chain_offsets.len().saturating_sub(1);
    let mut end = 0usize;
    for c in 0..chain_count {
        let nodes = chain_offsets[c] as usize..chain_offsets[c + 1] as usize;
        if nodes.is_empty() {
            return None;
        }
        let (Some(&first), Some(&last)) =
            (model_nodes.get(nodes.start), model_nodes.get(nodes.end - 1))
        else {
            return None;
        };
        if c > 0 && (first as usize) < end {
            return None;
        }
        end = last as usize + 1;
    }
    (end <= state_nodes).then_some(move |c: usize| {
        if c >= chain_count {
            end
        } else {
            model_nodes[chain_offsets[c] as usize] as usize
        }
    })
}

#[cfg(test)]
mod tests {
    use super::model_starts;

    /// Chains whose nodes lie in the state in chain order (with gaps between them) walk side by
    /// side, each starting at its first node; chains out of order, an empty chain or nodes past
    /// the state do not.
    #[test]
    fn chains_in_state_order_split_where_their_nodes_start() {
        // Three chains of gathered nodes 0..3, 3..5, 5..9 at state nodes 2..5, 7..9, 9..13.
        let offsets = [0, 3, 5, 9];
        let model = [2, 3, 4, 7, 8, 9, 10, 11, 12];
        let starts = model_starts(&offsets, &model, 13).expect("in order");
        assert_eq!([0, 1, 2, 3].map(starts), [2, 7, 9, 13]);
        assert!(
            model_starts(&offsets, &model, 12).is_none(),
            "past the state"
        );
        let swapped = [7, 8, 9, 2, 3, 4, 5, 10, 11];
        assert!(
            model_starts(&[0, 3, 5, 9], &swapped, 13).is_none(),
            "out of order"
        );
        assert!(
            model_starts(&[0, 3, 3, 9], &model, 13).is_none(),
            "an empty chain"
        );
        assert!(model_starts(&[0], &[], 0).is_some(), "no chains");
    }
}
