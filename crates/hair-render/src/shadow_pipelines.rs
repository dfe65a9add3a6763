//! The light passes' pipelines (self-shadowing, see [`crate::shadows`]): depth-only and additive
//! opacity pipelines for strands, clusters and patches, and the layout of the shadow maps' bind
//! group (group 2 of every pipeline that shades hair or the head).

use crate::target::DEPTH_FORMAT;

/// Format of the opacity map: four layers of optical depth, blended additively.
pub(crate) const OPACITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the depth map read by the shaders: the nearest depth in its red channel, written as
/// a colour next to the depth attachment (GLSL cannot load from depth textures, and GL cannot
/// render to `R32Float`). Half floats resolve depth 0..1 to 2⁻¹¹ or better: 0.3 mm over the
/// 0.6 m depth range of a head, well inside the first opacity layer.
pub(crate) const LIGHT_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The shader modules and layouts the light passes are built from.
pub(crate) struct ShadowSources<'a> {
    pub strands_module: &'a wgpu::ShaderModule,
    pub surfaces_module: &'a wgpu::ShaderModule,
    pub strand_layout: &'a wgpu::PipelineLayout,
    pub surface_layout: &'a wgpu::PipelineLayout,
    pub cluster_cull_mode: Option<wgpu::Face>,
}

/// One light pass (depth or opacity) for each kind of hair.
#[derive(Debug)]
pub(crate) struct LightPass {
    pub strands: wgpu::RenderPipeline,
    pub clusters: wgpu::RenderPipeline,
    pub patches: wgpu::RenderPipeline,
}

/// The depth pass and the opacity pass.
#[derive(Debug)]
pub(crate) struct ShadowPipelines {
    pub depth: LightPass,
    pub opacity: LightPass,
}

/// Group 2: the depth map (binding 0), the opacity map (1) and its sampler (2).
pub(crate) fn shadow_maps_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let visibility = wgpu::ShaderStages::VERTEX_FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("hair-render shadow maps"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

impl ShadowPipelines {
    /// Builds the six pipelines (single-sampled). The depth pass tests against a depth attachment
    /// and writes the kept depth to a [`LIGHT_DEPTH_FORMAT`] colour target; the opacity pass
    /// blends additively into an [`OPACITY_FORMAT`] one.
    pub fn new(device: &wgpu::Device, sources: &ShadowSources<'_>) -> ShadowPipelines {
        let additive = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let opacity_targets = [Some(wgpu::ColorTargetState {
            format: OPACITY_FORMAT,
            blend: Some(wgpu::BlendState {
                color: additive,
                alpha: additive,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let depth_targets = [Some(wgpu::ColorTargetState {
            format: LIGHT_DEPTH_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::RED,
        })];
        let pipeline = |label: &str,
                        layout: &wgpu::PipelineLayout,
                        module: &wgpu::ShaderModule,
                        vertex_entry: &str,
                        fragment_entry: &str,
                        topology,
                        cull_mode: Option<wgpu::Face>| {
            let depth_pass = fragment_entry.ends_with("_depth");
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(vertex_entry),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode,
                    ..wgpu::PrimitiveState::default()
                },
                depth_stencil: depth_pass.then(|| wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(fragment_entry),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: if depth_pass {
                        &depth_targets
                    } else {
                        &opacity_targets
                    },
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let strip = wgpu::PrimitiveTopology::TriangleStrip;
        let lines = wgpu::PrimitiveTopology::LineStrip;
        let pass = |name: &str, strand_fs: &str, surface_fs: &str| LightPass {
            strands: pipeline(
                &format!("hair-render shadow {name} strands"),
                sources.strand_layout,
                sources.strands_module,
                "vs_strand_shadow",
                strand_fs,
                lines,
                None,
            ),
            clusters: pipeline(
                &format!("hair-render shadow {name} clusters"),
                sources.surface_layout,
                sources.surfaces_module,
                "vs_cluster",
                surface_fs,
                strip,
                sources.cluster_cull_mode,
            ),
            patches: pipeline(
                &format!("hair-render shadow {name} patches"),
                sources.surface_layout,
                sources.surfaces_module,
                "vs_patch",
                surface_fs,
                strip,
                None,
            ),
        };
        ShadowPipelines {
            depth: pass("depth", "fs_strand_depth", "fs_surface_depth"),
            opacity: pass("opacity", "fs_strand_opacity", "fs_surface_opacity"),
        }
    }
}
