//! The observe stage of a frame: each section seen on its current level, its observation (size,
//! motion, place) and the pixels it covers, for the level selector and the cost model.

use hair_core::Camera;
use hair_core::Groom;
use hair_core::dynamics::Environment;
use hair_core::lod::{
    LodSettings, SectionObservation, covered_pixels, head_point_acceleration_from_poses,
    motion_measure,
};

use super::error::{PipelineError, Result};
use super::state::PipelineState;

/// What the observe stage reads: the model and the state, never written.
pub(super) struct Observed<'a> {
    /// The groom whose sections are observed.
    pub groom: &'a Groom,
    /// Head motion and wind (the sections' motion is measured against them).
    pub environment: &'a Environment,
    /// Air drag rate γ [1/s] of the skeletons' material.
    pub air_drag_rate: f32,
    /// The frame time [s].
    pub frame_time: f32,
    /// The pipeline's state (levels, blocks, time).
    pub state: &'a PipelineState,
    /// The selector's settings (what a covered pixel counts).
    pub lod: &'a LodSettings,
}

/// Writes every section's observation on its current level into `observations` and the pixels
/// it covers through `camera` into `section_pixels` (one each per section). Errors when a section
/// is not simulated at its level (a state that does not fit).
pub(super) fn observe_sections(
    observed: Observed<'_>,
    camera: &Camera,
    observations: &mut [SectionObservation],
    section_pixels: &mut [f64],
) -> Result<()> {
    let Observed {
        groom,
        environment,
        air_drag_rate,
        frame_time,
        state,
        lod,
    } = observed;
    // The head's poses a frame before, now and a frame after, once for every node.
    let head_poses = [-1.0, 0.0, 1.0].map(|k| {
        environment
            .head
            .transform_at(state.time + k * f64::from(frame_time))
    });
    let wind = &environment.wind;
    let time = state.time;
    for (section, observation) in observations.iter_mut().enumerate() {
        let level = state.levels.current()[section];
        let block = &state.blocks[level];
        let Some(slot) = block.slot(section) else {
            return Err(PipelineError::SectionNotAt { section, level });
        };
        let nodes = block.nodes(slot);
        let positions = &block.state.node_positions[nodes.clone()];
        let velocities = &block.state.node_velocities[nodes];
        let motion = motion_measure(
            positions,
            velocities,
            air_drag_rate,
            |x| wind.velocity_at(x, time),
            |x| head_point_acceleration_from_poses(&head_poses, frame_time, x),
        );
        *observation = SectionObservation::of_section(groom, section, level, positions, motion);
        section_pixels[section] = covered_pixels(camera, observation, lod);
    }
    Ok(())
}
