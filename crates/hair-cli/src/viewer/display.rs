//! The window's GPU side: the surface, the composed image (the renderer's frame with the HUD
//! drawn over it, kept in a texture so that a screenshot reads exactly what is shown), the copy
//! of that image onto the surface, and the egui renderer.

use std::sync::Arc;

use anyhow::{Context, Result, anyhow};
use hairlod::render::target::{COLOR_FORMAT, padded_bytes_per_row};
use hairlod::render::wgpu;
use hairlod::render::{DeviceOptions, GpuContext, acquire_device_for_surface};
use winit::window::Window;

/// The window's surface and the textures and pipelines that fill it.
pub struct Display {
    pub(super) gpu: GpuContext,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The format the surface is drawn in (sRGB where the surface allows it).
    view_format: wgpu::TextureFormat,
    composed: wgpu::Texture,
    composed_view: wgpu::TextureView,
    blit_layout: wgpu::BindGroupLayout,
    blit_pipeline: wgpu::RenderPipeline,
    blit_group: wgpu::BindGroup,
    pub(super) egui: egui_wgpu::Renderer,
}

impl Display {
    /// Opens a device that can present to `window` and configures its surface.
    pub fn new(
        instance: &wgpu::Instance,
        window: Arc<Window>,
        options: &DeviceOptions,
    ) -> Result<Display> {
        let size = window.inner_size();
        let surface = instance
            .create_surface(window)
            .context("cannot make a wgpu surface for the window")?;
        let gpu = acquire_device_for_surface(instance, &surface, options)?;
        let capabilities = surface.get_capabilities(&gpu.adapter);
        let format = capabilities
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| capabilities.formats.first().copied())
            .ok_or_else(|| anyhow!("the adapter offers no format to draw into the window"))?;
        let view_format = format.add_srgb_suffix();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoNoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: capabilities
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            color_space: wgpu::SurfaceColorSpace::Auto,
            view_formats: if view_format == format {
                Vec::new()
            } else {
                vec![view_format]
            },
        };
        surface.configure(&gpu.device, &config);
        let device = &gpu.device;
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("hairlod view blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("blit.wgsl").into()),
        });
        let blit_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlod view blit"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlod view blit"),
            bind_group_layouts: &[Some(&blit_layout)],
            immediate_size: 0,
        });
        let blit_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("hairlod view blit"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(view_format.into())],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: None,
        });
        let (composed, composed_view, blit_group) =
            composed_texture(device, &blit_layout, config.width, config.height);
        let egui = egui_wgpu::Renderer::new(
            device,
            COLOR_FORMAT,
            egui_wgpu::RendererOptions {
                dithering: false,
                ..Default::default()
            },
        );
        Ok(Display {
            gpu,
            surface,
            config,
            view_format,
            composed,
            composed_view,
            blit_layout,
            blit_pipeline,
            blit_group,
            egui,
        })
    }

    /// The size the frames are drawn at [pixels].
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Follows a window resize (a zero side, a minimised window, is ignored).
    pub fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 || (width, height) == self.size() {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.gpu.device, &self.config);
        let (texture, view, group) =
            composed_texture(&self.gpu.device, &self.blit_layout, width, height);
        self.composed = texture;
        self.composed_view = view;
        self.blit_group = group;
    }

    /// The texture the renderer draws the frame into (then the HUD over it).
    pub fn composed(&self) -> &wgpu::Texture {
        &self.composed
    }

    /// Draws egui's `jobs` over the composed image.
    pub fn draw_hud(
        &mut self,
        jobs: &[egui::ClippedPrimitive],
        mut textures: egui::TexturesDelta,
        pixels_per_point: f32,
    ) {
        let device = &self.gpu.device;
        let queue = &self.gpu.queue;
        for (id, deltas) in &textures.set {
            for delta in deltas {
                self.egui.update_texture(device, queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point,
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlod view hud"),
        });
        let mut commands = self
            .egui
            .update_buffers(device, queue, &mut encoder, jobs, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hairlod view hud"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.composed_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.egui.render(&mut pass.forget_lifetime(), jobs, &screen);
        }
        commands.push(encoder.finish());
        queue.submit(commands);
        for id in &textures.free {
            self.egui.free_texture(id);
        }
        // Every delta is applied (egui checks that none is dropped unapplied).
        textures.clear();
    }

    /// Copies the composed image onto the window and presents it. An outdated or lost surface
    /// is configured again and the frame skipped; a hidden window skips it.
    pub fn present(&mut self) -> Result<()> {
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(texture)
            | wgpu::CurrentSurfaceTexture::Suboptimal(texture) => texture,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.gpu.device, &self.config);
                return Ok(());
            }
            other => return Err(anyhow!("the window's surface failed: {other:?}")),
        };
        let view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format),
            ..Default::default()
        });
        let device = &self.gpu.device;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlod view present"),
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hairlod view present"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.blit_pipeline);
            pass.set_bind_group(0, &self.blit_group, &[]);
            pass.draw(0..3, 0..1);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.queue.present(texture);
        Ok(())
    }

    /// Waits until the GPU has done everything submitted (so a frame's rendering time is the
    /// GPU's too, not only the recording).
    pub fn wait_for_gpu(&self) -> Result<()> {
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|error| anyhow!("waiting for the GPU failed: {error}"))?;
        Ok(())
    }

    /// Reads the composed image back (what the window shows: the frame and the HUD).
    pub fn read_composed(&self) -> Result<image::RgbaImage> {
        let (width, height) = self.size();
        let row = padded_bytes_per_row(width);
        let device = &self.gpu.device;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlod view screenshot"),
            size: u64::from(row) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hairlod view screenshot"),
        });
        encoder.copy_texture_to_buffer(
            self.composed.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.gpu.queue.submit([encoder.finish()]);
        let (sender, receiver) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |result| {
            // The receiver waits below; a failed send only means it is gone.
            let _ = sender.send(result);
        });
        self.wait_for_gpu()?;
        receiver
            .recv()
            .map_err(|_| anyhow!("the screenshot's buffer mapping was never answered"))?
            .map_err(|error| anyhow!("mapping the screenshot's buffer failed: {error}"))?;
        let pixels = {
            let mapped = buffer
                .get_mapped_range(..)
                .map_err(|error| anyhow!("reading the screenshot's buffer failed: {error}"))?;
            let row_bytes = width as usize * 4;
            let mut pixels = Vec::with_capacity(row_bytes * height as usize);
            for line in mapped.chunks_exact(row as usize) {
                pixels.extend_from_slice(&line[..row_bytes]);
            }
            pixels
        };
        buffer.unmap();
        image::RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| anyhow!("the screenshot has the wrong size"))
    }
}

/// The composed image's texture (the renderer's colour format), its view and the blit's bind
/// group on it.
fn composed_texture(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    width: u32,
    height: u32,
) -> (wgpu::Texture, wgpu::TextureView, wgpu::BindGroup) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("hairlod view composed"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: COLOR_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hairlod view blit"),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::TextureView(&view),
        }],
    });
    (texture, view, group)
}
