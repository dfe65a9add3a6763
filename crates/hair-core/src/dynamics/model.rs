//! The dynamic model built once from a [`SkeletonRest`]: node masses, spring stiffnesses and the
//! rest directions of every segment in its parent's frame.

use glam::Vec3;

use crate::dynamics::error::DynamicsError;
use crate::dynamics::forces::rest_local_direction;
use crate::dynamics::params::DynamicsParams;
use crate::skeleton::SkeletonRest;

/// Per-node constants of the dynamics, flat and chain-major like the rest model they come from.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicsModel {
    /// The skeletons' rest model (lengths, rest angles, roots in head space).
    pub rest: SkeletonRest,
    /// The material.
    pub params: DynamicsParams,
    /// Lumped node masses [kg], one per node: `λ·(l_i + l_{i+1})/2` (the root `λ·l_1/2`, the tip
    /// `λ·l_{n−1}/2`).
    pub node_masses: Vec<f32>,
    /// Spring stiffness `k_i = EI / ((l_{i−1} + l_i)/2)` [N·m/rad] of the bend ending at each node;
    /// 0 at roots.
    pub joint_stiffness: Vec<f32>,
    /// The direction each segment's spring pulls it towards in its parent's frame (from the
    /// natural angles, the rest angles unless the groom was made sag-free), as local coordinates
    /// (normal, binormal, tangent), one per node; the root's entry is unused.
    pub rest_local_directions: Vec<Vec3>,
    /// Squared angular frequency `k_i / (m_i·l_i²)` [1/s²] of each node's spring acting on that node
    /// alone (a scale of the stiffness a step must resolve); 0 at roots.
    pub joint_frequency_squared: Vec<f32>,
}

impl DynamicsModel {
    /// Builds the model; fails on invalid parameters.
    pub fn new(rest: SkeletonRest, params: DynamicsParams) -> Result<Self, DynamicsError> {
        params.validate()?;
        let node_count = rest.node_count();
        let mut node_masses = vec![0.0; node_count];
        let mut joint_stiffness = vec![0.0; node_count];
        let mut rest_local_directions = vec![Vec3::Z; node_count];
        let mut joint_frequency_squared = vec![0.0; node_count];
        let lengths = &rest.segment_rest_lengths;
        for chain in 0..rest.chain_count() {
            let nodes = rest.nodes(chain);
            let (start, end) = (nodes.start, nodes.end);
            for i in start..end {
                let own = if i > start { lengths[i] } else { 0.0 };
                let next = if i + 1 < end { lengths[i + 1] } else { 0.0 };
                node_masses[i] = params.linear_density * 0.5 * (own + next);
                if i > start {
                    let parent = if i > start + 1 {
                        lengths[i - 1]
                    } else {
                        lengths[i]
                    };
                    let k = params.bending_stiffness / (0.5 * (parent + lengths[i]));
                    joint_stiffness[i] = k;
                    joint_frequency_squared[i] = k / (node_masses[i] * lengths[i] * lengths[i]);
                    rest_local_directions[i] = rest_local_direction(
                        rest.natural_polar_angles[i],
                        rest.natural_azimuth_angles[i],
                    );
                }
            }
        }
        Ok(DynamicsModel {
            rest,
            params,
            node_masses,
            joint_stiffness,
            rest_local_directions,
            joint_frequency_squared,
        })
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.rest.node_count()
    }

    /// Number of chains.
    pub fn chain_count(&self) -> usize {
        self.rest.chain_count()
    }

    /// The highest spring frequency `max_i √(k_i/(m_i l_i²))` [rad/s]: explicit integration of the
    /// springs needs a substep of order `1/ω` or less.
    pub fn max_joint_frequency(&self) -> f32 {
        self.joint_frequency_squared
            .iter()
            .fold(0.0f32, |a, &b| a.max(b))
            .sqrt()
    }
}
