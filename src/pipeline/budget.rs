//! The frame budget (§7's alternative to the pixel tolerance): the levels that minimise the
//! total estimated error within a budget of seconds per frame. One code path serves a character
//! alone and a crowd (a world of one or of many, [`super::world_pipeline`]): every character's
//! sections' options are gathered, refined together ([`choose_within_budget`]) and handed back
//! as each character's levels.

use hair_core::Level;
use hair_core::lod::{BudgetOutcome, CostModel, SectionOptions, refine_within_budget};

use super::error::{PipelineError, Result};
use super::report::FrameReport;

/// A frame budget [s] and the cost model it is spent by.
pub type FrameBudget = (f64, CostModel);

/// Checks a frame budget before it is taken: levels must be automatic (`automatic`) and the
/// budget a positive number of seconds.
pub(crate) fn check_budget(budget: Option<&FrameBudget>, automatic: bool) -> Result<()> {
    let Some((seconds, _)) = budget else {
        return Ok(());
    };
    if !automatic {
        return Err(PipelineError::FixedLevels {
            what: "a frame budget",
        });
    }
    if !(seconds.is_finite() && *seconds > 0.0) {
        return Err(hair_core::HairError::invalid(
            "frame budget (s)",
            seconds,
            "a positive number of seconds",
        )
        .into());
    }
    Ok(())
}

/// Chooses a level for every section of `options` within `budget` (into `levels`, one per
/// option), minimising the total estimated error; the frame's overhead is not any section's, so
/// it is left out of what they share.
pub(crate) fn choose_within_budget(
    options: &[SectionOptions],
    (seconds, model): &FrameBudget,
    levels: &mut Vec<Level>,
) -> BudgetOutcome {
    let share = (seconds - model.rates().overhead).max(0.0);
    levels.resize(options.len(), Level::Patch);
    refine_within_budget(options, share, levels)
}

/// Calibrates the budget's cost model (if any) with a finished frame's `report`.
pub(crate) fn calibrate(budget: Option<&mut FrameBudget>, report: &FrameReport) {
    if let Some((_, model)) = budget {
        report.calibrate(model);
    }
}
