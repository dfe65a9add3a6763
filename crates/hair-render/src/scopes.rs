//! wgpu error scopes around a group of GPU calls, turned into [`RenderError::Gpu`].

use crate::error::{RenderError, Result};

/// Validation and out-of-memory error scopes around a group of GPU calls.
pub(crate) struct ErrorScopes {
    out_of_memory: wgpu::ErrorScopeGuard,
    validation: wgpu::ErrorScopeGuard,
}

impl ErrorScopes {
    /// Pushes both scopes on `device`.
    pub fn push(device: &wgpu::Device) -> ErrorScopes {
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        ErrorScopes {
            out_of_memory,
            validation,
        }
    }

    /// Pops both scopes; the first error captured becomes [`RenderError::Gpu`] naming `what`.
    pub fn pop(self, what: &str) -> Result<()> {
        let validation = pollster::block_on(self.validation.pop());
        let out_of_memory = pollster::block_on(self.out_of_memory.pop());
        match validation.or(out_of_memory) {
            None => Ok(()),
            Some(error) => Err(RenderError::Gpu(format!("{what}: {error}"))),
        }
    }
}
