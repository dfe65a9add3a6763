//! The invariants of a [`PipelineState`], checked before a run resumes from one: a checkpoint
//! edited by hand, or damaged, is refused with the field that breaks them instead of resuming
//! silently wrong. (The checkpoint's checksum catches edits that keep to the invariants.)

use glam::Vec3;
use hair_core::{Groom, Level};

use super::error::{PipelineError, Result};
use super::state::PipelineState;

/// The fastest a skeleton node may move in a restored state [m/s]. Hair on a head moves at a
/// few metres per second (the head's shake peaks at 1–6 m/s, a gust at tens); 1,000 m/s, about
/// three times the speed of sound, is beyond any hair motion the integrators can follow at
/// 60 Hz (it crosses a 30 cm strand in a third of a millisecond).
pub const MAX_NODE_SPEED: f32 = 1_000.0;

/// The most frames a restored state may have advanced: 10^8 frames is over 460 hours at 60 Hz.
/// (The state's time is checked against its frame count step by step, so this bounds the check.)
pub const MAX_STATE_FRAMES: usize = 100_000_000;

/// How far a node may lie from its chain's root beyond the chain's rest length [m] (lengths
/// hold within 1e-5 relative; collision projection and blends move nodes by millimetres).
const LENGTH_SLACK: f32 = 0.01;

/// The key of `level`'s block in a checkpoint's JSON (`PerLevel`'s field names).
fn block_key(level: Level) -> &'static str {
    match level {
        Level::Patch => "patch",
        Level::Cluster => "cluster",
        Level::StrandGroup => "strand_group",
    }
}

/// The refusal of field `field` for `why`.
fn refuse(field: impl Into<String>, why: impl Into<String>) -> PipelineError {
    PipelineError::StateField {
        field: field.into(),
        why: why.into(),
    }
}

impl PipelineState {
    /// Checks the state against its invariants for `groom` stepped at `time_step` [s] a frame:
    /// the time is the frame count's (the pipeline adds `time_step` once a frame, from 0), every
    /// level block is laid out as the groom's and holds the sections at its level, its time is
    /// the state's, its positions, velocities and forces are finite, no node moves faster than
    /// [`MAX_NODE_SPEED`] or lies farther from its root than its chain is long, the collision
    /// memory has one entry per node (or none), blends and fades are within their ranges, and the
    /// selector's memory has one entry per section. Errors name the field.
    pub fn check(&self, groom: &Groom, time_step: f32) -> Result<()> {
        let sections = groom.section_count();
        if self.frame > MAX_STATE_FRAMES {
            return Err(refuse(
                "frame",
                format!(
                    "{} frames is beyond the {MAX_STATE_FRAMES} a run may have advanced",
                    self.frame
                ),
            ));
        }
        let mut expected_time = 0.0_f64;
        for _ in 0..self.frame {
            expected_time += f64::from(time_step);
        }
        if self.time.to_bits() != expected_time.to_bits() {
            return Err(refuse(
                "time",
                format!(
                    "{} s after {} frames of {time_step} s: the pipeline is at {expected_time} s \
                     then",
                    self.time, self.frame
                ),
            ));
        }
        if !self.levels.is_consistent(sections) {
            return Err(refuse(
                "levels",
                format!(
                    "levels for {} sections, the groom has {sections}",
                    self.levels.section_count()
                ),
            ));
        }
        if self.choices.len() != sections {
            return Err(refuse(
                "choices",
                format!(
                    "{} entries, the groom has {sections} sections",
                    self.choices.len()
                ),
            ));
        }
        if !self.selector_depths.is_empty() && self.selector_depths.len() != sections {
            return Err(refuse(
                "selector_depths",
                format!(
                    "{} entries: one per section ({sections}), or none",
                    self.selector_depths.len()
                ),
            ));
        }
        if let Some(index) = self.selector_depths.iter().position(|d| !d.is_finite()) {
            return Err(refuse(
                format!("selector_depths[{index}]"),
                format!("{} is not a finite depth [m]", self.selector_depths[index]),
            ));
        }
        if let Some(tolerance) = self.pixel_tolerance
            && !(tolerance.is_finite() && tolerance > 0.0)
        {
            return Err(refuse(
                "pixel_tolerance",
                format!("{tolerance}: a tolerance is a finite number of pixels above 0"),
            ));
        }
        self.levels
            .check_at(self.time)
            .map_err(|(field, why)| refuse(field, why))?;
        for (level, block) in self.blocks.iter() {
            block.check(groom, level)?;
            if block.sections != self.levels.members(level) {
                return Err(refuse(
                    format!("blocks.{}.sections", block_key(level)),
                    "does not hold the sections simulated at that level (levels.current and \
                     levels.blending)",
                ));
            }
            self.check_block_values(groom, level)?;
        }
        Ok(())
    }

    /// The values of the block of `level`: time, speeds, distances from the roots, collision
    /// memory.
    fn check_block_values(&self, groom: &Groom, level: Level) -> Result<()> {
        let block = &self.blocks[level];
        let field = |what: &str| format!("blocks.{}.{what}", block_key(level));
        let nodes = block.node_count();
        if nodes == 0 {
            return Ok(());
        }
        // A frame's substeps add up to its step in floating point: within a microsecond.
        if (block.state.time - self.time).abs() > 1e-6 {
            return Err(refuse(
                field("state.time"),
                format!(
                    "{} s, the state's time is {} s",
                    block.state.time, self.time
                ),
            ));
        }
        if let Some(index) = block
            .state
            .node_velocities
            .iter()
            .position(|v| v.length() > MAX_NODE_SPEED)
        {
            return Err(refuse(
                field(&format!("state.node_velocities[{index}]")),
                format!(
                    "{} m/s is faster than the {MAX_NODE_SPEED} m/s any hair node moves",
                    block.state.node_velocities[index].length()
                ),
            ));
        }
        let mut node = 0;
        for &chain in &block.chains {
            let count = groom.skeletons.chain_node_count(chain);
            let positions = &block.state.node_positions[node..node + count];
            let reach = groom.skeletons.chain_length(chain) + LENGTH_SLACK;
            if let Some(k) = positions
                .iter()
                .position(|p: &Vec3| p.distance(positions[0]) > reach)
            {
                return Err(refuse(
                    field(&format!("state.node_positions[{}]", node + k)),
                    format!(
                        "{:.4} m from its chain's root, the chain (groom chain {chain}) is {:.4} m \
                         long",
                        positions[k].distance(positions[0]),
                        reach - LENGTH_SLACK
                    ),
                ));
            }
            node += count;
        }
        let memory = &block.collision_memory;
        if !memory.positions.is_empty() && memory.positions.len() != nodes {
            return Err(refuse(
                field("collision_memory.positions"),
                format!(
                    "{} entries: one per node ({nodes}), or none",
                    memory.positions.len()
                ),
            ));
        }
        if let Some(time) = memory.time
            && !(time.is_finite() && time <= block.state.time)
        {
            return Err(refuse(
                field("collision_memory.time"),
                format!(
                    "{time} s: the collision's last step is at or before the block's time, {} s",
                    block.state.time
                ),
            ));
        }
        Ok(())
    }
}
