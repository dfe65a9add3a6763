//! Offscreen render target: multisampled colour and depth, a resolve texture, and readback to an image.

use crate::error::{RenderError, Result, invalid};

/// Colour format of the target: 8-bit RGBA with sRGB encoding (shaders work in linear RGB).
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth format of the target.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Bytes per pixel of [`COLOR_FORMAT`].
const BYTES_PER_PIXEL: u32 = 4;

/// An offscreen colour + depth target of a fixed size [pixels], with `sample_count`-times MSAA.
///
/// With MSAA the scene is drawn into a multisampled colour texture that is resolved into a
/// single-sampled one, which is copied to a mappable buffer for readback.
#[derive(Debug)]
pub struct RenderTarget {
    width: u32,
    height: u32,
    sample_count: u32,
    /// Multisampled colour attachment (absent without MSAA).
    multisampled_view: Option<wgpu::TextureView>,
    /// Single-sampled colour texture: the resolve target, or the attachment itself without MSAA.
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    /// Mappable buffer with rows padded to [`wgpu::COPY_BYTES_PER_ROW_ALIGNMENT`].
    readback: wgpu::Buffer,
    padded_bytes_per_row: u32,
}

/// Bytes per row of a `width`-pixel readback, padded to wgpu's 256-byte copy alignment.
pub fn padded_bytes_per_row(width: u32) -> u32 {
    let unpadded = width * BYTES_PER_PIXEL;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    unpadded.div_ceil(align) * align
}

impl RenderTarget {
    /// Creates a `width`×`height` target [pixels] on `device`.
    ///
    /// Errors when a side is zero or exceeds the device's `max_texture_dimension_2d`.
    pub fn new(device: &wgpu::Device, width: u32, height: u32, sample_count: u32) -> Result<Self> {
        let max = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 {
            return Err(invalid(format!(
                "image size {width}x{height}: both sides must be at least 1 pixel"
            )));
        }
        if width > max || height > max {
            return Err(invalid(format!(
                "image size {width}x{height} exceeds this device's limit of {max} pixels per side"
            )));
        }
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = |label: &str, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let multisampled_view = (sample_count > 1).then(|| {
            texture(
                "hair-render msaa colour",
                COLOR_FORMAT,
                sample_count,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&wgpu::TextureViewDescriptor::default())
        });
        let resolved = texture(
            "hair-render resolved colour",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let resolved_view = resolved.create_view(&wgpu::TextureViewDescriptor::default());
        let depth_view = texture(
            "hair-render depth",
            DEPTH_FORMAT,
            sample_count,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&wgpu::TextureViewDescriptor::default());
        let padded_bytes_per_row = padded_bytes_per_row(width);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hair-render readback"),
            size: u64::from(padded_bytes_per_row) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Ok(RenderTarget {
            width,
            height,
            sample_count,
            multisampled_view,
            resolved,
            resolved_view,
            depth_view,
            readback,
            padded_bytes_per_row,
        })
    }

    /// Width [pixels].
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height [pixels].
    pub fn height(&self) -> u32 {
        self.height
    }

    /// MSAA sample count.
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// The colour attachment for a pass that clears to `clear` (linear RGBA), resolving when
    /// multisampled.
    pub fn color_attachment(&self, clear: wgpu::Color) -> wgpu::RenderPassColorAttachment<'_> {
        let (view, resolve_target) = match &self.multisampled_view {
            Some(multisampled) => (multisampled, Some(&self.resolved_view)),
            None => (&self.resolved_view, None),
        };
        wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                // The multisampled samples are not needed after the resolve.
                store: if resolve_target.is_some() {
                    wgpu::StoreOp::Discard
                } else {
                    wgpu::StoreOp::Store
                },
            },
        }
    }

    /// The depth attachment, cleared to the far plane (1.0).
    pub fn depth_attachment(&self) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth_view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Discard,
            }),
            stencil_ops: None,
        }
    }

    /// Records the copy of the resolved image into the readback buffer.
    pub fn encode_readback(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_bytes_per_row),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Records the copy of the resolved image into `destination` (for a window: a texture of
    /// [`COLOR_FORMAT`] and this target's size with `COPY_DST` usage, checked by the caller).
    pub fn encode_copy_to(&self, encoder: &mut wgpu::CommandEncoder, destination: &wgpu::Texture) {
        encoder.copy_texture_to_texture(
            self.resolved.as_image_copy(),
            destination.as_image_copy(),
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Maps the readback buffer (after the commands from [`Self::encode_readback`] were submitted)
    /// and returns the image, rows unpadded; sRGB-encoded RGBA8 as stored in the target.
    pub fn read_image(&self, device: &wgpu::Device) -> Result<image::RgbaImage> {
        self.read_image_timed(device).map(|(image, _, _)| image)
    }

    /// [`Self::read_image`], with the time spent waiting for the device and the time spent
    /// copying the image out [s].
    pub fn read_image_timed(&self, device: &wgpu::Device) -> Result<(image::RgbaImage, f64, f64)> {
        let row_bytes = (self.width * BYTES_PER_PIXEL) as usize;
        let started = std::time::Instant::now();
        let mut waited = 0.0;
        // Rows are copied straight out of the mapped buffer, without their padding.
        let pixels = map_and_with(device, &self.readback, |bytes| {
            waited = started.elapsed().as_secs_f64();
            let mut pixels = Vec::with_capacity(row_bytes * self.height as usize);
            for row in bytes.chunks_exact(self.padded_bytes_per_row as usize) {
                pixels.extend_from_slice(&row[..row_bytes]);
            }
            pixels
        })?;
        let copied = started.elapsed().as_secs_f64() - waited;
        let image =
            image::RgbaImage::from_raw(self.width, self.height, pixels).ok_or_else(|| {
                RenderError::Gpu("readback returned a buffer of the wrong size".into())
            })?;
        Ok((image, waited, copied))
    }
}

/// Maps `buffer` for reading, waits for the GPU, copies its whole contents out and unmaps it.
pub(crate) fn map_and_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    map_and_with(device, buffer, <[u8]>::to_vec)
}

/// Maps `buffer` for reading, waits for the GPU, hands the mapped bytes to `read` and unmaps it.
pub(crate) fn map_and_with<T>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    read: impl FnOnce(&[u8]) -> T,
) -> Result<T> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver waits below; a failed send only means it is gone.
        let _ = sender.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|error| RenderError::Gpu(format!("waiting for the GPU failed: {error}")))?;
    receiver
        .recv()
        .map_err(|_| RenderError::Gpu("buffer mapping was never answered".into()))?
        .map_err(|error| {
            RenderError::Gpu(format!("mapping the readback buffer failed: {error}"))
        })?;
    let result = {
        let mapped = buffer.get_mapped_range(..).map_err(|error| {
            RenderError::Gpu(format!("reading the mapped buffer failed: {error}"))
        })?;
        read(&mapped)
    };
    buffer.unmap();
    Ok(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_padded_to_256_bytes() {
        assert_eq!(padded_bytes_per_row(1), 256);
        assert_eq!(padded_bytes_per_row(64), 256);
        assert_eq!(padded_bytes_per_row(65), 512);
        assert_eq!(padded_bytes_per_row(1280), 5120);
    }
}
