//! The selection stage (DESIGN "One frame", step 2, §7): each section's level chosen, by the
//! selector at the pixel tolerance or from levels a frame budget gave, and the changes started in
//! the state (switches and fades blended over the selector's blend time).

use hair_core::lod::{LodSelector, SectionChoice};
use hair_core::{Level, RigidTransform};

use super::error::Result;
use super::state::PipelineState;

/// Where the frame's levels come from.
pub(crate) enum LevelSource<'a> {
    /// The selector's own choice at its pixel tolerance, from the sections' observations.
    Tolerance {
        observations: &'a [hair_core::lod::SectionObservation],
        camera: &'a hair_core::Camera,
        head: &'a RigidTransform,
    },
    /// Levels chosen by a frame budget (one per section, each raised to its floor).
    Given(&'a [Level]),
}

/// Chooses levels from `source` and starts the changes in `state`; returns how many sections
/// changed level and how many came into view or left it.
pub(crate) fn select_levels(
    selector: &mut LodSelector,
    state: &mut PipelineState,
    source: LevelSource<'_>,
) -> Result<(usize, usize)> {
    let choices: &[SectionChoice] = match source {
        LevelSource::Given(levels) => selector.choose_levels(levels)?,
        LevelSource::Tolerance {
            observations,
            camera,
            head,
        } => selector.select(observations, camera, head)?,
    };
    state.choices.copy_from_slice(choices);
    state.selector_depths.clear();
    state.selector_depths.extend_from_slice(selector.depths());
    // The first frame picks the starting levels outright: there is nothing on screen to blend
    // from.
    let blend = if state.frame == 0 {
        0.0
    } else {
        selector.settings().blend_time
    };
    let time = state.time;
    let mut changes = 0;
    let mut visibility_changes = 0;
    let shares = selector.blend_shares();
    for (section, choice) in state.choices.iter().enumerate() {
        if state.levels.current()[section] != choice.level {
            // A switch the look ahead foresaw sooner than its lead blends over its share.
            let share = shares[section];
            state
                .levels
                .switch(section, choice.level, time, blend * share);
            changes += 1;
        }
        // Coming into view or leaving it fades over the blend too: a section drawn at once where
        // the conservative occlusion test or the frustum let it through would pop.
        if state
            .levels
            .set_visible(section, choice.visible, time, blend)
        {
            visibility_changes += 1;
        }
    }
    Ok((changes, visibility_changes))
}
