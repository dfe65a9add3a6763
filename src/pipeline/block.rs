//! The active skeletons of one level: which sections are simulated at that level, their model,
//! state and solver. Rebuilt (the only allocation of the pipeline) when sections join or leave.

use std::ops::Range;

use glam::Vec3;
use hair_core::dynamics::{
    DynamicsModel, DynamicsParams, Simulation, SimulationSettings, SimulationState,
};
use hair_core::{Groom, Level, SkeletonRest};

use super::error::Result;

/// The sections simulated at one level, packed: section `sections[i]`'s chains are chains
/// `chain_start[i]..chain_start[i + 1]` of the model and own nodes `node_start[i]..node_start[i + 1]`
/// of the state.
#[derive(Debug)]
pub struct LevelBlock {
    /// The level.
    pub level: Level,
    /// The sections simulated at this level, ascending.
    pub sections: Vec<usize>,
    /// First node of each section in the state (one more entry: the node count).
    pub node_start: Vec<usize>,
    /// The groom chains of the model, in model order.
    pub chains: Vec<usize>,
    /// The solver (`None` when no section is at this level).
    pub simulation: Option<Simulation>,
    /// Positions, velocities and collision forces of the active skeletons.
    pub state: SimulationState,
    /// Velocities [m/s] at the start of the last step (for the motion measure).
    pub previous_velocities: Vec<Vec3>,
}

impl LevelBlock {
    /// An empty block.
    pub fn empty(level: Level) -> Self {
        LevelBlock {
            level,
            sections: Vec::new(),
            node_start: vec![0],
            chains: Vec::new(),
            simulation: None,
            state: SimulationState {
                time: 0.0,
                node_positions: Vec::new(),
                node_velocities: Vec::new(),
                collision_forces: Vec::new(),
            },
            previous_velocities: Vec::new(),
        }
    }

    /// A block simulating `sections` (ascending) of `groom` at `level`, state zeroed at `time`
    /// (the caller fills it).
    pub fn build(
        groom: &Groom,
        level: Level,
        sections: Vec<usize>,
        params: DynamicsParams,
        settings: SimulationSettings,
        time: f64,
    ) -> Result<Self> {
        let mut block = LevelBlock::empty(level);
        block.state.time = time;
        if sections.is_empty() {
            return Ok(block);
        }
        let mut rest = SkeletonRest::default();
        for &section in &sections {
            for chain in groom.section_chains(section, level) {
                rest.push_chain_from(&groom.skeletons, chain)?;
                block.chains.push(chain);
            }
            block.node_start.push(rest.node_count());
        }
        let node_count = rest.node_count();
        block.sections = sections;
        block.simulation = Some(Simulation::new(
            DynamicsModel::new(rest, params)?,
            settings,
        )?);
        block.state.node_positions = vec![Vec3::ZERO; node_count];
        block.state.node_velocities = vec![Vec3::ZERO; node_count];
        block.state.collision_forces = vec![Vec3::ZERO; node_count];
        block.previous_velocities = vec![Vec3::ZERO; node_count];
        Ok(block)
    }

    /// Where section `section` is in this block, if it is simulated here.
    pub fn slot(&self, section: usize) -> Option<usize> {
        self.sections.binary_search(&section).ok()
    }

    /// The node range of the section in slot `slot`.
    pub fn nodes(&self, slot: usize) -> Range<usize> {
        self.node_start[slot]..self.node_start[slot + 1]
    }

    /// Number of simulated nodes.
    pub fn node_count(&self) -> usize {
        self.state.node_positions.len()
    }
}
