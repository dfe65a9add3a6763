//! Rendering into a caller's texture (a viewer's window, `Renderer::render_to_texture`): the
//! texture receives exactly the image `Renderer::render` reads back, and a texture of the wrong
//! size, format or usage is an error, not a GPU validation panic.

mod common;

use common::*;
use hair_render::target::{COLOR_FORMAT, padded_bytes_per_row};
use hair_render::wgpu;
use hair_render::{Camera, FrameSettings, RenderError};

fn texture(
    device: &wgpu::Device,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test destination"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// Reads `texture` (RGBA8) back into an image.
fn read(gpu: &hair_render::GpuContext, texture: &wgpu::Texture) -> image::RgbaImage {
    let (width, height) = (texture.width(), texture.height());
    let row = padded_bytes_per_row(width);
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test readback"),
        size: u64::from(row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    gpu.queue.submit([encoder.finish()]);
    buffer.map_async(wgpu::MapMode::Read, .., |result| result.unwrap());
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .unwrap();
    let mapped = buffer.get_mapped_range(..).unwrap();
    let mut pixels = Vec::new();
    for line in mapped.chunks_exact(row as usize) {
        pixels.extend_from_slice(&line[..4 * width as usize]);
    }
    image::RgbaImage::from_raw(width, height, pixels).unwrap()
}

#[test]
fn a_frame_rendered_into_a_texture_is_the_frame_read_back() {
    let mut renderer = renderer();
    let chains = along_and_across_chains();
    renderer
        .upload_strands(&Strands::one_per_chain(&chains).set())
        .unwrap();
    let settings = FrameSettings::new(96, 64, Camera::default());
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let gpu = renderer.context().clone();
    let destination = texture(&gpu.device, 96, 64, COLOR_FORMAT);
    renderer
        .render_to_texture(&chains.frame(), &settings, &destination)
        .unwrap();
    let copied = read(&gpu, &destination);
    assert!(
        image.pixels().any(|p| p.0 != image.get_pixel(0, 0).0),
        "hair drawn"
    );
    assert!(
        copied == image,
        "the texture holds another image than the read-back one"
    );
}

#[test]
fn a_destination_of_another_size_or_format_is_an_error() {
    let mut renderer = renderer();
    let chains = along_and_across_chains();
    renderer
        .upload_strands(&Strands::one_per_chain(&chains).set())
        .unwrap();
    let settings = FrameSettings::new(96, 64, Camera::default());
    let gpu = renderer.context().clone();
    for destination in [
        texture(&gpu.device, 95, 64, COLOR_FORMAT),
        texture(&gpu.device, 96, 64, wgpu::TextureFormat::Bgra8UnormSrgb),
    ] {
        let error = renderer
            .render_to_texture(&chains.frame(), &settings, &destination)
            .unwrap_err();
        assert!(matches!(error, RenderError::InvalidInput(_)), "{error}");
        assert!(error.to_string().contains("96x64"), "{error}");
    }
}
