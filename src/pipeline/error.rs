//! The error of the frame pipeline: whichever stage failed, with its own message.
//!
//! A variant that wraps a stage's error prints that error's message after its own prefix and so
//! reports no [`source`](std::error::Error::source): an error-chain printer (`anyhow`'s `{:#}`)
//! would print the inner message twice otherwise.

use hair_core::dynamics::{DynamicsError, IntegratorKind};
use hair_core::{HairError, Level};

/// What went wrong in a frame.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The model or a parameter was invalid (a camera, a LOD setting, a groom).
    #[error(transparent)]
    Model(#[from] HairError),
    /// The dynamics failed (an unstable step, an invalid setting).
    #[error("dynamics: {0}")]
    Dynamics(DynamicsError),
    /// Collision detection failed.
    #[error("collision: {0}")]
    Collision(hair_collide::CollideError),
    /// The renderer failed.
    #[error("rendering: {0}")]
    Render(hair_render::RenderError),
    /// A chain came out of [`hang_groom`](crate::rest_pose::hang_groom)'s fall (still head, calm
    /// air, gravity the only input) with more kinetic energy than gravity could have given it:
    /// the integrator made energy on these skeletons. Without this check such a groom hangs as
    /// a porcupine, flailing, with no error.
    #[error(
        "hanging the groom: chain {chain} of the {} level ({nodes} nodes) ended its {seconds} s \
         fall with {energy_per_mass:.3} J/kg of kinetic energy, more than the {limit:.3} J/kg \
         that falling twice its length under gravity can give: the {} integrator at substep \
         {substep:.3e} s makes energy on these skeletons; {}",
        .level.name(),
        .integrator.name(),
        unsettled_hint(*.integrator)
    )]
    Unsettled {
        /// The level that was falling.
        level: Level,
        /// The groom chain with the most kinetic energy per unit mass.
        chain: usize,
        /// Its node count.
        nodes: usize,
        /// Simulated seconds of the fall [s].
        seconds: f32,
        /// Its kinetic energy per unit mass at the end of the fall [J/kg].
        energy_per_mass: f32,
        /// The most gravity can give it, `2·g·L` for its length `L` [J/kg].
        limit: f32,
        /// The integrator of the fall.
        integrator: IntegratorKind,
        /// Its substep [s].
        substep: f32,
    },
    /// The dynamics went unstable while [`hang_groom`](crate::rest_pose::hang_groom) let the
    /// groom fall into its hanging shape (the message adds what to change to the stage's).
    #[error(
        "hanging the groom at the {} level: {error}; {}",
        .level.name(),
        unsettled_hint(*.integrator)
    )]
    HangUnstable {
        /// The level that was falling.
        level: Level,
        /// The integrator of the fall.
        integrator: IntegratorKind,
        /// The stage's error (an unstable step).
        error: Box<PipelineError>,
    },
    /// A call that must come between frames came while a frame was begun and not finished
    /// ([`Pipeline::begin_frame`](crate::pipeline::Pipeline::begin_frame)).
    #[error("pipeline state: a frame is begun and not finished: {action}")]
    FrameBegun {
        /// What to do instead (`take the state between frames`).
        action: &'static str,
    },
    /// Something that chooses levels asked of a run whose levels are fixed.
    #[error("pipeline state: {what} needs automatic levels (the levels are fixed)")]
    FixedLevels {
        /// What needs them (`a frame budget`).
        what: &'static str,
    },
    /// A checkpoint of another model (scene, groom, environment or settings) than the run's.
    #[error(
        "pipeline state: the checkpoint is of another scene (its fingerprint {theirs}, this \
         scene's {ours}): resume with the scene file, groom and settings that wrote it"
    )]
    ForeignCheckpoint {
        /// The checkpoint's model fingerprint.
        theirs: String,
        /// The run's.
        ours: String,
    },
    /// A state of automatic levels given to a run at a fixed level, or the other way round.
    #[error(
        "pipeline state: the state is of automatic levels and the settings fix one (or the \
         other way round)"
    )]
    LodModeMismatch,
    /// A shared collision body built from another mesh than the scene's head (a crowd's
    /// characters that wear one groom on one head share its body).
    #[error(
        "pipeline state: the shared collision body has {body} triangles, the scene's head \
         {head}: share the body built from this scene's head mesh"
    )]
    SharedBodyMismatch {
        /// The body's triangle count.
        body: usize,
        /// The scene head's.
        head: usize,
    },
    /// A section missing from the block it should be simulated in (a state that does not fit
    /// its groom).
    #[error("pipeline state: section {section} is not simulated at the {} level", .level.name())]
    SectionNotAt {
        /// The section.
        section: usize,
        /// The level it should be at.
        level: Level,
    },
    /// A section arriving at a level that no other level simulates (nothing to hand over from).
    #[error("pipeline state: section {section} is simulated at no level to hand over from")]
    NothingToHandOver {
        /// The section.
        section: usize,
    },
    /// A level's block that does not fit the groom (an edited or damaged checkpoint).
    #[error("pipeline state: {} block: {why}", .level.name())]
    Block {
        /// The block's level.
        level: Level,
        /// What is wrong with it.
        why: String,
    },
    /// A crowd asked of a shot without `[[character]]` tables.
    #[error("pipeline state: the shot has no characters: a crowd needs [[character]] tables")]
    NoCharacters,
    /// Frames asked of a run that lie outside its shot.
    #[error("pipeline state: frames {start}..{end} are not within the shot's 0..{frames}")]
    FramesOutsideShot {
        /// The first frame asked for.
        start: usize,
        /// One past the last.
        end: usize,
        /// The shot's frame count.
        frames: usize,
    },
    /// A run asked to start at a frame it cannot start from.
    #[error(
        "pipeline state: the run starts at frame {start}, but {}",
        match .checkpoint {
            Some(at) => format!("the checkpoint is at frame {at}: resume with --frames {at}.."),
            None => "no checkpoint is given to start there from (--resume FILE)".to_string(),
        }
    )]
    StartFrame {
        /// The frame asked to start at.
        start: usize,
        /// The checkpoint's frame, when one is given.
        checkpoint: Option<usize>,
    },
    /// A frame asked of a reference run that has none there.
    #[error("pipeline state: the reference has no frame {frame}")]
    NoReferenceFrame {
        /// The frame.
        frame: usize,
    },
    /// A crowd whose estimated memory is over what the machine has available, refused before
    /// its pipelines are built ([`crate::crowd::memory`]).
    #[error("{message}")]
    CrowdTooLarge {
        /// The estimate, what it is made of and what is available.
        message: String,
    },
    /// A field of a restored state breaks its invariant (an edited or damaged checkpoint).
    #[error("pipeline state: {field}: {why}")]
    StateField {
        /// The field, as written in the checkpoint (`blocks.strand_group.state.time`).
        field: String,
        /// What is wrong with its value.
        why: String,
    },
    /// A checkpoint could not be read or written, or belongs to another scene or version.
    #[error("checkpoint {path}: {why}")]
    Checkpoint {
        /// The checkpoint file.
        path: std::path::PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// A simulation cache's record could not be read or written, is missing, damaged, or
    /// belongs to another run or version ([`crate::cache`]).
    #[error(
        "cache {path}{}: {why}",
        .frame.map(|frame| format!(" (frame {frame})")).unwrap_or_default()
    )]
    Cache {
        /// The record file (or the cache folder).
        path: std::path::PathBuf,
        /// The frame the record is of, when one is.
        frame: Option<usize>,
        /// What is wrong.
        why: String,
    },
}

