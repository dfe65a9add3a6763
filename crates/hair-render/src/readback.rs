//! The readback stage: the frame's render target, sized for the frame, and the copy of its
//! image out (back to the CPU, or into a caller's texture).

use crate::error::{RenderError, Result};
use crate::target::RenderTarget;

/// Where a drawn frame goes.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Destination<'a> {
    /// Read back into an image.
    Image,
    /// Copied into this texture on the GPU (checked by the caller).
    Texture(&'a wgpu::Texture),
}

/// The render target and the copy of its image out.
#[derive(Debug)]
pub(crate) struct Readback {
    sample_count: u32,
    /// The target of the last frame's size; `None` before the first frame.
    target: Option<RenderTarget>,
}

impl Readback {
    /// No target yet; targets are made with `sample_count`-times MSAA.
    pub fn new(sample_count: u32) -> Readback {
        Readback {
            sample_count,
            target: None,
        }
    }

    /// Makes the target `width`×`height` [pixels], replacing it when its size differs.
    pub fn prepare(&mut self, device: &wgpu::Device, width: u32, height: u32) -> Result<()> {
        let needs_new_target = self
            .target
            .as_ref()
            .is_none_or(|t| t.width() != width || t.height() != height);
        if needs_new_target {
            self.target = None;
            self.target = Some(RenderTarget::new(device, width, height, self.sample_count)?);
        }
        Ok(())
    }

    /// The target (after [`Readback::prepare`]).
    pub fn target(&self) -> Result<&RenderTarget> {
        self.target
            .as_ref()
            .ok_or_else(|| RenderError::Gpu("render target missing".into()))
    }

    /// Encodes the copy of the target's image to `destination`.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        destination: Destination<'_>,
    ) -> Result<()> {
        let target = self.target()?;
        match destination {
            Destination::Image => target.encode_readback(encoder),
            Destination::Texture(texture) => target.encode_copy_to(encoder, texture),
        }
        Ok(())
    }

    /// Waits for the submitted frame and reads its image (for [`Destination::Image`]), with the
    /// time spent waiting for the device and copying the image out [s].
    pub fn read(&self, device: &wgpu::Device) -> Result<(image::RgbaImage, f64, f64)> {
        self.target()?.read_image_timed(device)
    }
}
