//! The error of the frame pipeline: whichever stage failed, with its own message.

use hair_core::HairError;
use hair_core::dynamics::DynamicsError;

/// What went wrong in a frame.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The model or a parameter was invalid (a camera, a LOD setting, a groom).
    #[error(transparent)]
    Model(#[from] HairError),
    /// The dynamics failed (an unstable step, an invalid setting).
    #[error("dynamics: {0}")]
    Dynamics(#[from] DynamicsError),
    /// Collision detection failed.
    #[error("collision: {0}")]
    Collision(#[from] hair_collide::CollideError),
    /// The renderer failed.
    #[error("rendering: {0}")]
    Render(#[from] hair_render::RenderError),
    /// A state handed to the pipeline (a checkpoint) does not fit its scene.
    #[error("pipeline state: {0}")]
    State(String),
    /// A checkpoint could not be read or written, or belongs to another scene or version.
    #[error("checkpoint {path}: {why}")]
    Checkpoint {
        /// The checkpoint file.
        path: std::path::PathBuf,
        /// What is wrong with it.
        why: String,
    },
}

impl PipelineError {
    /// Whether the method failed rather than the run: an integrator step that went unstable
    /// (detected by the dynamics, whether it surfaced there or inside the collision stage).
    /// Sweeps report such a configuration as failed and go on.
    pub fn is_unstable(&self) -> bool {
        matches!(
            self,
            PipelineError::Dynamics(DynamicsError::Unstable(_))
                | PipelineError::Collision(hair_collide::CollideError::Dynamics(
                    DynamicsError::Unstable(_)
                ))
        )
    }
}

/// Result alias of the pipeline.
pub type Result<T, E = PipelineError> = std::result::Result<T, E>;
