//! The state of one level: which sections are simulated at it, where their chains and nodes sit,
//! and the node state. Rebuilt (the only allocation of the pipeline) when sections join or leave,
//! with the arriving sections' state handed over from the level they leave (§4.2).

use std::ops::Range;

use glam::Vec3;
use hair_collide::VelocityMemory;
use hair_core::dynamics::{ChainRoots, SimulationState};
use hair_core::lod::{SectionStateRef, hand_over};
use hair_core::{Groom, Level, PerLevel};
use serde::{Deserialize, Serialize};

use super::error::{PipelineError, Result};

/// The sections simulated at one level, packed: section `sections[i]`'s chains are groom chains
/// `chains[chain_start..]` in order and own nodes `node_start[i]..node_start[i + 1]` of the state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelBlock {
    /// The level.
    pub level: Level,
    /// The sections simulated at this level, ascending.
    pub sections: Vec<usize>,
    /// First node of each section in the state (one more entry: the node count).
    pub node_start: Vec<usize>,
    /// The groom chains simulated, in the order of the state's nodes.
    pub chains: Vec<usize>,
    /// Time [s], node positions [m], velocities [m/s] and collision forces [N] of the chains.
    pub state: SimulationState,
    /// The collision response's memory of the node positions at its last step (see
    /// [`hair_collide::CollisionSolver::velocity_memory`]); empty without collision.
    #[serde(default)]
    pub collision_memory: VelocityMemory,
}

impl LevelBlock {
    /// An empty block at `time` [s].
    pub fn empty(level: Level, time: f64) -> Self {
        LevelBlock {
            level,
            sections: Vec::new(),
            node_start: vec![0],
            chains: Vec::new(),
            state: SimulationState {
                time,
                node_positions: Vec::new(),
                node_velocities: Vec::new(),
                collision_forces: Vec::new(),
            },
            collision_memory: VelocityMemory::default(),
        }
    }

    /// The layout of `sections` (ascending) of `groom` at `level`, its state zeroed at `time` [s]
    /// (the caller fills it).
    pub fn laid_out(groom: &Groom, level: Level, sections: Vec<usize>, time: f64) -> Self {
        let mut block = LevelBlock::empty(level, time);
        let mut nodes = 0;
        for &section in &sections {
            for chain in groom.section_chains(section, level) {
                nodes += groom.skeletons.chain_node_count(chain);
                block.chains.push(chain);
            }
            block.node_start.push(nodes);
        }
        block.sections = sections;
        block.state.node_positions = vec![Vec3::ZERO; nodes];
        block.state.node_velocities = vec![Vec3::ZERO; nodes];
        block.state.collision_forces = vec![Vec3::ZERO; nodes];
        block
    }

    /// The block of `level` for `sections` (ascending) at `time` [s]: sections that were
    /// simulated at this level in `blocks` keep their state bit for bit, the others are handed
    /// over from the level they were simulated at (§4.2) with the head at `head`.
    pub fn handed_over(
        groom: &Groom,
        level: Level,
        sections: Vec<usize>,
        blocks: &PerLevel<LevelBlock>,
        time: f64,
        roots: &ChainRoots<'_>,
    ) -> Result<Self> {
        let mut block = LevelBlock::laid_out(groom, level, sections, time);
        let old = &blocks[level];
        for slot in 0..block.sections.len() {
            let section = block.sections[slot];
            let target = block.nodes(slot);
            if let Some(old_slot) = old.slot(section) {
                let source = old.nodes(old_slot);
                block.state.node_positions[target.clone()]
                    .copy_from_slice(&old.state.node_positions[source.clone()]);
                block.state.node_velocities[target]
                    .copy_from_slice(&old.state.node_velocities[source]);
                continue;
            }
            // Arriving: hand over from the level it was simulated at until now.
            let Some((from_level, from_block)) = blocks
                .iter()
                .find(|(l, b)| *l != level && b.slot(section).is_some())
            else {
                return Err(PipelineError::NothingToHandOver { section });
            };
            let from_nodes = from_block.nodes(from_block.slot(section).expect("found above"));
            let from = SectionStateRef {
                positions: &from_block.state.node_positions[from_nodes.clone()],
                velocities: &from_block.state.node_velocities[from_nodes],
            };
            hand_over(
                groom,
                section,
                from_level,
                from,
                level,
                &mut block.state.node_positions[target.clone()],
                &mut block.state.node_velocities[target],
                roots,
            )?;
        }
        Ok(block)
    }

    /// Checks a block read from a checkpoint against `groom`: its layout must be the one
    /// [`LevelBlock::laid_out`] gives for its sections, its state sized to it and finite.
    pub fn check(&self, groom: &Groom, level: Level) -> Result<()> {
        let bad = |why: String| Err(PipelineError::Block { level, why });
        if self.level != level {
            return bad(format!("stored as the {} block", self.level.name()));
        }
        let sections = groom.section_count();
        if !self.sections.windows(2).all(|w| w[0] < w[1])
            || self.sections.iter().any(|&s| s >= sections)
        {
            return bad(format!(
                "sections must ascend, each below the groom's {sections}"
            ));
        }
        let expected = LevelBlock::laid_out(groom, level, self.sections.clone(), self.state.time);
        if expected.node_start != self.node_start || expected.chains != self.chains {
            return bad("its chain and node layout is not the groom's".into());
        }
        let nodes = expected.node_count();
        for (what, count) in [
            ("node_positions", self.state.node_positions.len()),
            ("node_velocities", self.state.node_velocities.len()),
            ("collision_forces", self.state.collision_forces.len()),
        ] {
            if count != nodes {
                return bad(format!("{what} has {count} entries for {nodes} nodes"));
            }
        }
        let finite = |v: &[Vec3]| v.iter().all(|p| p.is_finite());
        if !finite(&self.state.node_positions)
            || !finite(&self.state.node_velocities)
            || !finite(&self.state.collision_forces)
            || !finite(&self.collision_memory.positions)
            || !self.state.time.is_finite()
        {
            return bad("a position, velocity, force or time is not finite".into());
        }
        Ok(())
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
