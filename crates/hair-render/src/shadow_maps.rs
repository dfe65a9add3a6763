//! The GPU side of self-shadowing: the light-space depth and opacity maps, the bind groups that
//! read them, the light passes' globals, and the encoding of the two light passes (see
//! [`crate::shadows`] for the method).

use crate::batches::Batch;
use crate::shadow_pipelines::{LIGHT_DEPTH_FORMAT, LightPass, OPACITY_FORMAT};
use crate::target::DEPTH_FORMAT;
use crate::uniforms::{Globals, SHADOW_AROUND_SEGMENTS};

/// A depth map and an opacity map of one resolution.
#[derive(Debug)]
struct Maps {
    resolution: u32,
    /// The depth pass's depth attachment.
    depth_attachment: wgpu::TextureView,
    /// The nearest depth per texel, as the shaders read it.
    depth_view: wgpu::TextureView,
    opacity_view: wgpu::TextureView,
    /// Group 2 of the camera pass: both maps.
    lookup: wgpu::BindGroup,
    /// Group 2 of the opacity pass: the depth map (the opacity map is its target).
    opacity_pass: wgpu::BindGroup,
}

/// Shadow maps, created at the first shadowed frame of each resolution and kept (a zoom passes
/// through a few power-of-two sizes, see [`crate::shadows::map_resolution`]).
#[derive(Debug)]
pub(crate) struct ShadowMaps {
    sampler: wgpu::Sampler,
    /// 1×1 maps that let no shadow through: group 2 when self-shadowing is off, and in the depth
    /// pass (which writes the real depth map).
    unshadowed: wgpu::BindGroup,
    /// The maps of every resolution used so far.
    maps: Vec<Maps>,
    /// Index in `maps` of this frame's.
    current: Option<usize>,
    /// The globals of the light passes (drawn through the light's view).
    pub light_globals: wgpu::Buffer,
}

fn texture(
    device: &wgpu::Device,
    label: &str,
    side: u32,
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

fn maps_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    depth: &wgpu::TextureView,
    opacity: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hair-render shadow maps"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(depth),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(opacity),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}

impl ShadowMaps {
    /// The sampler, the unshadowed 1×1 maps and the light passes' globals buffer.
    pub fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> ShadowMaps {
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("hair-render opacity map"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..wgpu::SamplerDescriptor::default()
        });
        // Never written: a depth map and an opacity map of zeros (no hair in front of anything).
        let depth = texture(device, "hair-render no depth map", 1, LIGHT_DEPTH_FORMAT);
        let opacity = texture(device, "hair-render no opacity map", 1, OPACITY_FORMAT);
        let unshadowed = maps_group(device, layout, &depth, &opacity, &sampler);
        let light_globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hair-render light globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ShadowMaps {
            sampler,
            unshadowed,
            maps: Vec::new(),
            current: None,
            light_globals,
        }
    }

    /// Group 2 of a camera pass without self-shadowing.
    pub fn unshadowed(&self) -> &wgpu::BindGroup {
        &self.unshadowed
    }

    /// Makes `resolution`² maps the current ones (reusing those of that size when made before);
    /// returns the camera pass's group 2 reading them.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        resolution: u32,
    ) -> wgpu::BindGroup {
        let index = match self.maps.iter().position(|m| m.resolution == resolution) {
            Some(index) => index,
            None => {
                let depth_attachment = texture(
                    device,
                    "hair-render depth map attachment",
                    resolution,
                    DEPTH_FORMAT,
                );
                let depth_view = texture(
                    device,
                    "hair-render depth map",
                    resolution,
                    LIGHT_DEPTH_FORMAT,
                );
                let opacity_view = texture(
                    device,
                    "hair-render opacity map",
                    resolution,
                    OPACITY_FORMAT,
                );
                let unused_opacity = texture(device, "hair-render unused", 1, OPACITY_FORMAT);
                let lookup = maps_group(device, layout, &depth_view, &opacity_view, &self.sampler);
                let opacity_pass =
                    maps_group(device, layout, &depth_view, &unused_opacity, &self.sampler);
                self.maps.push(Maps {
                    resolution,
                    depth_attachment,
                    depth_view,
                    opacity_view,
                    lookup,
                    opacity_pass,
                });
                self.maps.len() - 1
            }
        };
        self.current = Some(index);
        self.maps[index].lookup.clone()
    }

    /// Encodes the depth pass and the opacity pass (after [`ShadowMaps::prepare`]) over the
    /// camera pass's batches, tessellated `stride` times coarser along.
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        depth: &LightPass,
        opacity: &LightPass,
        light_scene: &wgpu::BindGroup,
        item_groups: &[wgpu::BindGroup; 3],
        batches: &[Vec<Batch>; 3],
        stride: u32,
    ) {
        let Some(maps) = self.current.and_then(|index| self.maps.get(index)) else {
            return;
        };
        let light_batches: [Vec<Batch>; 3] = std::array::from_fn(|kind| {
            batches[kind]
                .iter()
                .map(|batch| batch.for_light_passes(stride))
                .collect()
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hair-render shadow depth"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &maps.depth_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &maps.depth_attachment,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            draw_hair(
                &mut pass,
                depth,
                light_scene,
                &self.unshadowed,
                item_groups,
                &light_batches,
            );
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hair-render shadow opacity"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &maps.opacity_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        draw_hair(
            &mut pass,
            opacity,
            light_scene,
            &maps.opacity_pass,
            item_groups,
            &light_batches,
        );
    }
}

/// Draws every batch of strands (line strips), clusters and patches with one light pass's
/// pipelines.
fn draw_hair(
    pass: &mut wgpu::RenderPass<'_>,
    pipelines: &LightPass,
    light_scene: &wgpu::BindGroup,
    maps: &wgpu::BindGroup,
    item_groups: &[wgpu::BindGroup; 3],
    batches: &[Vec<Batch>; 3],
) {
    pass.set_bind_group(0, light_scene, &[]);
    pass.set_bind_group(2, maps, &[]);
    let [strands, clusters, patches] = batches;
    if !strands.is_empty() {
        pass.set_pipeline(&pipelines.strands);
        pass.set_bind_group(1, &item_groups[0], &[]);
        for batch in strands {
            pass.draw(0..batch.line_vertices(), batch.items.clone());
        }
    }
    for (pipeline, group, batches, is_cluster) in [
        (&pipelines.clusters, &item_groups[1], clusters, true),
        (&pipelines.patches, &item_groups[2], patches, false),
    ] {
        if batches.is_empty() {
            continue;
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(1, group, &[]);
        for batch in batches {
            let bands = if is_cluster {
                batch.around_segments.min(SHADOW_AROUND_SEGMENTS)
            } else {
                1
            };
            pass.draw(0..batch.surface_vertices(bands), batch.items.clone());
        }
    }
}
