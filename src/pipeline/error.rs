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
}

/// Result alias of the pipeline.
pub type Result<T, E = PipelineError> = std::result::Result<T, E>;
