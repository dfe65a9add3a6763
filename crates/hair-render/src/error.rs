//! The renderer's error type: device, input validation, GPU and output failures.
//!
//! Every message is whole (a wrapped error's message is part of it), so no variant reports a
//! [`source`](std::error::Error::source): an error-chain printer would print it twice.

use std::path::PathBuf;

/// What to install when no adapter is found (Debian/Ubuntu package names).
pub const INSTALL_HINT: &str = "install Mesa's CPU drivers: `apt-get install mesa-vulkan-drivers` \
     (lavapipe, Vulkan backend) or `apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri` \
     (llvmpipe through EGL, GL backend; `libegl1-mesa` on older releases), or a GPU driver";

/// Everything that can go wrong while acquiring a device, rendering or writing frames.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter was found on the requested backends.
    #[error("no graphics adapter found on backend(s) {backends}; {hint}")]
    NoAdapter {
        /// The backends that were searched, e.g. `vulkan, gl`.
        backends: String,
        /// What to install ([`INSTALL_HINT`]).
        hint: &'static str,
    },
    /// Adapters were found, but none could open a device the renderer can use.
    #[error("no usable graphics adapter: {details}; {hint}")]
    NoUsableAdapter {
        /// Why each adapter was rejected.
        details: String,
        /// What to install ([`INSTALL_HINT`]).
        hint: &'static str,
    },
    /// `HAIRLOD_BACKEND` (or a backend name) was not one of `vulkan`, `gl`, `auto`.
    #[error("unknown backend {value:?} (from {source_name}); expected `vulkan`, `gl` or `auto`")]
    UnknownBackend {
        /// The rejected value.
        value: String,
        /// Where it came from, e.g. `HAIRLOD_BACKEND`.
        source_name: String,
    },
    /// Input arrays or parameters are inconsistent or not finite.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The head mesh fails [`hair_core::TriangleMesh::validate`]: the error names the problem.
    #[error("invalid head mesh: {0}")]
    InvalidMesh(hair_core::mesh::MeshError),
    /// A wgpu validation or out-of-memory error, or a failed readback.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// Writing a file failed.
    #[error("cannot write {path}: {cause}")]
    Io {
        /// The file or folder that could not be written.
        path: PathBuf,
        /// The underlying error.
        cause: std::io::Error,
    },
    /// Encoding an image failed.
    #[error("cannot encode {path}: {cause}")]
    Encode {
        /// The file that was being written.
        path: PathBuf,
        /// The underlying error.
        cause: image::ImageError,
    },
}

impl From<hair_core::mesh::MeshError> for RenderError {
    fn from(error: hair_core::mesh::MeshError) -> Self {
        RenderError::InvalidMesh(error)
    }
}

/// Shorthand for the renderer's results.
pub type Result<T, E = RenderError> = std::result::Result<T, E>;

/// Builds a [`RenderError::InvalidInput`] from a message.
pub(crate) fn invalid(message: impl Into<String>) -> RenderError {
    RenderError::InvalidInput(message.into())
}
