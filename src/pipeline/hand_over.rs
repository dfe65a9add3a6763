//! The hand-over stage (DESIGN "One frame", step 2, §4.2): the level blocks laid out at rest at
//! the start of a run, and rebuilt where sections changed level, the arriving sections' state
//! mapped over from the level they leave; the working memory rebuilt around the new blocks.

use hair_core::dynamics::DynamicsParams;
use hair_core::{Groom, Level, PerLevel, RigidTransform};

use super::block::LevelBlock;
use super::body_motion::{BodyRide, chain_roots};
use super::error::Result;
use super::settings::PipelineSettings;
use super::state::PipelineState;
use super::work::Workspace;

/// What the hand-over reads of the model: the groom, the skeletons' material, the settings and
/// where the roots ride a deforming body.
#[derive(Clone, Copy)]
pub(crate) struct HandOverModel<'a> {
    pub(crate) groom: &'a Groom,
    pub(crate) params: DynamicsParams,
    pub(crate) settings: &'a PipelineSettings,
    pub(crate) ride: Option<&'a BodyRide>,
}

/// Builds the blocks of the state's levels with every skeleton in its rest shape on the head at
/// `head`, and the working memory around them.
pub(crate) fn start_at_rest(
    model: HandOverModel<'_>,
    state: &mut PipelineState,
    work: &mut Workspace,
    head: &RigidTransform,
) -> Result<()> {
    for level in Level::ALL {
        let sections = state.levels.members(level);
        state.blocks[level] = LevelBlock::laid_out(model.groom, level, sections, state.time);
        let level_work = &mut work.levels[level];
        level_work.rebuild_simulation(
            model.groom,
            &state.blocks[level],
            model.params,
            model.settings,
        )?;
        if let Some(simulation) = &level_work.simulation {
            state.blocks[level].state.node_positions = simulation.model().rest.rest_positions(head);
        }
    }
    work.refresh_collision_chains(model.groom, &state.blocks)
}

/// Rebuilds the blocks whose sections changed (a section switched level or a blend ended):
/// sections that stay keep their state bit for bit, arriving ones are handed over (§4.2) on the
/// head at `head`, their roots where the deforming body carries them at the state's time.
pub(crate) fn apply_level_changes(
    model: HandOverModel<'_>,
    state: &mut PipelineState,
    work: &mut Workspace,
    head: &RigidTransform,
) -> Result<()> {
    let roots = chain_roots(model.ride, head, state.time);
    let mut rebuilt = PerLevel::from_fn(|_| None);
    for level in Level::ALL {
        let members = state.levels.members(level);
        if members == state.blocks[level].sections {
            continue;
        }
        rebuilt[level] = Some(LevelBlock::handed_over(
            model.groom,
            level,
            members,
            &state.blocks,
            state.time,
            &roots,
        )?);
    }
    for level in Level::ALL {
        if let Some(block) = rebuilt[level].take() {
            state.blocks[level] = block;
            work.levels[level].rebuild_simulation(
                model.groom,
                &state.blocks[level],
                model.params,
                model.settings,
            )?;
        }
    }
    work.refresh_collision_chains(model.groom, &state.blocks)
}

/// Rebuilds every level's working memory around the blocks of a restored `state`.
pub(crate) fn rebuild_all(
    model: HandOverModel<'_>,
    state: &PipelineState,
    work: &mut Workspace,
) -> Result<()> {
    for level in Level::ALL {
        let level_work = &mut work.levels[level];
        level_work.rebuild_simulation(
            model.groom,
            &state.blocks[level],
            model.params,
            model.settings,
        )?;
        if let Some(solver) = &mut level_work.solver {
            solver.set_velocity_memory(&state.blocks[level].collision_memory);
        }
    }
    work.refresh_collision_chains(model.groom, &state.blocks)
}
