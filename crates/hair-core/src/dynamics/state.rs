//! The simulation state: what changes every step (node positions, velocities, time) and the
//! per-node collision force slot that the collision stage fills.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::skeleton::SkeletonRest;
use crate::transform::RigidTransform;

/// The state of every skeleton node, flat and chain-major like the [`SkeletonRest`] it belongs to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimulationState {
    /// Simulation time [s].
    pub time: f64,
    /// Node positions [m], one per node, chain-major.
    pub node_positions: Vec<Vec3>,
    /// Node velocities [m/s], one per node, chain-major.
    pub node_velocities: Vec<Vec3>,
    /// Collision forces F_col [N], one per node, chain-major: an input that the collision stage
    /// writes before a step; held constant over the step's substeps and left as it is afterwards.
    pub collision_forces: Vec<Vec3>,
}

impl SimulationState {
    /// The rest shape with the head at `head`, at rest (zero velocities, zero collision forces), at
    /// time `time` [s].
    pub fn at_rest(rest: &SkeletonRest, head: &RigidTransform, time: f64) -> Self {
        let node_count = rest.node_count();
        SimulationState {
            time,
            node_positions: rest.rest_positions(head),
            node_velocities: vec![Vec3::ZERO; node_count],
            collision_forces: vec![Vec3::ZERO; node_count],
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.node_positions.len()
    }

    /// Whether every position and velocity is finite.
    pub fn is_finite(&self) -> bool {
        self.node_positions.iter().all(|p| p.is_finite())
            && self.node_velocities.iter().all(|v| v.is_finite())
    }

    /// The largest relative deviation `| |p_i − p_{i−1}| / l_i − 1 |` of any segment from its rest
    /// length.
    pub fn max_length_error(&self, rest: &SkeletonRest) -> f32 {
        let mut worst = 0.0f32;
        for chain in 0..rest.chain_count() {
            let nodes = rest.nodes(chain);
            for i in nodes.start + 1..nodes.end {
                let length = (self.node_positions[i] - self.node_positions[i - 1]).length();
                worst = worst.max((length / rest.segment_rest_lengths[i] - 1.0).abs());
            }
        }
        worst
    }
}