/// What to do about a groom that [`PipelineError::Unsettled`] or [`PipelineError::HangUnstable`]
/// refused, hung with `integrator`.
fn unsettled_hint(integrator: IntegratorKind) -> &'static str {
    match integrator {
        IntegratorKind::LinearImplicit => {
            "linear-implicit fails on curly skeletons finer than the presets' (docs/dynamics.md, \
             \"Where linear-implicit fails\"): set `integrator = \"xpbd\"` in the scene's [dynamics], or \
             a larger `smoothness` in its [groom]"
        }
        IntegratorKind::Xpbd => {
            "a smaller time step in the scene's [dynamics] or a larger `smoothness` in its [groom] \
             may hold it"
        }
        _ => "set `integrator = \"xpbd\"` in the scene's [dynamics], or a smaller time step",
    }
}

impl From<DynamicsError> for PipelineError {
    fn from(error: DynamicsError) -> Self {
        PipelineError::Dynamics(error)
    }
}

impl From<hair_collide::CollideError> for PipelineError {
    fn from(error: hair_collide::CollideError) -> Self {
        PipelineError::Collision(error)
    }
}

impl From<hair_render::RenderError> for PipelineError {
    fn from(error: hair_render::RenderError) -> Self {
        PipelineError::Render(error)
    }
}

impl PipelineError {
    /// Whether the method failed rather than the run: an integrator step that went unstable
    /// (detected by the dynamics, whether it surfaced there or inside the collision stage), or a
    /// groom whose hang made energy.
    /// Sweeps report such a configuration as failed and go on.
    pub fn is_unstable(&self) -> bool {
        match self {
            PipelineError::HangUnstable { error, .. } => error.is_unstable(),
            _ => matches!(
                self,
                PipelineError::Dynamics(DynamicsError::Unstable(_))
                    | PipelineError::Unsettled { .. }
                    | PipelineError::Collision(hair_collide::CollideError::Dynamics(
                        DynamicsError::Unstable(_)
                    ))
            ),
        }
    }
}

/// Result alias of the pipeline.
pub type Result<T, E = PipelineError> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;
    use hair_core::dynamics::{ChainFailure, FailedQuantity, IntegratorKind};

    /// Every message along an error's source chain, joined as `anyhow`'s `{:#}` prints them.
    fn chain(error: &dyn std::error::Error) -> String {
        let mut text = error.to_string();
        let mut next = error.source();
        while let Some(cause) = next {
            text.push_str(": ");
            text.push_str(&cause.to_string());
            next = cause.source();
        }
        text
    }

    #[test]
    fn an_unstable_step_inside_the_collision_stage_is_reported_once() {
        let unstable = DynamicsError::Unstable(ChainFailure {
            integrator: IntegratorKind::LinearImplicit,
            time: 0.0,
            substep: 1.0 / 240.0,
            halvings: 0,
            chain: 372,
            node: None,
            quantity: FailedQuantity::NonFiniteVelocity,
        });
        let message = unstable.to_string();
        let error = PipelineError::from(hair_collide::CollideError::from(unstable));
        assert!(error.is_unstable());
        let printed = chain(&error);
        assert_eq!(printed, format!("collision: dynamics: {message}"));
        assert_eq!(printed.matches("became unstable").count(), 1, "{printed}");
    }
}
