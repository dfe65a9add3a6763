//! The error type of `hair-collide`: bad sizes, non-finite numbers and broken meshes, named.
//!
//! A variant that wraps another crate's error prints its message and so reports no
//! [`source`](std::error::Error::source) (an error-chain printer would print it twice).

use thiserror::Error;

/// Errors from building or updating collision volumes, hierarchies and bodies.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CollideError {
    /// Two arrays that must agree in size do not.
    #[error("size mismatch: {what} has {actual} entries, expected {expected}")]
    SizeMismatch {
        /// What was being sized (`node_positions`, `control_points`).
        what: &'static str,
        /// The size that was given.
        actual: usize,
        /// The size that was required.
        expected: usize,
    },
    /// A coordinate or parameter is NaN or infinite.
    #[error("non-finite {what} at index {index}")]
    NonFinite {
        /// What holds the bad number (`node_positions`, `thickness`).
        what: &'static str,
        /// Index of the offending entry.
        index: usize,
    },
    /// A parameter is outside its allowed range.
    #[error("invalid {name}: {value} (allowed: {allowed})")]
    InvalidParameter {
        /// Name of the parameter.
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The chain offsets are not a valid `0 = o_0 <= o_1 <= ... = node count` sequence.
    #[error("invalid chain offsets: {reason}")]
    InvalidOffsets {
        /// What is wrong, in words.
        reason: String,
    },
    /// A mesh fails [`hair_core::TriangleMesh::validate_surface`]: the error names the problem.
    #[error("invalid mesh: {0}")]
    Mesh(hair_core::mesh::MeshError),
    /// The dynamics step failed (see [`hair_core::dynamics::DynamicsError`]).
    #[error("dynamics: {0}")]
    Dynamics(hair_core::dynamics::DynamicsError),
}

impl From<hair_core::mesh::MeshError> for CollideError {
    fn from(error: hair_core::mesh::MeshError) -> Self {
        CollideError::Mesh(error)
    }
}

impl From<hair_core::dynamics::DynamicsError> for CollideError {
    fn from(error: hair_core::dynamics::DynamicsError) -> Self {
        CollideError::Dynamics(error)
    }
}

/// Result alias for `hair-collide`.
pub type Result<T, E = CollideError> = std::result::Result<T, E>;

/// Checks that every point is finite; names the first bad one.
pub(crate) fn require_finite_points(what: &'static str, points: &[glam::Vec3]) -> Result<()> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(index) => Err(CollideError::NonFinite { what, index }),
        None => Ok(()),
    }
}

/// Checks that `actual == expected`.
pub(crate) fn require_len(what: &'static str, actual: usize, expected: usize) -> Result<()> {
    if actual == expected {
        Ok(())
    } else {
        Err(CollideError::SizeMismatch {
            what,
            actual,
            expected,
        })
    }
}

/// Checks a rigid pose (a finite, non-zero rotation and a finite translation) and returns the
/// rotation normalised.
pub(crate) fn require_pose(rotation: glam::Quat, translation: glam::Vec3) -> Result<glam::Quat> {
    if !rotation.is_finite() || rotation.length_squared() == 0.0 {
        return Err(CollideError::NonFinite {
            what: "body rotation",
            index: 0,
        });
    }
    if !translation.is_finite() {
        return Err(CollideError::NonFinite {
            what: "body translation",
            index: 0,
        });
    }
    Ok(rotation.normalize())
}
